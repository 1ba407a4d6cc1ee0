"""Optimization modes of ``dgpc optimize`` (SPEC §4): presets of weights after paper §5.2.

Guided projection minimizes Σ w_t ‖φ_t‖² (plus its damping), so the weights set priorities:

* ``fit``, ``developable``: the constraints at weight 1, fairness decaying (paper §5.2).
* ``revolution`` (a drag that stays isometric to *some* surface of revolution): (6), (7) and
  the handles are constraints (weight 1e6, met exactly: the system is regular, see
  ``shared notes/isometry-study``); among the many nets that meet them the drag keeps the
  smoothest displacement (``displacement_fairness`` 1, and ``displacement_smoothness`` 0.6, its
  third differences, so that a held vertex leaves no crease), stays put along the flexes that
  fairness does not see (``closeness`` 1e-5) and keeps the u-edges of a row nearly equal
  (``equal_u_edges`` 1e5: congruent strips; exactly equal would be singular again). A final
  projection with these off meets the constraints to ``--tol``. Measured on the 21×21 meridian
  net of a sphere (120°), corners of row 0 held and its middle pushed 15 % of the radius
  towards the axis: u-spread 3.8e-4 → 2.5e-4, largest crease 0.044 → 0.031 mean edges (u-edges
  held closer without it: 0.059), 28 → 31 iterations; a push of the far row (no corners held
  in it) still bends its parallels (departure from circles 4.7e-4 → 4.3e-4 of the radius).
* ``isometric`` (a drag that stays isometric to the *input's* surface of revolution, one mold
  for several patches): edge lengths and (6) cannot both hold exactly under a drag (their only
  exact deformations are Minding's bending and period-2 pleats), so the net, the handles are
  constraints (1e6) and (6) and the input's edge lengths are weighed against each other (1
  each) with the drag's smoothness (``displacement_fairness`` 1e-5): the smooth net of least
  strain; its status is decided by ``--max-strain`` and ``--gpc-tol``. Folding along a few
  meridians is nearly an exact deformation of that weighing, so as the smoothness is lowered a
  push creases the rows (three columns from a held corner, at the pushed vertex); the
  ``crease_guard`` (1) lets no run of a row's third differences grow more than its margin over
  the start net's. Measured on the 21×21 sphere net (120°), corners of row 0 held, its middle
  pushed 5 % of the radius towards the axis: crease 0.123 → 0.048 mean edges, strain 1.5e-4 →
  2.9e-4 (at 21×21 a smooth net pays for this push in strain); on the 41×41 net crease 0.054 →
  0.034, strain 6.0e-5 → 3.3e-5; Gehry facade 1 (21×13): crease 0.155 → 0.066, strain 3.1e-5
  → 3.9e-5. Why the 21×21 net pays (``benchmarks/push_frontier.py``): the normal curvatures
  of row 0 and of the meridian across it multiply to K plus the squared geodesic torsion
  (Gauss), so where the push flattens row 0 the meridian must curl; in the 41×41 result row 0
  turns 0.09 times its start angle at the pushed vertex and 2.1 times near the corners, the
  pushed meridian 2.8 times next to row 0.
  Edges twice as long cannot follow that: the 41×41 result read on the 21×21 net (every other
  vertex) has strain 1.4e-3, crease 0.072. Across 24 weightings at 21×21 ((6) at 0.3, 1, 3;
  the guard at 1, 1e-3 or off, or the displacement's third differences instead; relaxed or
  not) the least strain at crease ≤ 0.05 is 1.2e-4 (gpc defect 2.5e-4), 2.7e-4 within
  ``--gpc-tol``, 8.5e-5 at any crease; by size (guarded): 2.9e-4 (21×21), 2.2e-4 (25×25),
  1.6e-4 (31×31), 3.3e-5 (41×41): the paper's 4e-5 is met at 41×41, not at 31×31.

Weights hold as written for a net scaled to mean edge length 1 (``core.problem``).
"""

from __future__ import annotations

from dgpc_cli.core.constraints import TERMS
from dgpc_cli.core.solver import Schedule, parse_weight

#: Weights per mode, in the notation of ``--weight`` (a value or a schedule ``A->B``).
#: ``net`` is 1 unless the mode says otherwise. Data-bound terms take part only when their
#: data is given: approximation needs ``--reference``, handles ``--handles``, isometry the input
#: net; boundary needs net rim vertices that start on the reference's boundary.
MODES: dict[str, dict[str, str]] = {
    "fit": {"gpc": "1", "approximation": "1", "boundary": "1", "rim": "1",
            "fairness": "0.01->0"},
    "developable": {"gpc": "1", "arclength": "1", "equal_strip_width": "1", "developable": "1",
                    "approximation": "1", "boundary": "1"},
    "revolution": {"net": "1e6", "gpc": "1e6", "equal_strip_width": "1e6", "handles": "1e6",
                   "approximation": "1e6", "displacement_fairness": "1",
                   "displacement_smoothness": "0.6", "closeness": "1e-5", "equal_u_edges": "1e5"},
    "isometric": {"net": "1e6", "handles": "1e6", "gpc": "1", "isometry": "1",
                  "displacement_fairness": "1e-5", "crease_guard": "1"},
}

#: Terms each mode treats as soft (they pull, the tolerance does not apply to them): the
#: reference of a nearly developable fit is not exactly developable (paper Fig. 8: R = 0.29),
#: nor need a reference be isometric to a surface of revolution. The reference's boundary
#: only pulls: a geodesic net need not end on it everywhere. In isometric mode (6) and the
#: edge lengths are weighed against each other; ``--gpc-tol`` and ``--max-strain`` judge them.
SOFT = {"fit": ("boundary", "rim"), "developable": ("approximation", "boundary"),
        "revolution": ("approximation",), "isometric": ("gpc", "isometry")}

#: The regularizer each mode lowers once the net has settled, while the strain against the input
#: falls and no pleat appears (``fitting.optimize._relax``).
RELAX = {"isometric": "displacement_fairness"}

#: What ``dgpc init`` nets are measured against: discrete geodesic parallel coordinates.
GPC_ONLY = {"net": Schedule.constant(1.0), "gpc": Schedule.constant(1.0)}


def mode_weights(mode: str, overrides: list[str] | tuple[str, ...] = ()) -> dict[str, Schedule]:
    """The weight schedules of ``mode`` with ``--weight NAME=VALUE|NAME=A->B`` overrides.

    Raises ValueError with a one-line reason for an unknown mode or weight name or a bad value.
    """
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}")
    weights = {"net": Schedule.constant(1.0)}
    weights.update({name: parse_weight(f"{name}={value}")[1]
                    for name, value in MODES[mode].items()})
    for text in overrides:
        name, schedule = parse_weight(text)
        if name not in TERMS:
            raise ValueError(f"unknown weight {name!r}; the terms are {', '.join(TERMS)}")
        weights[name] = schedule
    return weights


def describe_weights(weights: dict[str, Schedule]) -> dict[str, str]:
    """JSON-able form of the weights (``"1"``, ``"0.01->0"``), every term listed."""
    return {name: str(weights.get(name, Schedule.constant(0.0))) for name in TERMS}
