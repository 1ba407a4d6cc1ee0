"""A short guided-projection polish of an almost planar quad strip (paper §5, §6.2.4): quads made
planar while the vertices stay on the original boundary geodesics.

Both are constraints (hard terms); the solver's regularization (Levenberg–Marquardt ε²) makes
each step a least-change step, so the polish ends at a nearby discrete developable strip whose
vertices have only slid along the geodesics. A fading anchor to the start positions keeps the
first steps from sliding vertices onto each other (a collapsed quad is trivially planar).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.core.constraints.planarity import QuadGridLayout, anchor, closeness, planarity
from dgpc_cli.core.solver import Schedule, Term, guided_projection

#: Weight of the closeness term against planarity (weight 1).
CLOSENESS_WEIGHT = 1.0
#: Weight schedule of the anchor to the start positions (fades out, like the paper's fairness).
ANCHOR_WEIGHT = Schedule(0.1, 0.0, 30)
#: Constant anchor weight of the polish without sliding.
ANCHORED_WEIGHT = 1e-4
#: A u-edge shorter than this fraction of its start length counts as collapsed.
COLLAPSE = 0.2
#: Tolerance on the planarity residual at mean edge length 1.
POLISH_TOL = 1e-12
#: Iteration limit of the polish.
POLISH_MAX_ITER = 200


@dataclass
class PolishResult:
    """Polished vertices ``A, B (m, 3)`` and the solver's outcome."""

    A: np.ndarray
    B: np.ndarray
    status: str
    mode: str
    iterations: int
    R: float


def _solve(start, layout, terms, tol, max_iter):
    return guided_projection(layout.pack(start), terms, tol=tol, max_iter=max_iter)


def _collapsed(grid: np.ndarray, start: np.ndarray) -> bool:
    """Whether a u-edge shrank below ``COLLAPSE`` of its start length (a quad turned into a
    triangle, which is trivially planar)."""
    before = np.linalg.norm(np.diff(start, axis=0), axis=-1)
    after = np.linalg.norm(np.diff(grid, axis=0), axis=-1)
    return bool(np.any(after < COLLAPSE * before))


def polish_strip(A: np.ndarray, B: np.ndarray, tangents: np.ndarray, *,
                 closeness_weight: float = CLOSENESS_WEIGHT, tol: float = POLISH_TOL,
                 max_iter: int = POLISH_MAX_ITER) -> PolishResult:
    """Planarize the quads of the strip ``A, B (m, 3)`` by guided projection, its vertices
    sliding along the tangent lines ``tangents (m, 2, 3)`` of the boundary geodesics there.

    Where two consecutive vertices lie on one straight segment of a geodesic, the only nearby
    planar quad may be a collapsed one; if sliding collapses a u-edge, the polish is redone
    without sliding: planarity against a weak anchor to the start (``mode = "anchored"``; the
    vertices may then leave the geodesics slightly, which the deviation measures).

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
    plan = Term("planarity", lambda x: planarity(x, layout), Schedule.constant(1.0), True)
    terms = [plan,
             Term("closeness", lambda x: closeness(x, layout, start, tangents),
                  Schedule.constant(closeness_weight), True),
             Term("anchor", lambda x: anchor(x, layout, start), ANCHOR_WEIGHT, False)]
    result, mode = _solve(start, layout, terms, tol, max_iter), "sliding"
    if _collapsed(layout.vertices(result.x), start):
        terms = [plan, Term("anchor", lambda x: anchor(x, layout, start),
                            Schedule.constant(ANCHORED_WEIGHT), False)]
        result, mode = _solve(start, layout, terms, tol, max_iter), "anchored"
    out = layout.vertices(result.x) / scale + center
    return PolishResult(A=out[:, 0], B=out[:, 1], status=result.status, mode=mode,
                        iterations=result.iterations, R=result.R / scale)
