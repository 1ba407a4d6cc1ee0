"""Geometric residuals from vertex positions alone (SPEC §7).

Each function takes a net f of shape ``(m, n, 3)`` (u along the geodesics, v across; see
:mod:`dgpc_cli.metrics.frames`) and returns an array of local values, NaN where a value is
undefined; :func:`finite_max` turns one into the reported maximum. Pure and vectorized.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import (
    as_grid,
    corner_angles,
    edge_lengths,
    tangent_frames,
    unit,
)
from dgpc_cli.tolerances import tol

__all__ = [
    "arclength_spread",
    "edge_length_stats",
    "finite_max",
    "gpc_angle_defect",
    "gpc_angle_defect_max",
    "jacobi_residual",
    "orthogonality",
    "pleat",
    "ratio_spread",
    "spread",
    "strip_width_spread",
    "u_edge_spread",
]


def finite_max(x, absolute: bool = False) -> float | None:
    """Largest finite entry of x (of ``|x|`` with ``absolute``), or None if there is none."""
    x = np.asarray(x, dtype=float)
    if absolute:
        x = np.abs(x)
    x = x[np.isfinite(x)]
    return float(x.max()) if x.size else None


def spread(x: np.ndarray, axis: int) -> np.ndarray:
    """Relative spread ``(max − min)/mean`` of positive values along ``axis``.

    NaN where the mean is not positive. Shape: ``x.shape`` without ``axis``.
    """
    x = np.asarray(x, dtype=float)
    mean = x.mean(axis=axis)
    width = x.max(axis=axis) - x.min(axis=axis)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(mean > 0, width / np.where(mean > 0, mean, 1.0), np.nan)


def gpc_angle_defect(f) -> np.ndarray:
    """Angle defect of discrete geodesic parallel coordinates, Prop. 2.7 (ii), shape ``(m, n)``.

    ``max(|α12 − α_12̄|, |α_1̄2 − α_1̄2̄|)`` in radians over the pairs that exist at the vertex:
    both at interior vertices, only the α12/α_12̄ pair on the row u = 0, only α_1̄2/α_1̄2̄ on
    u = m−1. Undefined (NaN) on the boundary u-lines v = 0 and v = n−1, where a discrete
    geodesic is not defined (Def. 2.2). Zero exactly for discrete GPC (Def. 2.6), e.g. the
    meridian net of a surface of revolution.
    """
    a = corner_angles(f)
    d1 = np.abs(a.a12 - a.a12b)
    d2 = np.abs(a.a1b2 - a.a1b2b)
    return np.fmax(d1, d2)   # NaN only where both are NaN


def gpc_angle_defect_max(f) -> float | None:
    """Maximum of :func:`gpc_angle_defect` (radians); None for a net without interior u-lines."""
    return finite_max(gpc_angle_defect(f))


def orthogonality(f) -> np.ndarray:
    """Orthogonality residual ``|⟨T^u, T^v⟩|`` (Def. 2.4, Lemma 2.5), shape ``(m, n)``.

    Defined at interior vertices 0 < u < m−1, 0 < v < n−1 (where both tangents exist); NaN
    elsewhere. It is the cosine of the angle between the parameter lines.
    """
    Tu, Tv, _ = tangent_frames(f)
    return np.abs(np.einsum("...i,...i->...", Tu, Tv))


def arclength_spread(f) -> np.ndarray:
    """Per u-line (fixed v) relative spread ``(max − min)/mean`` of its u-edge lengths, ``(n,)``.

    Zero for a discrete arc-length parametrization of the geodesics (§3.1, §5.1 "arclength").
    """
    lu, _ = edge_lengths(f)
    return spread(lu, axis=0)


def strip_width_spread(f) -> np.ndarray:
    """Per row u relative spread ``(max − min)/mean`` of the v-edge lengths, shape ``(m,)``.

    Zero for equal strip widths, equation (7) / §4.2.1 (intrinsic repetitivity).
    """
    _, lv = edge_lengths(f)
    return spread(lv, axis=1)


def u_edge_spread(f) -> np.ndarray:
    """Per row step u → u+1 the relative spread ``(max − min)/mean`` of its u-edge lengths
    across the columns, shape ``(m − 1,)``.

    Zero when the strips of a net isometric to a surface of revolution are congruent
    (§4.2.1); what a revolution-mode drag leaves of it is the congruence error of the strips.
    """
    lu, _ = edge_lengths(f)
    return spread(lu, axis=1)


#: Rows over which the pleat measure averages (a pleat runs along the geodesics; noise does not).
PLEAT_WINDOW = 5


def pleat(f) -> np.ndarray:
    """Period-2 corrugation across the geodesics, shape ``(m, n − 5)`` (empty for n < 6), in
    units of the net's mean edge length.

    Along each row, the second differences s(v) = f(v−1) − 2 f(v) + f(v+1), their alternating
    part a(v) = s(v) − (s(v−1) + s(v+1))/2 and its change (a(v) − a(v+1))/2, along the net's
    normal, divided by 8 and averaged (signed) over ``PLEAT_WINDOW`` consecutive rows. For the
    pleated nets of the isometry study (even and odd meridians on two profiles, offset ±p
    along the normal) it is p; for a smooth net it is a fifth difference, O(h⁵/ρ⁴), small even
    on coarse nets of curved surfaces. Unevenly spaced vertices along a row (a tangential
    change) and noise uncorrelated along the geodesics (shrunk by the average over rows) are
    not pleats.
    """
    f = as_grid(f)
    m, n, _ = f.shape
    if n < 6:
        return np.zeros((m, 0))
    s = f[:, :-2] - 2.0 * f[:, 1:-1] + f[:, 2:]
    a = s[:, 1:-1] - 0.5 * (s[:, :-2] + s[:, 2:])          # at vertices 2 … n−3
    d = 0.5 * (a[:, :-1] - a[:, 1:])                        # between vertices v, v+1
    _, _, N = tangent_frames(f, one_sided=True)
    normal = unit(N[:, 2:-3] + N[:, 3:-2])
    lu, lv = edge_lengths(f)
    mean = (lu.sum() + lv.sum()) / (lu.size + lv.size)
    signed = np.einsum("uvk,uvk->uv", d, normal) / (8.0 * mean)
    k = min(PLEAT_WINDOW, m)
    c = np.concatenate([np.zeros((1, signed.shape[1])), np.cumsum(signed, axis=0)])
    window = (c[k:] - c[:-k]) / k                           # (m − k + 1, n − 5)
    lo = np.clip(np.arange(m) - k // 2, 0, m - k)           # the window centred at each row
    return np.abs(window[lo])


def ratio_spread(f) -> np.ndarray:
    """Residual of equation (5) for consecutive rows, shape ``(m − 1,)``.

    For rows a, a+1 the ratio ``‖δ_v f(a, v)‖ / ‖δ_v f(a+1, v)‖`` must not depend on v; returns
    per row pair its relative spread ``(max − min)/mean`` over v. (Consecutive pairs imply (5)
    for all pairs a, b.) NaN where a v-edge is degenerate.
    """
    _, lv = edge_lengths(f)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(lv[1:] > 0, lv[:-1] / np.where(lv[1:] > 0, lv[1:], 1.0), np.nan)
    return spread(ratio, axis=1)


def jacobi_residual(f) -> np.ndarray:
    """Relative discrete Jacobi residual, equation (2), shape ``(m, n − 1)``.

    For strip j (between the u-lines j and j+1) with widths ``w(u) = ‖δ_v f(u, j)‖``:
    ``(w(u+1) − 2 w(u) + w(u−1)) / mean(w)``, the mean over all v-edges of the net. Signed;
    defined for 0 < u < m−1, NaN on the rows u = 0 and u = m−1. Zero for a developable net in
    discrete arc-length parametrization (§3.2, (8)).
    """
    _, w = edge_lengths(f)
    out = np.full(w.shape, np.nan)
    mean = w.mean()
    if mean > 0:
        out[1:-1] = (w[2:] - 2.0 * w[1:-1] + w[:-2]) / mean
    return out


def edge_length_stats(f) -> dict:
    """Edge lengths over all u- and v-edges: ``{min, mean, max, min_ratio, folded}``.

    ``min_ratio`` = min/mean; ``folded`` is True when an edge is shorter than
    ``tol.min_edge_ratio`` (10 %) of the mean edge (the fold check of SPEC §7).
    """
    lu, lv = edge_lengths(as_grid(f))
    lengths = np.concatenate([lu.ravel(), lv.ravel()])
    mean = float(lengths.mean())
    lo = float(lengths.min())
    ratio = lo / mean if mean > 0 else 0.0
    return {"min": lo, "mean": mean, "max": float(lengths.max()), "min_ratio": ratio,
            "folded": bool(ratio < tol.min_edge_ratio)}
