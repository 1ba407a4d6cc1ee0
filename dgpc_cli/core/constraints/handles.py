"""Handle constraints (§5.1): prescribed vertex positions ``f_i − p_i = 0``."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def handles(x, layout, vertex_ids, targets):
    """Residuals ``f_i − p_i`` (3 per handle); ``vertex_ids (l,)``, ``targets (l, 3)``."""
    f, _, _ = layout.split(x)
    vertex_ids = np.asarray(vertex_ids, dtype=int)
    phi = (f[vertex_ids] - targets).ravel()
    rows = np.arange(phi.size)
    return phi, jacobian(phi.size, layout.size, (rows, layout.f_cols(vertex_ids).ravel(), 1.0))
