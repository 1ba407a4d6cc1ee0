"""How far a net is from a surface of revolution it could be mistaken for: its parallels (the
rows f(u, ·), orthogonal to the geodesics) against their best-fit circles.

A net on a surface of revolution in meridian position has circles for rows (every rigid motion
keeps them circles), so the figure is 0 there; a freeform surface isometric to a surface of
revolution (paper Fig. 1, 19) has rows that are visibly not circles.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import as_grid

__all__ = ["circle_departure", "parallel_departure"]


def circle_departure(f) -> np.ndarray:
    """Per row u of ``f (m, n, 3)`` the largest distance of its vertices from the row's
    best-fit circle, shape ``(m,)``: the plane of least squares through the row, then the
    circle of least squares in it (Kåsa's algebraic fit); the distance counts both the
    offset from the plane and from the circle within it; a straight row (a circle of infinite
    radius) departs by its distance from its line. NaN for rows of fewer than 3 vertices."""
    f = as_grid(f)
    m, n, _ = f.shape
    if n < 3:
        return np.full(m, np.nan)
    c = f.mean(axis=1, keepdims=True)
    q = f - c                                                   # (m, n, 3)
    _, sv, vt = np.linalg.svd(q, full_matrices=False)           # rows' principal axes
    straight = sv[:, 1] <= 1e-12 * sv[:, 0]                     # rows on a line (or a point)
    x = np.einsum("mnk,mk->mn", q, vt[:, 0])
    y = np.einsum("mnk,mk->mn", q, vt[:, 1])
    z = np.einsum("mnk,mk->mn", q, vt[:, 2])
    A = np.stack([x, y, np.ones_like(x)], axis=-1)              # (m, n, 3)
    b = x * x + y * y
    AtA = np.einsum("mni,mnj->mij", A, A)
    AtA[straight] = np.eye(3)                                   # solved apart, below
    sol = np.linalg.solve(AtA, np.einsum("mni,mn->mi", A, b)[..., None])[..., 0]
    cx, cy = 0.5 * sol[:, 0], 0.5 * sol[:, 1]
    radius = np.sqrt(np.maximum(sol[:, 2] + cx * cx + cy * cy, 0.0))
    in_plane = np.hypot(x - cx[:, None], y - cy[:, None]) - radius[:, None]
    out = np.sqrt(in_plane**2 + z**2).max(axis=1)
    out[straight] = np.sqrt(y**2 + z**2)[straight].max(axis=1)
    return out


def parallel_departure(f) -> dict:
    """``{"max", "relative", "row"}``: the largest :func:`circle_departure`, also relative to
    the net's bounding-box diagonal, and the row where it is reached."""
    f = as_grid(f)
    d = circle_departure(f)
    if not np.isfinite(d).any():
        return {"max": None, "relative": None, "row": None}
    u = int(np.nanargmax(d))
    diagonal = float(np.linalg.norm(np.ptp(f.reshape(-1, 3), axis=0)))
    return {"max": float(d[u]), "relative": float(d[u] / diagonal) if diagonal > 0 else None,
            "row": u}
