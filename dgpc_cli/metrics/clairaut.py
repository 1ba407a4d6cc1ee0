"""Clairaut's relation (9) for nets on a surface of revolution (paper §6.1, Fig. 11).

Along a geodesic of a surface of revolution ``r cos α = const`` (9), r the distance to the
axis and α the angle between the geodesic and the parallel circle. Discretely, at a vertex f
of a u-line with tangent T^u (§2.2.1) and axis through a with unit direction d,
``r cos α = ⟨T^u, d × (f − a)⟩``, since ``d × (f − a)`` is the parallel circle's tangent
scaled by r.
"""

from __future__ import annotations

import math

import numpy as np

from dgpc_cli.metrics.frames import as_grid, tangent_frames

__all__ = ["as_axis", "clairaut", "clairaut_values", "normalize_axis", "parse_axis"]


def normalize_axis(point, direction) -> tuple[np.ndarray, np.ndarray]:
    """Validate an axis: returns ``(a (3,), d (3,))`` with d a unit vector.

    Raises ``ValueError`` with a one-line reason for wrong sizes, non-finite numbers or a zero
    direction.
    """
    a = np.asarray(point, dtype=float).reshape(-1)
    d = np.asarray(direction, dtype=float).reshape(-1)
    if a.size != 3 or d.size != 3:
        raise ValueError("axis needs a point and a direction of 3 coordinates each")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(d))):
        raise ValueError("axis has non-finite numbers")
    norm = float(np.linalg.norm(d))
    if not norm > 0:
        raise ValueError("axis direction is the zero vector")
    return a, d / norm


def parse_axis(text: str) -> tuple[np.ndarray, np.ndarray]:
    """Parse ``"px,py,pz,dx,dy,dz"`` into a point ``a (3,)`` and a unit direction ``d (3,)``.

    Raises ``ValueError`` with a one-line reason if there are not exactly 6 numbers, a number is
    not finite, or the direction is zero.
    """
    parts = [p.strip() for p in str(text).split(",")]
    if len(parts) != 6 or any(not p for p in parts):
        raise ValueError(f"axis must be 6 comma-separated numbers px,py,pz,dx,dy,dz, got "
                         f"{text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"axis must be 6 comma-separated numbers px,py,pz,dx,dy,dz, got "
                         f"{text!r}") from None
    if not all(math.isfinite(x) for x in values):
        raise ValueError(f"axis has non-finite numbers: {text!r}")
    return normalize_axis(values[:3], values[3:])


def as_axis(axis) -> tuple[np.ndarray, np.ndarray]:
    """An axis given as ``(point, direction)`` or as the text ``"px,py,pz,dx,dy,dz"``, validated
    into ``(a (3,), d (3,))`` with d a unit vector (ValueError with a one-line reason)."""
    if isinstance(axis, str):
        return parse_axis(axis)
    try:
        point, direction = axis
    except (TypeError, ValueError):
        raise ValueError("axis must be a (point, direction) pair or 'px,py,pz,dx,dy,dz'") from None
    return normalize_axis(point, direction)


def clairaut_values(f, axis) -> np.ndarray:
    """``r cos α = ⟨T^u, d × (f − a)⟩`` at every vertex (equation (9)), shape ``(m, n)``.

    Defined at 0 < u < m−1 on every u-line (fixed v), where T^u exists; NaN on the rows
    u = 0, m−1. Signed: positive where the u-line winds about d in the positive sense.
    """
    f = as_grid(f)
    a, d = as_axis(axis)
    Tu, _, _ = tangent_frames(f)
    circle = np.cross(d, f - a)             # parallel-circle tangent times r
    return np.einsum("...i,...i->...", Tu, circle)


def _none_if_nan(x: np.ndarray) -> list:
    return [float(v) if np.isfinite(v) else None for v in np.asarray(x, dtype=float)]


def clairaut(f, axis) -> dict:
    """Clairaut check (9) per geodesic (u-line) and for the net; axis as in :func:`as_axis`.

    Returns::

        {"per_geodesic": {"v": [n-2], "mean": [n-2], "mad": [n-2], "relative_mad": [n-2]},
         "max_relative_mad": float | None, "max_mad": float | None,
         "max_mad_over_radius": float | None, "mean_abs": float | None,
         "mean_radius": float}

    The geodesics are the interior u-lines v = 1 … n−2: the angle condition (6) makes no claim
    about the two boundary u-lines (paper §2.2.2), so they are not checked.
    ``mad`` is the mean absolute deviation of r cos α from its mean along the geodesic,
    ``relative_mad`` = mad/|mean| (None when |mean| ≤ 1e-12 · mean radius, e.g. a meridian,
    where r cos α = 0), ``mean_abs`` the mean |r cos α| over all interior vertices,
    ``max_mad_over_radius`` = max mad / mean radius (defined even for meridians), and
    ``mean_radius`` the mean distance of the net's vertices to the axis. Lists are None
    where undefined (nets with fewer than 3 rows).
    """
    f = as_grid(f)
    a, d = as_axis(axis)
    m, n, _ = f.shape
    radius = float(np.linalg.norm(np.cross(d, f - a), axis=-1).mean())
    if m < 3:
        per = {key: [None] * max(n - 2, 0) for key in ("mean", "mad", "relative_mad")}
        per["v"] = list(range(1, n - 1))
        return {"per_geodesic": per, "max_relative_mad": None, "max_mad": None,
                "max_mad_over_radius": None, "mean_abs": None, "mean_radius": radius}
    c = clairaut_values(f, (a, d))[1:-1, 1:-1]                 # (m-2, n-2)
    mean = c.mean(axis=0)
    mad = np.abs(c - mean).mean(axis=0)
    defined = np.abs(mean) > 1e-12 * max(radius, np.finfo(float).tiny)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(defined, mad / np.where(defined, np.abs(mean), 1.0), np.nan)

    def fmax(x):
        x = x[np.isfinite(x)]
        return float(x.max()) if x.size else None

    max_mad = fmax(mad)
    return {
        "per_geodesic": {"v": list(range(1, n - 1)), "mean": _none_if_nan(mean),
                         "mad": _none_if_nan(mad), "relative_mad": _none_if_nan(rel)},
        "max_relative_mad": fmax(rel),
        "max_mad": max_mad,
        "max_mad_over_radius": (max_mad / radius if max_mad is not None and radius > 0
                                else None),
        "mean_abs": float(np.abs(c).mean()) if np.all(np.isfinite(c)) else None,
        "mean_radius": radius,
    }
