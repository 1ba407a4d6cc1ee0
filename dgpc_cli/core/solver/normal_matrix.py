"""Assembly of the normal matrix ``A = JᵀWJ + ε²I`` into a pattern computed once.

scipy's sparse product drops exact zeros, which changes the pattern between iterations and breaks
the reuse of a symbolic factorization (SPEC §10). Here the pattern of the upper triangle of A is
derived once from the (fixed) pattern of the stacked Jacobian J; every iteration then only
scatters products of Jacobian values into it with one ``bincount``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


class NormalMatrix:
    """Fixed-pattern ``A = JᵀWJ + ε²I`` (upper triangle, CSR) and ``g = JᵀWφ``.

    Parameters
    ----------
    rows, cols : (nnz,) int arrays
        The COO pattern of the stacked Jacobian J (n_rows × size). Duplicates are allowed.
    n_rows, size : int
        Shape of J.
    """

    def __init__(self, rows: np.ndarray, cols: np.ndarray, n_rows: int, size: int):
        self.rows = np.asarray(rows, dtype=np.int64)
        self.cols = np.asarray(cols, dtype=np.int64)
        self.n_rows, self.size = n_rows, size
        order = np.argsort(self.rows, kind="stable")
        r = self.rows[order]
        c = self.cols[order]
        counts = np.bincount(r, minlength=n_rows)
        start = np.concatenate([[0], np.cumsum(counts)[:-1]])
        k = counts[r]                                       # size of each entry's row
        a = np.repeat(np.arange(r.size), k)                 # every ordered pair (a, b) in a row
        b = start[r[a]] + (np.arange(a.size) - np.repeat(np.cumsum(k) - k, k))
        keep = c[a] <= c[b]
        a, b = a[keep], b[keep]
        diag = np.arange(size, dtype=np.int64)
        keys = np.concatenate([c[a] * size + c[b], diag * size + diag])
        unique, slot = np.unique(keys, return_inverse=True)
        self._pa, self._pb = order[a], order[b]             # pair entries in J's own order
        self._pair_row = r[a]
        self._slot = slot[: a.size]
        self._diag_slot = slot[a.size:]
        self.nnz = unique.size
        ai, aj = unique // size, unique % size
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(ai, minlength=size))])
        self.indices = aj
        self.n_pairs = a.size

    def same_pattern(self, rows: np.ndarray, cols: np.ndarray) -> bool:
        return np.array_equal(rows, self.rows) and np.array_equal(cols, self.cols)

    def values(self, jac_values: np.ndarray, row_weights: np.ndarray, eps2: float) -> np.ndarray:
        """Data array of A in the fixed CSR pattern."""
        v = jac_values[self._pa] * jac_values[self._pb] * row_weights[self._pair_row]
        data = np.bincount(self._slot, weights=v, minlength=self.nnz)
        data[self._diag_slot] += eps2
        return data

    def gradient(self, jac_values: np.ndarray, row_weights: np.ndarray,
                 phi: np.ndarray) -> np.ndarray:
        """``JᵀWφ``."""
        return np.bincount(self.cols, weights=jac_values * (row_weights * phi)[self.rows],
                           minlength=self.size)

    def upper(self, data: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.size, self.size))

    def full(self, data: np.ndarray) -> sp.csc_matrix:
        """The whole symmetric matrix (for solvers that do not take a triangle)."""
        U = self.upper(data)
        return (U + sp.triu(U, k=1).T).tocsc()
