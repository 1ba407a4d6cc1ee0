"""Where the rulings of a planar strip cross (its boundary runs backwards along a geodesic of
the net between two rows: a folded quad), in the strip's ``(t, s)`` parameters (``t`` the row,
``s`` from side A at 0 to side B at 1), so that a trimmed part is refused only where the fold
lies inside it, not beyond the outline that cuts it away."""

from __future__ import annotations

import numpy as np
from shapely import box
from shapely.geometry import Polygon


def backward(X: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """``(m−1,)``: whether each segment of the strip's boundary ``X (m, 3)`` runs backwards
    along the original geodesic ``curve (m, 3)`` (a non-positive projection on it)."""
    return np.einsum("ij,ij->i", np.diff(X, axis=0), np.diff(curve, axis=0)) <= 0


def folds(A: np.ndarray, B: np.ndarray, P: np.ndarray | None = None,
          Q: np.ndarray | None = None) -> np.ndarray:
    """``(k, 3)``: the folded regions of the strip ``A, B (m, 3)`` cut from the geodesics
    ``P, Q (m, 3)``, each ``(row, s0, s1)``: the quad between rows ``row`` and ``row + 1``,
    from ``s0`` to ``s1`` across (from the side that runs backwards to where the two rulings
    meet; the whole quad when they meet outside it). Without the geodesics (a strips artifact
    alone) a side runs backwards against the strip's middle line."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    if P is None or Q is None:
        P = Q = 0.5 * (A + B)
    bad_a, bad_b = backward(A, P), backward(B, Q)
    rows = np.nonzero(bad_a | bad_b)[0]
    if not rows.size:
        return np.zeros((0, 3))
    # rulings A_k + s (B_k − A_k) and A_k+1 + r (B_k+1 − A_k+1) of a planar quad: least squares
    u, w, d = B[rows] - A[rows], B[rows + 1] - A[rows + 1], A[rows + 1] - A[rows]
    uu, ww, uw = (np.einsum("ij,ij->i", x, y) for x, y in ((u, u), (w, w), (u, w)))
    ud, wd = np.einsum("ij,ij->i", u, d), np.einsum("ij,ij->i", w, d)
    det = uu * ww - uw * uw
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(det > 0, (ud * ww - wd * uw) / det, np.nan)
    inside = np.isfinite(s) & (s > 0) & (s < 1) & (bad_a[rows] != bad_b[rows])
    s0 = np.where(inside & bad_b[rows], s, 0.0)
    s1 = np.where(inside & bad_a[rows], s, 1.0)
    return np.stack([rows.astype(float), s0, s1], axis=1)


def folded_inside(A, B, P, Q, outlines: list) -> bool:
    """Whether a fold of the strip (:func:`folds`) lies inside one of the parts ``outlines``
    (each ``(k, 2)`` in ``(t, s)``) by more than a sliver."""
    regions = folds(A, B, P, Q)
    parts = [Polygon(np.asarray(o, float)).buffer(0) for o in outlines]
    return any(part.intersection(box(k, s0, k + 1, s1)).area > 1e-9
               for k, s0, s1 in regions for part in parts)
