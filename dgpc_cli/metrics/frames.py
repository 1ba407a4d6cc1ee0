"""Edge vectors, corner angles and the tangent frame T^u, T^v, N of a net (paper §2.2).

Grid conventions (SPEC §4, ``dgpc_cli.core.layout``): f is an ``(m, n, 3)`` array ``f[u, v]``;
u runs along the geodesics (u-lines, fixed v), v across them. At the vertex f = f(u, v)

* e1 = unit(f(u+1, v) − f), e3 = unit(f(u−1, v) − f)   (u-edges, paper §2.2.1)
* e2 = unit(f(u, v+1) − f), e4 = unit(f(u, v−1) − f)   (v-edges)
* α12 = ∠(e1, e2), α_1̄2 = ∠(e3, e2), α_1̄2̄ = ∠(e3, e4), α_12̄ = ∠(e1, e4)
* T^u = unit(e1 − e3), T^v = unit(e2 − e4), N = unit(T^u × T^v)   (§2.2.1)

Everything that does not exist at a vertex (the edge beyond a boundary, an angle using it, a
tangent needing both edges) is NaN, so masks are ``np.isfinite(x)`` (vectors: ``.all(-1)``).
All functions are pure and vectorized over the grid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "CornerAngles",
    "NetFrames",
    "angle",
    "as_grid",
    "corner_angles",
    "edge_lengths",
    "edge_vectors",
    "net_frames",
    "tangent_frames",
    "unit",
    "unit_edge_vectors",
]


def as_grid(f, name: str = "net") -> np.ndarray:
    """Validate and return a net as a float array of shape ``(m, n, 3)``, m, n ≥ 2, all finite.

    Raises ``ValueError`` with a one-line reason otherwise.
    """
    f = np.asarray(f, dtype=float)
    if f.ndim != 3 or f.shape[2] != 3:
        raise ValueError(f"{name} must be an (m, n, 3) array of vertex positions, got shape "
                         f"{f.shape}")
    if f.shape[0] < 2 or f.shape[1] < 2:
        raise ValueError(f"{name} needs at least 2×2 vertices, got {f.shape[0]}×{f.shape[1]}")
    if not np.all(np.isfinite(f)):
        raise ValueError(f"{name} has non-finite vertex coordinates")
    return f


def unit(x: np.ndarray) -> np.ndarray:
    """Normalize vectors along the last axis; zero or NaN vectors give NaN. Shape preserved."""
    x = np.asarray(x, dtype=float)
    norm = np.linalg.norm(x, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, x / np.where(norm > 0, norm, 1.0), np.nan)


def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle ∠(a, b) ∈ [0, π] between vectors along the last axis, shape ``a.shape[:-1]``.

    Computed as ``atan2(‖a × b‖, ⟨a, b⟩)``, which is accurate to round-off for all angles
    (``arccos`` of the paper's definition loses half the digits near 0 and π). The formula is
    scale invariant, so a and b need not be unit vectors. NaN in, NaN out.
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i->...", a, b))


def edge_lengths(f) -> tuple[np.ndarray, np.ndarray]:
    """Lengths ``‖δ_u f‖`` of the u-edges ``(m−1, n)`` and ``‖δ_v f‖`` of the v-edges ``(m, n−1)``.

    ``lv[u, j]`` is the width of strip j (between the u-lines j and j+1) at row u (paper §3.1).
    """
    f = as_grid(f)
    return (np.linalg.norm(f[1:] - f[:-1], axis=-1),
            np.linalg.norm(f[:, 1:] - f[:, :-1], axis=-1))


def edge_vectors(f) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Edge vectors emanating from each vertex, ``(E1, E2, E3, E4)``, each ``(m, n, 3)``.

    E1 = f(u+1, v) − f = δ_u f, E2 = δ_v f, E3 = −δ_u f_1̄, E4 = −δ_v f_2̄ (paper §2.2.1, before
    normalization); NaN where the neighbour does not exist.
    """
    f = as_grid(f)
    m, n, _ = f.shape
    du = f[1:] - f[:-1]
    dv = f[:, 1:] - f[:, :-1]
    E1, E2, E3, E4 = (np.full((m, n, 3), np.nan) for _ in range(4))
    E1[:-1] = du
    E3[1:] = -du
    E2[:, :-1] = dv
    E4[:, 1:] = -dv
    return E1, E2, E3, E4


def unit_edge_vectors(f) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Unit edge vectors ``(e1, e2, e3, e4)`` of paper §2.2.1, each ``(m, n, 3)``.

    NaN where the edge does not exist or is degenerate (zero length).
    """
    return tuple(unit(E) for E in edge_vectors(f))


@dataclass(frozen=True)
class CornerAngles:
    """The four angles at each vertex (paper §2.2.1), each ``(m, n)``, NaN where undefined.

    ``a12`` = α12 = ∠(e1, e2); ``a1b2`` = α_1̄2 = ∠(e3, e2); ``a1b2b`` = α_1̄2̄ = ∠(e3, e4);
    ``a12b`` = α_12̄ = ∠(e1, e4).
    """

    a12: np.ndarray
    a1b2: np.ndarray
    a1b2b: np.ndarray
    a12b: np.ndarray


def corner_angles(f) -> CornerAngles:
    """Corner angles α12, α_1̄2, α_1̄2̄, α_12̄ at every vertex (paper §2.2.1), each ``(m, n)``.

    Computed with :func:`angle` (atan2) from the edge vectors; NaN where one of the two edges
    does not exist or is degenerate.
    """
    E1, E2, E3, E4 = edge_vectors(f)
    with np.errstate(invalid="ignore"):
        return CornerAngles(a12=_angle_nz(E1, E2), a1b2=_angle_nz(E3, E2),
                            a1b2b=_angle_nz(E3, E4), a12b=_angle_nz(E1, E4))


def _angle_nz(a, b):
    """:func:`angle`, NaN when a or b has zero length."""
    ok = (np.linalg.norm(a, axis=-1) > 0) & (np.linalg.norm(b, axis=-1) > 0)
    return np.where(ok, angle(a, b), np.nan)


def tangent_frames(f, one_sided: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tangents and normal ``(T^u, T^v, N)`` at every vertex (paper §2.2.1), each ``(m, n, 3)``.

    T^u = (e1 − e3)/‖e1 − e3‖, T^v = (e2 − e4)/‖e2 − e4‖, N = T^u × T^v/‖T^u × T^v‖.
    By default T^u exists at 0 < u < m−1 and T^v at 0 < v < n−1 (both edges needed), N where
    both exist (the interior); NaN elsewhere. With ``one_sided=True`` a missing edge counts as
    the zero vector, so boundary vertices get T^u = e1 or −e3 (T^v = e2 or −e4) and every
    vertex has a frame.
    """
    e1, e2, e3, e4 = unit_edge_vectors(f)
    if one_sided:
        e1, e2, e3, e4 = (np.nan_to_num(e, nan=0.0) for e in (e1, e2, e3, e4))
    Tu = unit(e1 - e3)
    Tv = unit(e2 - e4)
    N = unit(np.cross(Tu, Tv))
    return Tu, Tv, N


@dataclass(frozen=True)
class NetFrames:
    """Everything of paper §2.2.1 at once; arrays ``(m, n, 3)`` or ``(m, n)``, NaN = missing."""

    e1: np.ndarray
    e2: np.ndarray
    e3: np.ndarray
    e4: np.ndarray
    angles: CornerAngles
    Tu: np.ndarray
    Tv: np.ndarray
    N: np.ndarray

    @property
    def has_Tu(self) -> np.ndarray:
        """``(m, n)`` bool: where T^u exists."""
        return np.isfinite(self.Tu).all(axis=-1)

    @property
    def has_Tv(self) -> np.ndarray:
        """``(m, n)`` bool: where T^v exists."""
        return np.isfinite(self.Tv).all(axis=-1)

    @property
    def has_N(self) -> np.ndarray:
        """``(m, n)`` bool: where N exists."""
        return np.isfinite(self.N).all(axis=-1)


def net_frames(f, one_sided: bool = False) -> NetFrames:
    """Unit edge vectors, corner angles and ``(T^u, T^v, N)`` of a net (paper §2.2.1).

    ``one_sided`` as in :func:`tangent_frames`.
    """
    f = as_grid(f)
    e1, e2, e3, e4 = unit_edge_vectors(f)
    Tu, Tv, N = tangent_frames(f, one_sided=one_sided)
    return NetFrames(e1=e1, e2=e2, e3=e3, e4=e4, angles=corner_angles(f), Tu=Tu, Tv=Tv, N=N)
