"""Discrete Gaussian curvature from the strip widths via the Jacobi equation (1) (paper §3.1).

For geodesic parallel coordinates in arc-length parametrization the strip width w(u) solves
``∂_uu w + K w = 0`` (1), so ``K = −∂_uu w / w``. Discretely (cf. (2)) w is the length of a
v-edge and ∂_uu the second difference along the strip divided by the squared u-edge length.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import as_grid

__all__ = ["gaussian_curvature", "strip_widths"]


def strip_widths(f) -> np.ndarray:
    """Strip widths ``w[u, j] = ‖δ_v f(u, j)‖`` (§3.1), shape ``(m, n − 1)``; strip j lies
    between the u-lines j and j+1."""
    f = as_grid(f)
    return np.linalg.norm(f[:, 1:] - f[:, :-1], axis=-1)


def gaussian_curvature(f) -> np.ndarray:
    """Discrete Gaussian curvature per strip and row from the Jacobi equation (1), ``(m, n − 1)``.

    ``K[u, j] = −∂_uu w / w`` at the v-edge (u, j), with ``w`` the strip width
    (:func:`strip_widths`) and the second derivative on the (possibly non-uniform) u-spacing
    of the strip::

        ∂_uu w ≈ 2 [ (w(u+1) − w(u)) / l₊ − (w(u) − w(u−1)) / l₋ ] / (l₊ + l₋),

    where l₊ (l₋) is the mean length of the strip's two u-edges from row u to u+1 (u−1 to u).
    For equal u-edges l₊ = l₋ = l (the discrete arc-length parametrization the paper assumes in
    (2)) this is exactly ``K = −δ_uu w / (w · l²)``, δ_uu w = w(u+1) − 2 w(u) + w(u−1); the
    non-uniform form keeps K consistent when the u-edges vary. Units 1/length². Exact (1/R²)
    on a sphere's meridian net with equally spaced latitudes; 0 on a cylinder. Defined for
    0 < u < m−1; NaN on the rows u = 0, m−1 and where w or an l is zero.
    """
    f = as_grid(f)
    w = strip_widths(f)
    lu = np.linalg.norm(f[1:] - f[:-1], axis=-1)          # (m-1, n)
    lstrip = 0.5 * (lu[:, :-1] + lu[:, 1:])               # (m-1, n-1): strip's u-step u→u+1
    K = np.full(w.shape, np.nan)
    if w.shape[0] < 3:
        return K
    lp, lm = lstrip[1:], lstrip[:-1]
    wc = w[1:-1]
    with np.errstate(invalid="ignore", divide="ignore"):
        d2w = 2.0 * ((w[2:] - wc) / lp - (wc - w[:-2]) / lm) / (lp + lm)
        ok = (wc > 0) & (lp > 0) & (lm > 0)
        K[1:-1] = np.where(ok, -d2w / np.where(ok, wc, 1.0), np.nan)
    return K
