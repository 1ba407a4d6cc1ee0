"""A short guided-projection polish of an almost planar quad strip (paper §5, §6.2.4): quads made
planar while the strip stays as close as it can to the original (non-developable) strip.

Hard terms: planarity of every quad, and every vertex kept on its side of the strip (it may
slide along its boundary geodesic and leave the surface along the normal, but not move across
the geodesic, so neighbouring strips still meet); the end rulings stay where the construction
trimmed them. Soft term: the point-to-plane distance of the quads' corners, edge midpoints and
centres from the original strip (its quads as bilinear patches). A planar-quad strip cannot
follow a doubly curved strip exactly; the least-squares fit spreads the unavoidable sag to both
sides of the surface instead of keeping the vertices on it and letting the quads' middles sag
(about half the deviation of a strip whose vertices stay on the geodesics). A small, constant
slide fairness keeps the vertices' slides along the geodesics smooth, so the rulings never
zigzag and cross.

The closeness weight falls during the fit (like the paper's fairness weight), and a final
projection onto the hard terms alone (the solver's regularization makes it the least change)
makes the quads planar to the solver's tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.core.constraints.planarity import (
    QuadGridLayout,
    anchor,
    lateral,
    planarity,
    quad_samples,
    slide_fairness,
    surface_closeness,
)
from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.core.solver import Schedule, Term, guided_projection
from dgpc_cli.metrics.frames import unit
from dgpc_cli.strips.quality import patch_mesh

#: Weight schedule of the closeness to the original strip (planarity has weight 1).
CLOSENESS_WEIGHT = Schedule(1.0, 1e-2, 30)
#: Weight schedule of the anchor to the start positions: it keeps the first steps from sliding
#: vertices past each other along their geodesics, then fades out.
ANCHOR_WEIGHT = Schedule(0.01, 0.0, 20)
#: Weight of the slide fairness (second differences of the vertices' slides along their
#: geodesics), kept to the end: the rulings may shift together but not zigzag. Without it the
#: fit folds the strip where the surface gives no preference (a strip on a cylinder is planar
#: between any two parallel rulings): alternate vertices slide past each other, turning quads
#: into near-triangles (planar, and hugging the surface) whose rulings cross.
SLIDE_WEIGHT = Schedule.constant(1e-2)
#: Tolerance on the hard residual at mean edge length 1.
POLISH_TOL = 1e-12
#: Iteration limits of the fit and of the final projection.
POLISH_MAX_ITER = 200
PROJECTION_MAX_ITER = 50


@dataclass
class PolishResult:
    """Polished vertices ``A, B (m, 3)`` and the solver's outcome (status and hard residual R
    of the final projection, iterations of both phases)."""

    A: np.ndarray
    B: np.ndarray
    status: str
    iterations: int
    R: float


def _side_constraints(start: np.ndarray, tangents: np.ndarray, reference: ReferenceSurface):
    """Start points, directions and vertex ids of the lateral term: every vertex across its
    geodesic (b = N × t), and the vertices of the two end rows also along it (t); and the unit
    tangents ``t (2m, 3)`` of all vertices."""
    m = start.shape[0]
    c = start.reshape(-1, 3)
    t = unit(np.asarray(tangents, dtype=float).reshape(-1, 3))
    _, N = reference.closest(c)
    b = unit(np.cross(N, t))
    ends = np.r_[0, 1, 2 * m - 2, 2 * m - 1]
    ids = np.r_[np.arange(2 * m), ends]
    return c[ids], np.concatenate([b, t[ends]]), ids, t


def polish_strip(A: np.ndarray, B: np.ndarray, P: np.ndarray, Q: np.ndarray,
                 tangents: np.ndarray, *, closeness_weight: Schedule = CLOSENESS_WEIGHT,
                 tol: float = POLISH_TOL, max_iter: int = POLISH_MAX_ITER) -> PolishResult:
    """Planarize the quads of the strip ``A, B (m, 3)`` (vertices on the boundary geodesics
    ``P, Q (m, 3)`` of the original strip, where these have the unit ``tangents (m, 2, 3)``) by
    guided projection, fitting the original strip.

    The strip is scaled to mean edge length 1 about its centroid for the solve (the solver's
    tolerances are meant for that scale) and scaled back.
    """
    layout = QuadGridLayout(A.shape[0], 2)
    grid = np.stack([A, B], axis=1)
    center = grid.reshape(-1, 3).mean(axis=0)
    edges = np.concatenate([np.linalg.norm(np.diff(grid, axis=0), axis=-1).ravel(),
                            np.linalg.norm(B - A, axis=-1)])
    scale = 1.0 / float(np.mean(edges))
    start = (grid - center) * scale
    V, F = patch_mesh(P, Q)
    reference = ReferenceSurface((V - center) * scale, F)
    points, directions, ids, t = _side_constraints(start, tangents, reference)
    samples = quad_samples(layout)
    hard = [Term("planarity", lambda x: planarity(x, layout), Schedule.constant(1.0), True),
            Term("lateral", lambda x: lateral(x, layout, points, directions, ids),
                 Schedule.constant(1.0), True)]
    fit = hard + [
        Term("closeness", lambda x: surface_closeness(x, layout, reference, samples),
             closeness_weight, False),
        Term("anchor", lambda x: anchor(x, layout, start), ANCHOR_WEIGHT, False),
        Term("slide_fairness", lambda x: slide_fairness(x, layout, start, t),
             SLIDE_WEIGHT, False)]
    fitted = guided_projection(layout.pack(start), fit, tol=tol, max_iter=max_iter)
    result = guided_projection(fitted.x, hard, tol=tol, max_iter=PROJECTION_MAX_ITER)
    out = layout.vertices(result.x) / scale + center
    return PolishResult(A=out[:, 0], B=out[:, 1], status=result.status,
                        iterations=fitted.iterations + result.iterations, R=result.R / scale)
