"""Index bookkeeping for an m×n net f(u, v) and its variable vector (paper §5.1).

Conventions (SPEC §3, §4)
-------------------------
* Vertex ``(u, v)`` has id ``u * n + v``; u ∈ [0, m) runs along the geodesics (the u-lines),
  v ∈ [0, n) across them.
* u-edges join ``(u, v) → (u + 1, v)``; there are ``(m - 1) * n`` of them, with ids
  ``eu[u, v]``. v-edges join ``(u, v) → (u, v + 1)``; ``m * (n - 1)`` of them, ids ``ev[u, v]``.
  Edge ids are global: u-edges first, then v-edges.
* The variable vector is the lean equivalent of the paper's set (SPEC §4 allows it): vertex
  coordinates f (3|V|), one unit edge vector e_ij per oriented edge (3|E|) and one edge length
  w_ij (|E|); e_ji = −e_ij and w_ji = w_ij are implied. Every constraint stays at most quadratic.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class NetLayout:
    """Grid and variable indices of an ``m × n`` net."""

    m: int
    n: int
    vid: np.ndarray = field(init=False, repr=False)
    eu: np.ndarray = field(init=False, repr=False)
    ev: np.ndarray = field(init=False, repr=False)
    edge_i: np.ndarray = field(init=False, repr=False)
    edge_j: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        m, n = self.m, self.n
        if m < 2 or n < 2:
            raise ValueError(f"a net needs at least 2×2 vertices, got {m}×{n}")
        vid = np.arange(m * n).reshape(m, n)
        n_eu = (m - 1) * n
        eu = np.arange(n_eu).reshape(m - 1, n)
        ev = n_eu + np.arange(m * (n - 1)).reshape(m, n - 1)
        edge_i = np.concatenate([vid[:-1, :].ravel(), vid[:, :-1].ravel()])
        edge_j = np.concatenate([vid[1:, :].ravel(), vid[:, 1:].ravel()])
        for name, value in (("vid", vid), ("eu", eu), ("ev", ev), ("edge_i", edge_i),
                            ("edge_j", edge_j)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    # sizes --------------------------------------------------------------------------------
    @property
    def n_vertices(self) -> int:
        return self.m * self.n

    @property
    def n_edges(self) -> int:
        return self.edge_i.size

    @property
    def size(self) -> int:
        """Number of variables: 3|V| + 3|E| + |E|."""
        return 3 * self.n_vertices + 4 * self.n_edges

    @property
    def paper_size(self) -> int:
        """Number of variables in the paper's layout, 3|V| + 8|E| (8,043 for 21×21)."""
        return 3 * self.n_vertices + 8 * self.n_edges

    # column indices -----------------------------------------------------------------------
    def f_cols(self, vertex_ids) -> np.ndarray:
        """Columns of f_i, shape ``(*vertex_ids.shape, 3)``."""
        return 3 * np.asarray(vertex_ids)[..., None] + np.arange(3)

    def e_cols(self, edge_ids) -> np.ndarray:
        """Columns of e_ij, shape ``(*edge_ids.shape, 3)``."""
        return 3 * self.n_vertices + 3 * np.asarray(edge_ids)[..., None] + np.arange(3)

    def w_cols(self, edge_ids) -> np.ndarray:
        """Columns of w_ij, shape ``edge_ids.shape``."""
        return 3 * self.n_vertices + 3 * self.n_edges + np.asarray(edge_ids)

    # packing ------------------------------------------------------------------------------
    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Views ``f (|V|, 3)``, ``e (|E|, 3)``, ``w (|E|,)`` of the variable vector."""
        nv, ne = self.n_vertices, self.n_edges
        f = x[: 3 * nv].reshape(nv, 3)
        e = x[3 * nv: 3 * nv + 3 * ne].reshape(ne, 3)
        w = x[3 * nv + 3 * ne:]
        return f, e, w

    def edge_vectors(self, f: np.ndarray) -> np.ndarray:
        """f_j − f_i for every edge, shape ``(|E|, 3)``; f is ``(|V|, 3)`` or ``(m, n, 3)``."""
        f = np.asarray(f).reshape(-1, 3)
        return f[self.edge_j] - f[self.edge_i]

    def pack(self, f: np.ndarray) -> np.ndarray:
        """Variable vector with e, w derived from the vertex positions (net constraints hold)."""
        f = np.asarray(f, dtype=float).reshape(-1, 3)
        d = self.edge_vectors(f)
        w = np.linalg.norm(d, axis=1)
        e = d / np.where(w > 0, w, 1.0)[:, None]
        return np.concatenate([f.ravel(), e.ravel(), w])

    def orient_edges(self, x: np.ndarray) -> np.ndarray:
        """x with every negative edge length flipped: ``(w, e) → (−w, −e)``.

        The net constraints ``f_j − f_i − w e = 0``, ``‖f_j − f_i‖² − w² = 0`` cannot tell the two
        apart, but the angle condition (6) can: a flipped e_ij satisfies it while the edge it
        stands for does not (paper §5.1 counts on fairness to prevent this; we restore the sign).
        """
        x = x.copy()
        nv, ne = self.n_vertices, self.n_edges
        w = x[3 * nv + 3 * ne:]
        neg = w < 0
        if neg.any():
            w[neg] = -w[neg]
            e = x[3 * nv: 3 * nv + 3 * ne].reshape(ne, 3)
            e[neg] = -e[neg]
        return x

    def vertices(self, x: np.ndarray) -> np.ndarray:
        """Vertex positions as a grid ``(m, n, 3)``."""
        return x[: 3 * self.n_vertices].reshape(self.m, self.n, 3).copy()

    def edge_lengths(self, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lengths of the u-edges ``(m-1, n)`` and v-edges ``(m, n-1)`` of a grid ``(m, n, 3)``."""
        f = np.asarray(f).reshape(self.m, self.n, 3)
        return (np.linalg.norm(f[1:] - f[:-1], axis=-1),
                np.linalg.norm(f[:, 1:] - f[:, :-1], axis=-1))
