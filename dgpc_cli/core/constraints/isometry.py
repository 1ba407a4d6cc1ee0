"""Isometry to a reference net (§5.1): ``w_ij − w⁰_ij = 0``."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def isometry(x, layout, w0):
    """Residuals ``w_ij − w⁰_ij`` for every edge; ``w0`` has shape (|E|,)."""
    _, _, w = layout.split(x)
    rows = np.arange(layout.n_edges)
    return w - w0, jacobian(rows.size, layout.size, (rows, layout.w_cols(rows), 1.0))
