"""Quality of a discrete developable strip (SPEC §6 planarize-strips, §7): planarity of its quads
and its deviation from the original geodesic strip (paper §6.2.4)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.reference import ReferenceSurface

#: Subdivisions per side of an original quad when it is triangulated as a bilinear patch.
PATCH_SUBDIVISIONS = 4
#: Samples per side of a new (planar) quad where the deviation is measured.
QUAD_SAMPLES = 3


def diagonal_gap(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Distance between the lines of the two diagonals of every quad ``A_u, A_(u+1), B_(u+1),
    B_u`` of a strip ``A, B (..., m, 3)``, in its unit: shape ``(..., m−1)``; zero exactly for
    planar quads (the two diagonals of a planar quad intersect)."""
    d1 = B[..., 1:, :] - A[..., :-1, :]          # A_u -> B_(u+1)
    d2 = A[..., 1:, :] - B[..., :-1, :]          # B_u -> A_(u+1)
    c = np.cross(d1, d2)
    cn = np.linalg.norm(c, axis=-1)
    gap = np.abs(np.einsum("...i,...i->...", B[..., :-1, :] - A[..., :-1, :], c))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(cn > 0, gap / np.where(cn > 0, cn, 1.0), 0.0)


def planarity_defect(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Distance between the diagonals' lines over their mean length for every quad
    ``A_u, A_(u+1), B_(u+1), B_u`` of a strip ``A, B (..., m, 3)``: shape ``(..., m−1)``.

    Zero exactly for planar quads (the two diagonals of a planar quad intersect).
    """
    d1 = B[..., 1:, :] - A[..., :-1, :]
    d2 = A[..., 1:, :] - B[..., :-1, :]
    mean = 0.5 * (np.linalg.norm(d1, axis=-1) + np.linalg.norm(d2, axis=-1))
    return diagonal_gap(A, B) / mean


def bilinear_samples(A: np.ndarray, B: np.ndarray, k: int) -> np.ndarray:
    """Points of the bilinear patches of the quads of a strip ``A, B (m, 3)``: ``k × k`` per
    quad, ``((m−1) k², 3)``."""
    s = np.linspace(0.0, 1.0, k)
    su, sv = np.meshgrid(s, s, indexing="ij")
    su, sv = su.ravel()[None, :, None], sv.ravel()[None, :, None]
    a0, a1, b0, b1 = A[:-1, None], A[1:, None], B[:-1, None], B[1:, None]
    pts = (1 - su) * (1 - sv) * a0 + su * (1 - sv) * a1 + su * sv * b1 + (1 - su) * sv * b0
    return pts.reshape(-1, 3)


def patch_mesh(P: np.ndarray, Q: np.ndarray, k: int = PATCH_SUBDIVISIONS):
    """Triangle mesh ``(vertices, faces)`` of the original strip ``P, Q (m, 3)``: each quad as a
    bilinear patch subdivided ``k × k``."""
    m = P.shape[0]
    rows = (m - 1) * k + 1
    t = np.linspace(0.0, m - 1.0, rows)
    i = np.clip(np.floor(t).astype(int), 0, m - 2)
    fr = (t - i)[:, None]
    p_rows = P[i] + fr * (P[i + 1] - P[i])
    q_rows = Q[i] + fr * (Q[i + 1] - Q[i])
    w = np.linspace(0.0, 1.0, k + 1)[None, :, None]
    V = ((1 - w) * p_rows[:, None] + w * q_rows[:, None]).reshape(-1, 3)     # (rows, k+1)
    vid = np.arange(rows * (k + 1)).reshape(rows, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                        np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F


def quad_deviation(A: np.ndarray, B: np.ndarray, P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Per quad of the planar strip ``A, B (r, 3)`` ``(r − 1,)``: the largest distance of its
    points (``QUAD_SAMPLES²`` per quad, bilinear) from the original strip ``P, Q (m, 3)``
    (bilinear quads, finely triangulated), in their unit."""
    V, F = patch_mesh(P, Q)
    surface = ReferenceSurface(V, F)
    pts = bilinear_samples(A, B, QUAD_SAMPLES)
    closest, _ = surface.closest(pts)
    dist = np.linalg.norm(pts - closest, axis=1)
    return dist.reshape(A.shape[0] - 1, -1).max(axis=1)


def deviation(A: np.ndarray, B: np.ndarray, P: np.ndarray, Q: np.ndarray) -> float:
    """Largest distance of the planar strip ``A, B (m, 3)`` (sampled ``QUAD_SAMPLES²`` per quad)
    from the original strip ``P, Q (m, 3)`` (bilinear quads, finely triangulated)."""
    return float(np.max(quad_deviation(A, B, P, Q)))


def strip_width(P: np.ndarray, Q: np.ndarray) -> float:
    """Mean length of the v-edges of a strip (its width, paper §3.1)."""
    return float(np.mean(np.linalg.norm(Q - P, axis=-1)))
