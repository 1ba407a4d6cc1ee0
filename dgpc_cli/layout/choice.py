"""``dgpc init`` on a mesh aims at the whole surface (SPEC §5): it tries base curves and grid
directions, never keeps a folded or collapsed net, and says what it chose and how much of the
reference the net covers.

* Candidates. ``--method geodesic``: the sections whose planes turn about the shortest
  principal axis in a sweep of :data:`SWEEP` (0°, along the longest principal axis, first),
  every boundary curve (``geodesics.boundary``) that is not tiny, and the sections across the
  two longest sides of the mesh's bounding box of least volume (``geodesics.extent``: the
  *spine* of a roof as wide as long, which the principal axes miss once its height tilts
  them), a plane within :data:`SAME_PLANE` of one already listed left out; ``--method
  project``: the grid along the projected principal axis, at 45° to it, and along the chord of
  every boundary curve. An explicit ``--base``/``--direction``/``--angle`` narrows them down
  to one (or, with ``--base boundary``, to the boundary curves). Which one ``init`` keeps,
  after a quick fit, over which overhang and size, is ``layout.search``'s business.
* Soundness. A candidate net that is degenerate (``metrics.degenerate``: collapsed edges, folded
  or flipped quads, and for traced geodesics a gpc defect above 0.1 rad; a projected grid is not
  gpc yet, ``optimize --mode fit`` makes it so) is made again over the largest rectangle of its
  sound quads (or cut down to it); an explicit choice whose sound rectangle keeps less than
  :data:`MIN_KEPT` of the net is refused, naming rows and columns and the candidate that works.
* Choice (``--method project``). The sound net that covers most of the reference
  (``metrics.coverage``, measured on the mesh itself, not on its continuation); within
  :data:`COVERAGE_SLACK` of the best the earlier candidate wins.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.boundary import (
    BoundaryCurve,
    boundary_curves,
    describe,
    prolonged,
    relocated,
)
from dgpc_cli.geodesics.extent import extent_axes
from dgpc_cli.geodesics.rectangle import largest_rectangle
from dgpc_cli.geodesics.tracing import plane_axes, principal_frame
from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.layout.grids import (
    MeshGrid,
    MeshTracing,
    init_geodesic,
    init_project,
    rotated,
)
from dgpc_cli.layout.net_size import NetTooLarge
from dgpc_cli.metrics.coverage import coverage
from dgpc_cli.metrics.degenerate import GPC_LIMIT, degeneracies

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
#: The automatic choice's sweep of section planes, ``--angle`` in degrees (0 and 90 first: the
#: principal axes).
SWEEP = (0.0, 90.0, 30.0, 60.0, 120.0, 150.0)
#: A section plane whose normal lies within this angle (degrees) of one already listed is not
#: tried again.
SAME_PLANE = 5.0


@dataclass
class Candidate:
    """One way to make the net: a ``label`` and the keyword arguments of the builder."""

    label: str
    kwargs: dict

    def record(self) -> dict:
        """What the artifact records of the candidate besides its label: the base plane's
        normal of a section, the name of a boundary curve."""
        if "curve" in self.kwargs:
            return {"base": self.kwargs["curve"].name}
        d = self.kwargs.get("direction")
        return {"direction": [float(x) for x in d]} if d is not None else {}


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
               angle: float | None, frame: ReferenceMesh | None = None) -> list[Candidate]:
    """The candidates to try (see the module), in order of preference; the sweep of sections
    turns the principal axes of ``frame`` (default: ``mesh``; ``--extend`` given: its
    continuation, as ``--angle`` does)."""
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
        sections = _auto_sections(mesh, mesh if frame is None else frame)
        return (sections[:2] + [Candidate(f"boundary {c.name}", {"curve": c})
                                for c in _curves(mesh)] + sections[2:])
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


def _auto_sections(mesh: ReferenceMesh, frame: ReferenceMesh) -> list[Candidate]:
    """The sections the automatic choice tries (see the module), their planes' normals
    resolved once (the sweep on ``frame``'s principal axes, the extents of ``mesh``), so that
    the same planes cut every continuation."""
    _, axes = principal_frame(frame.vertices, frame.faces)
    listed: list[np.ndarray] = []
    out = []

    def add(label, d):
        d = np.asarray(d, float) / np.linalg.norm(d)
        if any(abs(float(d @ e)) >= np.cos(np.radians(SAME_PLANE)) for e in listed):
            return
        listed.append(d)
        out.append(Candidate(label, {"direction": d.tolist(), "angle": 0.0}))

    for a in SWEEP:
        add(f"section {a:g}°", rotated(axes[:, 0], axes[:, 2], a) if a else axes[:, 0])
    sides, _ = extent_axes(mesh.vertices)
    add("along the longest extent", sides[:, 0])
    add("along the second extent", sides[:, 1])
    return out


def _build(domain: ReferenceMesh, method: str, cand: Candidate, size: dict,
           extend_length: float, tracing: MeshTracing | None = None,
           relocate: bool = False) -> MeshGrid:
    if method == "project":
        return init_project(domain, **cand.kwargs, **size)
    kwargs = dict(cand.kwargs)
    curve = kwargs.pop("curve", None)
    if curve is not None:
        base = curve.curve if not relocate else relocated(curve.curve, domain.vertices,
                                                          domain.faces)
        base = prolonged(base, domain.vertices, domain.faces, extend_length,
                         tracer=tracing.tracer if tracing is not None else None)
        return init_geodesic(domain, base=base, base_name=curve.name, **size, tracing=tracing)
    return init_geodesic(domain, **kwargs, **size, tracing=tracing)


def evaluate(mesh: ReferenceMesh, domain: ReferenceMesh, method: str, cand: Candidate,
             size: dict, extend_length: float, *, explicit: bool = False,
             tracing: MeshTracing | None = None, surface=None,
             relocate: bool = False) -> tuple[dict, Outcome | None]:
    """One candidate made on ``domain``, made sound and measured on ``mesh``: its record and
    its :class:`Outcome` (None when it fails or nothing sound is left; an explicit choice's
    DgpcError is raised). ``tracing`` (of ``domain``) and ``surface`` (the
    ``core.reference.ReferenceSurface`` of ``mesh``) are made once when given; ``relocate``:
    ``domain`` is not ``mesh`` continued (a patch's surroundings), so a boundary curve's faces
    are found on it again."""
    try:
        grid = _build(domain, method, cand, size, extend_length, tracing, relocate)
    except NetTooLarge:
        raise
    except DgpcError as err:
        if explicit:
            raise
        log.info("%s: %s", cand.label, err.reason)
        return {"candidate": cand.label, "failed": err.reason}, None
    grid.label = cand.label
    shape = grid.net.shape
    fixed, note, kept = sound(grid)
    if fixed is None:
        log.info("%s: degenerate, no sound rectangle left (%s)", cand.label, note)
        return {"candidate": cand.label, "shape": list(shape), "degenerate": note}, None
    fixed.label = cand.label
    cov = coverage(fixed.net.f, mesh.vertices, mesh.faces, samples=COVERAGE_SAMPLES,
                   surface=surface)["area_fraction"]
    log.info("%s: %d x %d net covers %.1f %% of the reference%s", cand.label,
             *fixed.net.shape, 100 * cov, f" ({note})" if note else "")
    return ({"candidate": cand.label, "shape": list(fixed.net.shape), "coverage": cov,
             **({"shrunk_from": list(shape)} if note else {})},
            Outcome(fixed, cov, note, kept))


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
    pairs = evaluate_all(mesh, domain, method, cands, size, extend_length, explicit=explicit)
    tried = [record for record, _ in pairs]
    good = [o for _, o in pairs if o is not None]
    if not good:
        raise no_sound_net(mesh, tried)
    best = max(o.coverage for o in good)
    chosen = next(o for o in good if o.coverage >= best - COVERAGE_SLACK)
    return chosen.grid, chosen, tried


def no_sound_net(mesh: ReferenceMesh, tried: list[dict]) -> DgpcError:
    """The error of a mesh on which no candidate gives a sound net, each one's reason."""
    return DgpcError("no base curve or direction gives a sound net on the mesh (every "
                     "candidate folds or collapses: "
                     + "; ".join(f"{t['candidate']}: {t.get('degenerate') or t.get('failed')}"
                                 for t in tried) + ")", source=mesh.path)


def evaluate_all(mesh: ReferenceMesh, domain: ReferenceMesh, method: str,
                 cands: list[Candidate], size: dict, extend_length: float, *,
                 explicit: bool = False, tracing: MeshTracing | None = None,
                 surface=None, relocate: bool = False) -> list[tuple[dict, Outcome | None]]:
    """:func:`evaluate` of each candidate; an ``explicit`` choice (one candidate) that leaves
    no sound net, or one of less than :data:`MIN_KEPT` of its quads, is refused (DgpcError
    naming the automatic candidate that works); ``tracing``, ``surface``, ``relocate`` as
    there."""
    if method == "geodesic" and tracing is None:
        tracing = MeshTracing.of(domain)
    pairs = [evaluate(mesh, domain, method, cand, size, extend_length, explicit=explicit,
                      tracing=tracing, surface=surface, relocate=relocate) for cand in cands]
    if explicit and (pairs[0][1] is None or pairs[0][1].kept < MIN_KEPT):
        _refuse(mesh, domain, method, cands[0], [pairs[0][0]], [pairs[0][1]], size,
                extend_length)
    return pairs


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
            others.append((cov, -len(others), alt))
    best = max(others, key=lambda o: o[:2]) if others else None
    hint = (f"; {option(best[2])} gives a sound net covering {best[0]:.0%}"
            if others else "; try fewer --rows/--cols or a smaller --extend")
    raise DgpcError(f"the {cand.label} net is degenerate (folded or collapsed): {what}{hint}",
                    source=mesh.path)


def option(cand: Candidate, by_direction: bool = False) -> str:
    """The options that pick the candidate ``cand`` (a section by its ``--direction`` with
    ``by_direction``: over an overhang ``--angle`` turns the principal axes of the continued
    mesh, the search those of the mesh)."""
    kind, _, arg = cand.label.partition(" ")
    if kind == "boundary":
        return f"--base {arg}"
    if kind == "section" and arg and not by_direction:
        return f"--angle {arg.rstrip('°')}"
    d = cand.kwargs.get("direction")
    return "--direction " + ",".join(f"{x:.6g}" for x in d) if d is not None else kind
