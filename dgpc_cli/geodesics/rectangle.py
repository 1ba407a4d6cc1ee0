"""Largest rectangles of a grid that stay on the mesh (SPEC §5: "geodesics that leave the mesh
are trimmed to a common rectangle of the grid")."""

from __future__ import annotations

import numpy as np


def _range_min(x: np.ndarray) -> np.ndarray:
    """``M[i, j] = min(x[i..j])`` for ``j ≥ i`` (``+inf`` below the diagonal), ``(n, n)``."""
    n = len(x)
    full = np.where(np.arange(n)[None, :] >= np.arange(n)[:, None], x[None, :], np.inf)
    return np.minimum.accumulate(full, axis=1)


def largest_band(t: np.ndarray, ahead: np.ndarray, behind: np.ndarray):
    """Best column range of a fan of geodesics from a base curve.

    Column ``k`` sits at arc length ``t[k]`` on the base curve and its geodesic reaches
    ``ahead[k]`` forward and ``behind[k]`` backward before it leaves the mesh. A rectangle of
    columns ``i..j`` in geodesic distance ``[-B, A]`` lies on the mesh for ``A = min ahead[i..j]``
    and ``B = min behind[i..j]``; returns ``(i, j, A, B)`` maximizing the parameter area
    ``(t[j] - t[i]) · (A + B)`` (``j > i``), or None when no two columns make a rectangle.
    """
    t = np.asarray(t, dtype=float)
    A = _range_min(np.asarray(ahead, dtype=float))
    B = _range_min(np.asarray(behind, dtype=float))
    width = t[None, :] - t[:, None]
    area = np.where(width > 0, width * (A + B), -np.inf)
    area = np.where(np.isfinite(area), area, -np.inf)
    k = int(np.argmax(area))
    i, j = divmod(k, len(t))
    if not np.isfinite(area[i, j]) or area[i, j] <= 0:
        return None
    return i, j, float(A[i, j]), float(B[i, j])


def largest_rectangle(mask: np.ndarray, count: str = "spanned"):
    """Largest axis-aligned block of True entries of ``mask (R, C)`` with at least 2 rows and
    2 columns, by spanned area ``(rows - 1)(cols - 1)`` (a mask of grid points), or with
    ``count="entries"`` by ``rows · cols`` (a mask of grid cells): ``(r0, r1, c0, c1)``
    inclusive, or None.

    Histogram method: ``H[r, c]`` counts the consecutive True entries ending at row r; for each
    row the best column range comes from the range minima of ``H[r]`` (vectorized per row).
    """
    mask = np.asarray(mask, dtype=bool)
    R, C = mask.shape
    H = np.zeros((R, C), dtype=np.int64)
    run = np.zeros(C, dtype=np.int64)
    for r in range(R):  # a loop over rows, vectorized over columns
        run = np.where(mask[r], run + 1, 0)
        H[r] = run
    cols = np.arange(C)
    width = (cols[None, :] - cols[:, None]).astype(float)
    best, where = 0.0, None
    for r in range(R):
        h = _range_min(H[r].astype(float))
        if count == "entries":
            ok = (width > 0) & (h >= 2) & np.isfinite(h)
            area = np.where(ok, (width + 1) * np.where(ok, h, 0.0), 0.0)
        else:
            area = np.where(width > 0, width * np.maximum(h - 1, 0), 0.0)
        k = int(np.argmax(area))
        if area.flat[k] > best:
            i, j = divmod(k, C)
            best, where = float(area.flat[k]), (r - int(h[i, j]) + 1, r, i, j)
    return where
