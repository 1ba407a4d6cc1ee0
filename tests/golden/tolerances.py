"""How closely the golden tests compare each figure of tests/golden/NAME.json, and why.

Every tolerance comes from the stopping rule of the stage that made the figure, never from
what one machine happened to compute: another CPU rounds a sum in another order (MKL's and
OpenBLAS's kernels, numpy's SIMD loops), and a stage that stops at a tolerance stops anywhere
within it. ``tests/test_golden_numerics.py`` proves each of them: every pipeline run again with
its input nets moved by 1e-12 of their size, and with another OpenBLAS kernel, moves every
figure by less than a tenth of its tolerance.

Kinds of comparison (``Tol.kind``):

- ``rel``: ``|got − want| ≤ value · max(|got|, |want|)``;
- ``max``: ``got ≤ value``, the golden value not compared (any value below is as good: a
  residual the solver drove below its ``--tol``);
- ``none``: not compared (the figure is not fixed by the pipeline's inputs; see its reason).

A figure whose golden and computed values are both at most ``FLOOR`` is round-off (a residual
of exact constraints, the congruence of one template's copies) and passes. Counts and DXF
entity counts are compared exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from inspect import signature

from dgpc_cli.core.solver.guided_projection import guided_projection
from dgpc_cli.fitting.optimize import STEP_RATIO
from dgpc_cli.tolerances import tol as TOL


@dataclass(frozen=True)
class Tol:
    kind: str            # "rel", "max" or "none"
    value: float
    why: str


#: Round-off: residuals of exactly met constraints, congruence errors of one template's copies.
FLOOR = 1e-8

#: The stagnation rule of guided projection's runs of soft terms (the relaxation rounds of a
#: drag): stop once the weighted objective stayed above this fraction of its best value for a
#: window of iterations.
SOFT_RATIO = signature(guided_projection).parameters["stagnation_ratio"].default

R_OPTIMIZE = Tol(
    "max", 2 * TOL.solver_R,
    "optimize stops once the hard residual is at most --tol (default 1e-9); inspect recomputes "
    "R at the written vertices (scaled by their own mean edge), within 2x of the solver's")
R_FIT_1E8 = Tol(
    "max", 2 * 1e-8,
    "optimize --tol 1e-8 (pipelines/*.mk); inspect recomputes R within 2x of the solver's")
DRAG_FIGURE = Tol(
    "rel", round(1 - SOFT_RATIO, 12),
    "a drag's soft terms (strain and gpc angles weighed against each other, the smoothness) "
    "stop on stagnation: the objective, a sum of these squared figures, within 1 - 0.999 of "
    "its best over the window; a figure of the net fixed no closer than that")
DRAG_COORDINATES = Tol(
    "rel", 1e-6,
    "x bbox diagonal. The drag ends on its soft terms' stagnation (1 - STEP_RATIO = 1 % of "
    "the objective over the last window), then projects onto the hard terms to --tol: along "
    "the flexes the net stays where the soft iterations stopped, 1 % of their residual (the "
    "strain, ~1e-3 of an edge; ~1e-4 of a 9x7 net's diagonal)")
NEST_UTILIZATION = Tol(
    "rel", 1e-4,
    "nest places the parts by outlines within 1e-4 of their diagonal (nesting.geometry."
    "piece_outline): the used length of the sheets moves with the parts that much")
MOLD_FIGURE = Tol(
    "rel", round(1 - SOFT_RATIO, 12),
    "extract-mold measures the drags' nets exactly: their tolerance (DRAG_FIGURE)")

CYLINDER_DRAG = Tol(
    "rel", round(1 - STEP_RATIO, 12),
    "the gallery's cylinder is developable: a drag bends it along exact isometries, so the "
    "least strain lies on a flat valley and the drag's last runs stop on their objective "
    "falling by less than 1 - STEP_RATIO = 1 % over the window; a start moved by 1e-12 moves "
    "its strain by 1.1e-4 of itself")

# the reasons quote them
assert round(1 - STEP_RATIO, 12) == 0.01 and round(1 - SOFT_RATIO, 12) == 1e-3


def _drag(keys) -> dict[str, Tol]:
    out = {}
    for key in keys:
        if key.startswith("R"):
            out[key] = R_OPTIMIZE
        elif key.startswith("mold_"):
            out[key] = MOLD_FIGURE
        elif key == "utilization":
            out[key] = NEST_UTILIZATION
        else:
            out[key] = DRAG_FIGURE
    return out


def tolerances(name: str, metric_keys) -> dict:
    """``{"metrics": {key: Tol}, "coordinates": Tol}`` of pipeline ``name``."""
    if name in ("gehry-facade", "timber-cladding", "gallery"):
        figures = _drag(metric_keys)
        figures.update({k: CYLINDER_DRAG for k in figures if k.endswith("_cylinder")})
        return {"metrics": figures, "coordinates": DRAG_COORDINATES}
    if name == "felt-developable":
        soft = Tol(
            "rel", 1e-3,
            "the developable fit's approximation is soft: its run stops once the objective "
            "falls by less than 1 % over 10 iterations, then projects onto the hard terms; "
            "the distance to the mesh is fixed to 1 % of itself, the figures of the net to "
            "about 1 % of the approximation's share (~0.1 %)")
        return {"metrics": {"R": R_OPTIMIZE, "jacobi_residual_max": Tol(
                    "max", 2 * TOL.solver_R,
                    "(8) is a hard term of the developable mode: within --tol"),
                "hausdorff_over_diagonal": soft, "congruence_error": soft,
                "flat_max_strain": soft},
                "coordinates": Tol(
                    "rel", 3e-5,
                    "x bbox diagonal: 1 % (the stop on the objective falling 1 % over 10 "
                    "iterations) of the soft approximation's distance, 3.5e-3 of the diagonal")}
    if name == "gridshell":
        return {"metrics": {
            "R_a": R_FIT_1E8, "R_b": R_FIT_1E8,
            **{k: Tol("rel", 0.2,
                      "the fit's vertices slide along the reference (rim and boundary only "
                      "pull): the farthest point of the reference from the net moves with "
                      "them by a fraction of a mesh edge") for k in
               ("hausdorff_over_diagonal_a", "hausdorff_over_diagonal_b")},
            **{k: Tol("rel", 5e-3, "the reference is covered to the fit's rim; its rim moves "
                                   "by a fraction of a mesh edge along the boundary")
               for k in ("coverage_a", "coverage_b")}},
            "coordinates": Tol(
                "none", 0.0,
                "not compared: the fitted vertices slide along the reference within the fit's "
                "tolerance (a 1e-12 change of the start moves them by 2e-3 of the diagonal); "
                "the surface they span is compared (Hausdorff, coverage)")}
    if name == "bowling-pin-clairaut":
        return {"metrics": {
            "R": R_FIT_1E8,
            "clairaut_max_relative_mad": Tol(
                "max", 1e-2, "Clairaut's r cos α constant along each geodesic within 1 %"),
            "hausdorff_over_diagonal": Tol("max", 5e-3, "the net on the pin")},
            "coordinates": Tol(
                "none", 0.0,
                "not compared: the twisted net may turn about the pin's axis and slide along "
                "its geodesics while staying a gpc net on it, and the last bits of its start "
                "pick the member (1e-15 changes of the 21x11 start moved the fitted vertices "
                "by 3-8 % of the diagonal)")}
    raise KeyError(name)
