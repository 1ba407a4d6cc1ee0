"""The common shape of a constraint term: residuals φ(x) and a sparse Jacobian ∂φ/∂x.

Every term is a pure function ``term(x, layout, ...) -> (phi, J)`` with ``phi`` of shape (k,) and
``J`` a ``scipy.sparse.coo_array`` of shape (k, layout.size). The triplet order of ``J`` depends on
the layout only, never on the values of x, and explicit zeros are kept: the solver relies on it to
assemble the normal matrix into a pattern computed once (SPEC §10).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def jacobian(n_rows: int, n_cols: int, *blocks: tuple) -> sp.coo_array:
    """Build a COO Jacobian from blocks ``(rows, cols, vals)`` that broadcast together.

    Each block's arrays are broadcast to a common shape and flattened; blocks are concatenated
    in the order given, so the pattern is fixed by the call site.
    """
    rows, cols, vals = [], [], []
    for r, c, v in blocks:
        r, c, v = np.broadcast_arrays(np.asarray(r), np.asarray(c), np.asarray(v, dtype=float))
        rows.append(r.ravel())
        cols.append(c.ravel())
        vals.append(v.ravel())
    return sp.coo_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_rows, n_cols),
    )


def linear_difference(x, layout, plus, minus, coefficients=(1.0, -1.0), middle=None):
    """Residuals ``c0·x[plus] + c1·x[minus] (+ c2·x[middle])`` of scalar variables.

    ``plus``, ``minus`` and ``middle`` are arrays of variable columns of one shape (k,).
    Used by the linear terms on edge lengths (arclength, strip widths, developable).
    """
    cols = [np.asarray(plus), np.asarray(minus)] + ([np.asarray(middle)] if middle is not None
                                                    else [])
    k = cols[0].size
    phi = sum(c * x[col] for c, col in zip(coefficients, cols, strict=True))
    rows = np.arange(k)
    J = jacobian(k, layout.size, *[(rows, col, c) for c, col in
                                   zip(coefficients, cols, strict=True)])
    return phi, J
