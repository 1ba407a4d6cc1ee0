"""Discrete geodesic parallel coordinates: the angle condition (6), Proposition 2.7 (ii)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def gpc_stencil(layout):
    """Edge ids of the angle condition, one pair of equations per u-edge of an interior column.

    For the u-edge ``eu[u, v]`` (1 ≤ v ≤ n−2) the two v-edges at its start vertex are
    ``ev[u, v]`` and ``ev[u, v−1]``, and at its end vertex ``ev[u+1, v]``, ``ev[u+1, v−1]``.
    Returns ``(eu, ev_start, ev_start_prev, ev_end, ev_end_prev)``, each of shape (k,).
    """
    eu = layout.eu[:, 1:-1]
    ev = layout.ev
    return (eu.ravel(), ev[:-1, 1:].ravel(), ev[:-1, :-1].ravel(), ev[1:, 1:].ravel(),
            ev[1:, :-1].ravel())


def gpc(x, layout):
    """Residuals of the angle condition, equation (6).

    ``⟨e_ij, e_ik⟩ − ⟨e_im, e_ij⟩ = 0`` and ``⟨e_il, e_ik⟩ − ⟨e_im, e_il⟩ = 0``.

    With one unit vector per edge, at a vertex f with u-edges e1 = e_u, e3 = −e_u(ū) and v-edges
    e2 = e_v, e4 = −e_v(v̄) both equations read ``⟨e_u, e_v + e_v(v̄)⟩ = 0``: each u-edge is
    orthogonal to the bisector of the two v-edges at either end (Prop. 2.7 (iii)). There are
    2(m−1)(n−2) equations, as in the paper's count 2(mn − n − 2m + 2).
    """
    _, e, _ = layout.split(x)
    eu, a0, b0, a1, b1 = gpc_stencil(layout)
    k = eu.size
    s0 = e[a0] + e[b0]                                  # bisector at the start vertex
    s1 = e[a1] + e[b1]                                  # bisector at the end vertex
    t = e[eu]
    phi = np.concatenate([np.einsum("ij,ij->i", t, s0), np.einsum("ij,ij->i", t, s1)])
    r0 = np.arange(k)[:, None]
    r1 = k + r0
    J = jacobian(
        2 * k, layout.size,
        (r0, layout.e_cols(eu), s0),
        (r0, layout.e_cols(a0), t),
        (r0, layout.e_cols(b0), t),
        (r1, layout.e_cols(eu), s1),
        (r1, layout.e_cols(a1), t),
        (r1, layout.e_cols(b1), t),
    )
    return phi, J
