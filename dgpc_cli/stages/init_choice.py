"""``dgpc init`` on a mesh aims at the whole surface (SPEC §5): it tries base curves and grid
directions, never keeps a folded or collapsed net, and says what it chose and how much of the
reference the net covers.

* Candidates. ``--method geodesic``: the sections orthogonal to the two longest principal axes
  and every boundary curve (``geodesics.boundary``) that is not tiny; ``--method project``: the
  grid along the projected principal axis, at 45° to it, and along the chord of every boundary
  curve. An explicit ``--base``/``--direction``/``--angle`` narrows them down to one (or, with
  ``--base boundary``, to the boundary curves).
* Soundness. A candidate net that is degenerate (``metrics.degenerate``: collapsed edges, folded
  or flipped quads, and for traced geodesics a gpc defect above 0.1 rad; a projected grid is not
  gpc yet, ``optimize --mode fit`` makes it so) is made again over the largest rectangle of its
  sound quads (or cut down to it); an explicit choice whose sound rectangle keeps less than
  :data:`MIN_KEPT` of the net is refused, naming rows and columns and the candidate that works.
* Choice. The sound net that covers most of the reference (``metrics.coverage``, measured on
  the mesh itself, not on its continuation); within :data:`COVERAGE_SLACK` of the best the
  earlier candidate wins, so that a plain section stays the default where it covers as well.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.boundary import BoundaryCurve, boundary_curves, describe, prolonged
from dgpc_cli.geodesics.rectangle import largest_rectangle
from dgpc_cli.geodesics.tracing import plane_axes, principal_frame
from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.metrics.coverage import coverage
from dgpc_cli.metrics.degenerate import GPC_LIMIT, degeneracies
from dgpc_cli.stages.init_mesh import MeshGrid, init_geodesic, init_project
from dgpc_cli.stages.net_size import NetTooLarge

log = logging.getLogger(__name__)

#: An explicit choice is shrunk to its sound rectangle only when that keeps at least this
#: fraction of the net's quads; below, init refuses.
MIN_KEPT = 0.25
#: Boundary curves shorter than this fraction of the longest are not tried as base curves.
MIN_CURVE = 0.1
#: Candidates covering within this of the best count as covering as much.
COVERAGE_SLACK = 0.005
#: Samples of the reference for the coverage of each candidate.
COVERAGE_SAMPLES = 20_000


@dataclass
class Candidate:
    """One way to make the net: a ``label`` and the keyword arguments of the builder."""

    label: str
    kwargs: dict


@dataclass
class Outcome:
    """A sound candidate net, its coverage of the reference and what was done to it."""

    grid: MeshGrid
    coverage: float
    note: str | None = None       # "shrunk from 34 x 21 to 30 x 21: <what was degenerate>"
    kept: float = 1.0             # fraction of the quads kept


def _curves(mesh: ReferenceMesh) -> list[BoundaryCurve]:
    curves = boundary_curves(mesh.vertices, mesh.faces)
    if not curves:
        return []
    return [c for c in curves if c.length >= MIN_CURVE * curves[0].length]


def named_curve(mesh: ReferenceMesh, name: str) -> BoundaryCurve:
    """The boundary curve ``name`` (``b1``, ``b2``, …) of the mesh; DgpcError naming ``--base``
    and listing the curves otherwise."""
    curves = boundary_curves(mesh.vertices, mesh.faces)
    for c in curves:
        if c.name == name:
            return c
    listed = describe(curves) if curves else "none: the mesh is closed"
    raise DgpcError(f"no boundary curve {name!r}; the boundary curves of {mesh.path.name} are "
                    f"{listed}", source="--base")


def candidates(mesh: ReferenceMesh, method: str, *, base: str | None, direction,
               angle: float | None) -> list[Candidate]:
    """The candidates to try (see the module), in order of preference."""
    if method == "project":
        if angle is not None:
            return [Candidate(f"project {angle:g}°", {"direction": direction, "angle": angle})]
        angles = [0.0, 45.0]
        d = (principal_frame(mesh.vertices, mesh.faces)[1][:, 2] if direction is None
             else np.asarray(direction, float) / np.linalg.norm(direction))
        _, e1, e2 = plane_axes(mesh.vertices, mesh.faces, d)
        for c in _curves(mesh):
            chord = c.curve.points[-1] - c.curve.points[0]
            if c.curve.closed or np.linalg.norm(chord) == 0:
                continue
            a = float(np.degrees(np.arctan2(chord @ e2, chord @ e1))) % 90.0
            if min(abs(a - b) % 90.0 for b in angles) > 1.0 and \
                    min(90.0 - abs(a - b) % 90.0 for b in angles) > 1.0:
                angles.append(round(a, 6))
        return [Candidate(f"project {a:g}°", {"direction": direction, "angle": a})
                for a in angles]
    if base in (None, "auto") and direction is None and angle is None:
        out = [Candidate("section 0°", {"angle": 0.0}), Candidate("section 90°", {"angle": 90.0})]
        return out + [Candidate(f"boundary {c.name}", {"curve": c}) for c in _curves(mesh)]
    if base == "boundary":
        curves = _curves(mesh)
        if not curves:
            raise DgpcError(f"{mesh.path.name} is closed: it has no boundary curve to start "
                            "from", source="--base")
        return [Candidate(f"boundary {c.name}", {"curve": c}) for c in curves]
    if base not in (None, "auto", "section"):
        c = named_curve(mesh, base)
        return [Candidate(f"boundary {c.name}", {"curve": c})]
    label = "section" if direction is not None else f"section {angle or 0.0:g}°"
    return [Candidate(label, {"direction": direction, "angle": angle or 0.0})]


def _build(domain: ReferenceMesh, method: str, cand: Candidate, size: dict,
           extend_length: float) -> MeshGrid:
    if method == "project":
        return init_project(domain, **cand.kwargs, **size)
    kwargs = dict(cand.kwargs)
    curve = kwargs.pop("curve", None)
    if curve is not None:
        base = prolonged(curve.curve, domain.vertices, domain.faces, extend_length)
        return init_geodesic(domain, base=base, base_name=curve.name, **size)
    return init_geodesic(domain, **kwargs, **size)


def sound(grid: MeshGrid) -> tuple[MeshGrid, str | None, float]:
    """``grid`` itself when its net is not degenerate; else the net made again over the
    largest rectangle of its sound quads (cut down to that rectangle when the remade net is
    still degenerate), a note saying so, and the fraction of the quads kept. DgpcError-free:
    ``None`` grid when no rectangle of 2 × 2 sound quads is left."""
    gpc_limit = GPC_LIMIT if grid.traced else None
    found = degeneracies(grid.net.f, gpc_limit=gpc_limit)
    if not found:
        return grid, None, 1.0
    m, n = grid.net.shape
    rect = largest_rectangle(~found.bad_quads, count="entries")
    if rect is None:
        return None, found.message(), 0.0
    r0, r1, c0, c1 = rect
    kept = (r1 - r0 + 1) * (c1 - c0 + 1) / ((m - 1) * (n - 1))
    smaller = None
    try:
        smaller = grid.remake(grid.u[r0], grid.u[r1 + 1], grid.v[c0], grid.v[c1 + 1])
    except DgpcError:
        pass
    if smaller is None or degeneracies(smaller.net.f, gpc_limit=gpc_limit):
        f = np.ascontiguousarray(grid.net.f[r0:r1 + 2, c0:c1 + 2])
        net = grid.net
        net.f = f
        net.data["init"]["cut_to"] = {"rows": [int(r0), int(r1 + 1)],
                                      "cols": [int(c0), int(c1 + 1)]}
        smaller = MeshGrid(net, grid.u[r0:r1 + 2], grid.v[c0:c1 + 2], grid.label, grid.remake)
    note = (f"{grid.label}: the {m} x {n} net is degenerate ({found.message()}); shrunk to "
            f"its largest sound rectangle (rows {r0}-{r1 + 1}, columns {c0}-{c1 + 1}), "
            f"{smaller.net.shape[0]} x {smaller.net.shape[1]}")
    smaller.net.data["init"]["shrunk"] = {"from": [m, n], "degenerate": found.record()}
    return smaller, note, kept


def choose(mesh: ReferenceMesh, domain: ReferenceMesh, method: str, *, base: str | None = None,
           direction=None, angle: float | None = None, rows: int | None = None,
           cols: int | None = None, spacing: float | None = None,
           extend_length: float = 0.0) -> tuple[MeshGrid, Outcome, list[dict]]:
    """The net ``init`` writes: every candidate made on ``domain`` (the mesh, or its
    continuation with ``--extend``), made sound, measured on ``mesh``; the best one (see the
    module), its outcome, and the record of every candidate tried."""
    size = {"rows": rows, "cols": cols, "spacing": spacing}
    cands = candidates(mesh, method, base=base, direction=direction, angle=angle)
    explicit = len(cands) == 1
    tried, outcomes = [], []
    for cand in cands:
        try:
            grid = _build(domain, method, cand, size, extend_length)
        except NetTooLarge:
            raise
        except DgpcError as err:
            if explicit:
                raise
            tried.append({"candidate": cand.label, "failed": err.reason})
            log.info("%s: %s", cand.label, err.reason)
            continue
        grid.label = cand.label
        shape = grid.net.shape
        fixed, note, kept = sound(grid)
        if fixed is None:
            tried.append({"candidate": cand.label, "shape": list(shape),
                          "degenerate": note})
            outcomes.append(None)
            log.info("%s: degenerate, no sound rectangle left (%s)", cand.label, note)
            continue
        cov = coverage(fixed.net.f, mesh.vertices, mesh.faces,
                       samples=COVERAGE_SAMPLES)["area_fraction"]
        out = Outcome(fixed, cov, note, kept)
        outcomes.append(out)
        tried.append({"candidate": cand.label, "shape": list(fixed.net.shape),
                      "coverage": cov, **({"shrunk_from": list(shape)} if note else {})})
        log.info("%s: %d x %d net covers %.1f %% of the reference%s", cand.label,
                 *fixed.net.shape, 100 * cov, f" ({note})" if note else "")
    good = [o for o in outcomes if o is not None]
    if explicit and (not good or good[0].kept < MIN_KEPT):
        _refuse(mesh, domain, method, cands[0], tried, outcomes, size, extend_length)
    if not good:
        raise DgpcError("no base curve or direction gives a sound net on the mesh (every "
                        "candidate folds or collapses: "
                        + "; ".join(f"{t['candidate']}: {t.get('degenerate') or t.get('failed')}"
                                    for t in tried) + ")", source=mesh.path)
    best = max(o.coverage for o in good)
    chosen = next(o for o in good if o.coverage >= best - COVERAGE_SLACK)
    return chosen.grid, chosen, tried


def _refuse(mesh, domain, method, cand, tried, outcomes, size, extend_length):
    """DgpcError for an explicit choice that gives a degenerate net: where, and which
    automatic candidate works instead (if any)."""
    what = tried[0].get("degenerate") if outcomes[0] is None else \
        f"only {outcomes[0].kept:.0%} of it is sound ({outcomes[0].note})"
    others = []
    for alt in candidates(mesh, method, base=None, direction=None, angle=None):
        if alt.label == cand.label:
            continue
        try:
            fixed, _, kept = sound(_build(domain, method, alt, size, extend_length))
        except DgpcError:
            continue
        if fixed is not None and kept >= MIN_KEPT:
            cov = coverage(fixed.net.f, mesh.vertices, mesh.faces,
                           samples=COVERAGE_SAMPLES)["area_fraction"]
            others.append((cov, alt.label))
    hint = (f"; {_option(max(others)[1])} gives a sound net covering {max(others)[0]:.0%}"
            if others else "; try fewer --rows/--cols or a smaller --extend")
    raise DgpcError(f"the {cand.label} net is degenerate (folded or collapsed): {what}{hint}",
                    source=mesh.path)


def _option(label: str) -> str:
    """The options that pick the candidate ``label``."""
    kind, _, arg = label.partition(" ")
    if kind == "boundary":
        return f"--base {arg}"
    return f"--angle {arg.rstrip('°')}"
