"""Closeness to a reference surface (§5.1): ``⟨f_i − p_i, n_i⟩ = 0``."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def approximation(x, layout, reference, vertex_ids=None):
    """Point-to-plane residuals against the closest points of ``reference``.

    ``reference.closest(points) -> (p (k, 3), n (k, 3))`` gives the closest point on the reference
    and the unit normal there; it is evaluated at the current x, so the closest points are
    recomputed every iteration, as in the paper. p and n are held fixed in the Jacobian.
    """
    f, _, _ = layout.split(x)
    if vertex_ids is None:
        vertex_ids = np.arange(layout.n_vertices)
    q = f[vertex_ids]
    p, nrm = reference.closest(q)
    phi = np.einsum("ij,ij->i", q - p, nrm)
    rows = np.arange(phi.size)
    return phi, jacobian(phi.size, layout.size, (rows[:, None], layout.f_cols(vertex_ids), nrm))
