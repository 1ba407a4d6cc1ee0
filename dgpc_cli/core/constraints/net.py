"""Net constraints: tie the edge variables e_ij, w_ij to the vertices (paper §5.1)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def net(x, layout):
    """Residuals of ``f_j − f_i − w_ij e_ij = 0`` and ``‖f_j − f_i‖² − w_ij² = 0`` (§5.1).

    Rows: 3|E| vector equations (edge-major, xyz), then |E| length equations.
    Together they make every e_ij a unit vector and w_ij the edge length.
    """
    f, e, w = layout.split(x)
    E = layout.n_edges
    i, j = layout.edge_i, layout.edge_j
    d = f[j] - f[i]                                    # (E, 3)
    phi_vec = d - w[:, None] * e                       # (E, 3)
    phi_len = np.einsum("ij,ij->i", d, d) - w * w      # (E,)

    rows_vec = np.arange(3 * E).reshape(E, 3)
    rows_len = 3 * E + np.arange(E)
    fi, fj = layout.f_cols(i), layout.f_cols(j)        # (E, 3)
    ec, wc = layout.e_cols(np.arange(E)), layout.w_cols(np.arange(E))
    J = jacobian(
        4 * E, layout.size,
        (rows_vec, fj, 1.0),
        (rows_vec, fi, -1.0),
        (rows_vec, ec, -w[:, None]),
        (rows_vec, wc[:, None], -e),
        (rows_len[:, None], fj, 2.0 * d),
        (rows_len[:, None], fi, -2.0 * d),
        (rows_len, wc, -2.0 * w),
    )
    return np.concatenate([phi_vec.ravel(), phi_len]), J
