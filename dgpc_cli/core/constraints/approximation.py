"""Closeness to a reference surface (§5.1): ``⟨f_i − p_i, n_i⟩ = 0``."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian

#: A vertex counts as off the reference's boundary (or off an edge or corner) when the
#: tangential part of f − p exceeds this fraction of |f − p|.
TANGENTIAL = 1e-2


def approximation(x, layout, reference, vertex_ids=None):
    """Residuals against the closest points p_i of ``reference``, 3 rows per vertex.

    ``reference.closest(points) -> (p (k, 3), n (k, 3))`` gives the closest point on the reference
    and the unit normal there; it is evaluated at the current x, so the closest points are
    recomputed every iteration, as in the paper. The residual is ``n nᵀ (f − p)`` — the paper's
    point-to-plane ``⟨f − p, n⟩`` (same squared norm), which lets vertices slide along the
    surface — where f − p is normal to the surface, and the full offset ``f − p`` where it is not:
    there p lies on the reference's boundary, and point-to-plane would let the vertex leave the
    surface within the boundary face's plane. p and n are held fixed in the Jacobian.
    """
    f, _, _ = layout.split(x)
    if vertex_ids is None:
        vertex_ids = np.arange(layout.n_vertices)
    q = f[vertex_ids]
    p, nrm = reference.closest(q)
    d = q - p
    along = np.einsum("ij,ij->i", d, nrm)
    tangential = np.linalg.norm(d - along[:, None] * nrm, axis=1)
    off = tangential > TANGENTIAL * np.linalg.norm(d, axis=1)
    P = np.where(off[:, None, None], np.eye(3), nrm[:, :, None] * nrm[:, None, :])  # (k, 3, 3)
    phi = np.einsum("kij,kj->ki", P, d).ravel()
    rows = np.arange(phi.size).reshape(-1, 3, 1)
    cols = layout.f_cols(vertex_ids)[:, None, :]
    return phi, jacobian(phi.size, layout.size, (rows, cols, P))
