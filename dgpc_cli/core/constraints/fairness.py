"""Fairness (§5.1): vanishing second differences ``f_l − 2 f_i + f_j = 0`` along u and v."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def fairness(x, layout):
    """Second differences of the vertices along the u-lines, then along the v-lines (xyz rows)."""
    f, _, _ = layout.split(x)
    vid = layout.vid
    triples = [(vid[:-2], vid[1:-1], vid[2:]), (vid[:, :-2], vid[:, 1:-1], vid[:, 2:])]
    lo = np.concatenate([t[0].ravel() for t in triples])
    mid = np.concatenate([t[1].ravel() for t in triples])
    hi = np.concatenate([t[2].ravel() for t in triples])
    phi = (f[lo] - 2.0 * f[mid] + f[hi]).ravel()
    rows = np.arange(phi.size).reshape(-1, 3)
    J = jacobian(phi.size, layout.size,
                 (rows, layout.f_cols(lo), 1.0),
                 (rows, layout.f_cols(mid), -2.0),
                 (rows, layout.f_cols(hi), 1.0))
    return phi, J
