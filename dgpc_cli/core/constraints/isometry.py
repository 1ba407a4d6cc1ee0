"""Isometry to a reference net (§5.1): ``w_ij − w⁰_ij = 0``, and the boundary angles.

Edge lengths alone leave every quad one degree of freedom (its shear). Inside the net the angle
condition (6) takes it away; on the two boundary u-lines (v = 0 and v = n−1) it does not reach,
so there the angle between each u-edge and the v-edge at the same vertex is kept as well:
``⟨e_u, e_v⟩ − ⟨e⁰_u, e⁰_v⟩ = 0``. Without it the boundary quads shear freely and the strain
tensor D of §6.1 (which measures angle changes) is far from zero on the boundary.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def boundary_angle_pairs(layout):
    """Edge id pairs ``(u-edge, v-edge)`` meeting at a vertex of the boundary u-lines, (k, 2)."""
    eu, ev = layout.eu, layout.ev
    pairs = [np.stack([eu[:, 0], ev[:-1, 0]], 1), np.stack([eu[:, 0], ev[1:, 0]], 1),
             np.stack([eu[:, -1], ev[:-1, -1]], 1), np.stack([eu[:, -1], ev[1:, -1]], 1)]
    return np.concatenate(pairs)


def isometry_data(layout, f0):
    """``(w0, cos0)`` of the reference net ``f0 (m, n, 3)``: its edge lengths and the cosines of
    the boundary angles (see :func:`boundary_angle_pairs`)."""
    d = layout.edge_vectors(f0)
    w0 = np.linalg.norm(d, axis=1)
    e0 = d / w0[:, None]
    p = boundary_angle_pairs(layout)
    return w0, np.einsum("ij,ij->i", e0[p[:, 0]], e0[p[:, 1]])


def isometry(x, layout, w0, cos0=None):
    """Residuals ``w_ij − w⁰_ij`` for every edge (|E|,), then, with ``cos0``, the boundary
    angle residuals ``⟨e_u, e_v⟩ − cos0`` (k,)."""
    _, e, w = layout.split(x)
    rows = np.arange(layout.n_edges)
    blocks = [(rows, layout.w_cols(rows), 1.0)]
    phi = [w - w0]
    if cos0 is not None:
        p = boundary_angle_pairs(layout)
        a, b = e[p[:, 0]], e[p[:, 1]]
        phi.append(np.einsum("ij,ij->i", a, b) - cos0)
        r = layout.n_edges + np.arange(len(p))[:, None]
        blocks += [(r, layout.e_cols(p[:, 0]), b), (r, layout.e_cols(p[:, 1]), a)]
    phi = np.concatenate(phi)
    return phi, jacobian(phi.size, layout.size, *blocks)
