"""Degenerate nets: folded or collapsed quads that no fabrication stage may take on (SPEC §4,
§7: "a pleated, folded or collapsed net is never converged").

A net ``f (m, n, 3)`` is *degenerate* where

* an edge is shorter than :data:`EDGE_RATIO` of the mean edge (collapsed rows or columns),
* a quad's normal flips against a neighbour's (a fold: the normals of two quads sharing an
  edge turn by more than 120°, :data:`FLIP_COS`; or the two triangles of one quad, cut along
  either diagonal, do: a quad folded over itself), or its vector area vanishes, or
* the angle defect of geodesic parallel coordinates (Prop. 2.7 (ii), equation (6)) exceeds
  :data:`GPC_LIMIT` radians: far from a discrete gpc net, typically where the grid turns over.

:func:`degeneracies` measures all three at once, pure and vectorized, and says where.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.metrics.frames import edge_lengths
from dgpc_cli.metrics.residuals import gpc_angle_defect

__all__ = ["EDGE_RATIO", "FLIP_COS", "GPC_LIMIT", "Degeneracy", "degeneracies",
           "index_ranges"]

#: An edge shorter than this fraction of the mean edge length is collapsed.
EDGE_RATIO = 1e-3
#: A gpc angle defect (radians) above this marks a degenerate vertex.
GPC_LIMIT = 0.1
#: Neighbouring quad normals (or a quad's two triangles) whose cosine is below this are
#: flipped: turned by more than 120°, beyond what a coarse but sound net bends (a ring of five
#: quads round a catenoid's waist turns by 85°), short of a fold's 180°.
FLIP_COS = -0.5


def index_ranges(indices) -> str:
    """``[0, 1, 2, 5, 7, 8]`` → ``"0-2, 5, 7-8"`` (sorted, duplicates dropped)."""
    idx = np.unique(np.asarray(indices, dtype=np.int64))
    if idx.size == 0:
        return "none"
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    return ", ".join(str(a) if a == b else f"{a}-{b}"
                     for a, b in zip(starts.tolist(), ends.tolist(), strict=True))


@dataclass(frozen=True)
class Degeneracy:
    """What is degenerate in a net and where (grid indices, u = row, v = column).

    ``short_u (k, 2)``: u-edges ``f(u, v) → f(u+1, v)`` as ``(u, v)``; ``short_v (k, 2)``:
    v-edges ``f(u, v) → f(u, v+1)``; ``flipped (k, 2)``: quads ``(u, v)`` (corners
    ``f(u..u+1, v..v+1)``) folded against a neighbour or over themselves, or of zero area;
    ``gpc (k, 2)``: vertices whose gpc angle defect exceeds the limit. ``bad_quads (m−1, n−1)``
    marks every quad that touches one of them. ``edge_ratio_min`` is the shortest edge over the
    mean edge, ``gpc_defect_max`` the largest defect (None without interior u-lines);
    ``edge_ratio`` and ``gpc_limit`` the thresholds used.
    """

    shape: tuple[int, int]
    short_u: np.ndarray
    short_v: np.ndarray
    flipped: np.ndarray
    gpc: np.ndarray
    bad_quads: np.ndarray
    edge_ratio_min: float
    gpc_defect_max: float | None
    edge_ratio: float = EDGE_RATIO
    gpc_limit: float | None = GPC_LIMIT

    @property
    def any(self) -> bool:
        """Whether the net is degenerate."""
        return bool(self.bad_quads.any())

    def __bool__(self) -> bool:
        return self.any

    @property
    def rows(self) -> np.ndarray:
        """Rows u of the vertices involved, sorted."""
        return np.unique(np.concatenate([self.short_u[:, 0], self.short_u[:, 0] + 1,
                                         self.short_v[:, 0], self.flipped[:, 0],
                                         self.flipped[:, 0] + 1, self.gpc[:, 0]]))

    @property
    def cols(self) -> np.ndarray:
        """Columns v of the vertices involved, sorted."""
        return np.unique(np.concatenate([self.short_u[:, 1], self.short_v[:, 1],
                                         self.short_v[:, 1] + 1, self.flipped[:, 1],
                                         self.flipped[:, 1] + 1, self.gpc[:, 1]]))

    def message(self) -> str:
        """One line: what is wrong, where (rows and columns), and how badly; ``""`` if
        nothing is."""
        parts = []
        short = len(self.short_u) + len(self.short_v)
        if short:
            rows = np.concatenate([self.short_u[:, 0], self.short_u[:, 0] + 1,
                                   self.short_v[:, 0]])
            cols = np.concatenate([self.short_u[:, 1], self.short_v[:, 1],
                                   self.short_v[:, 1] + 1])
            parts.append(f"{short} edge{'s' * (short > 1)} shorter than {self.edge_ratio:g} "
                         f"of the mean (shortest {self.edge_ratio_min:.3g}; rows "
                         f"{index_ranges(rows)}, columns {index_ranges(cols)})")
        if len(self.flipped):
            k = len(self.flipped)
            parts.append(f"{k} quad{'s' * (k > 1)} folded or flipped (rows "
                         f"{index_ranges(np.r_[self.flipped[:, 0], self.flipped[:, 0] + 1])}, "
                         f"columns "
                         f"{index_ranges(np.r_[self.flipped[:, 1], self.flipped[:, 1] + 1])})")
        if len(self.gpc):
            parts.append(f"gpc angle defect {self.gpc_defect_max:.3g} rad > {self.gpc_limit:g} "
                         f"at {len(self.gpc)} vertices (rows {index_ranges(self.gpc[:, 0])}, "
                         f"columns {index_ranges(self.gpc[:, 1])})")
        return "; ".join(parts)

    def record(self) -> dict:
        """JSON-able summary for an artifact's status or metrics."""
        return {"degenerate": self.any, "message": self.message(),
                "short_edges": int(len(self.short_u) + len(self.short_v)),
                "flipped_quads": int(len(self.flipped)), "gpc_vertices": int(len(self.gpc)),
                "edge_ratio_min": self.edge_ratio_min, "gpc_defect_max": self.gpc_defect_max,
                "rows": self.rows.tolist(), "cols": self.cols.tolist()}


def _unit_or_nan(x: np.ndarray, floor: float) -> np.ndarray:
    norm = np.linalg.norm(x, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > floor, x / np.where(norm > 0, norm, 1.0), np.nan)


def degeneracies(f, *, edge_ratio: float = EDGE_RATIO,
                 gpc_limit: float | None = GPC_LIMIT) -> Degeneracy:
    """Where the net ``f (m, n, 3)`` is degenerate (see the module): collapsed edges, folded or
    flipped quads, and vertices whose gpc angle defect (6) exceeds ``gpc_limit`` (None: not
    checked, for nets that are not meant to be gpc, e.g. the planar-quad strips of §6.2.4).

    Quad normals are the cross products of the diagonals (the vector area, valid for
    non-convex quads); two quads sharing an edge fold when their unit normals' dot product is
    below :data:`FLIP_COS`, a quad folds over itself when the triangles (u,v),(u+1,v),(u+1,v+1)
    and (u,v),(u+1,v+1),(u,v+1) do (or those of the other diagonal), and a quad with a vector
    area below ``(edge_ratio · mean edge)²`` has no normal at all.
    """
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    lu, lv = edge_lengths(f)
    mean = float((lu.sum() + lv.sum()) / (lu.size + lv.size))
    floor = edge_ratio * mean
    short_u, short_v = lu < floor, lv < floor
    a, b, c, d = f[:-1, :-1], f[1:, :-1], f[1:, 1:], f[:-1, 1:]
    area_floor = floor * floor
    nq = _unit_or_nan(np.cross(c - a, d - b), area_floor)             # (m−1, n−1, 3)
    t1, t2 = np.cross(b - a, c - a), np.cross(c - a, d - a)           # diagonal a–c
    t3, t4 = np.cross(c - b, d - b), np.cross(d - b, a - b)           # diagonal b–d

    def cos(x, y):
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.einsum("...i,...i->...", x, y) / (np.linalg.norm(x, axis=-1)
                                                         * np.linalg.norm(y, axis=-1))

    self_fold = (cos(t1, t2) < FLIP_COS) | (cos(t3, t4) < FLIP_COS)
    flip = self_fold | ~np.isfinite(nq).all(axis=-1)
    across_u = np.einsum("...i,...i->...", nq[1:], nq[:-1]) < FLIP_COS       # (m−2, n−1)
    across_v = np.einsum("...i,...i->...", nq[:, 1:], nq[:, :-1]) < FLIP_COS  # (m−1, n−2)
    flip[1:] |= across_u
    flip[:-1] |= across_u
    flip[:, 1:] |= across_v
    flip[:, :-1] |= across_v
    bad = flip.copy()
    bad |= short_u[:, :-1] | short_u[:, 1:] | short_v[:-1] | short_v[1:]
    gpc_max = None
    gpc_bad = np.zeros((m, n), dtype=bool)
    if gpc_limit is not None and n > 2:
        defect = gpc_angle_defect(f)
        finite = defect[np.isfinite(defect)]
        gpc_max = float(finite.max()) if finite.size else None
        with np.errstate(invalid="ignore"):
            gpc_bad = np.nan_to_num(defect, nan=0.0) > gpc_limit
        bad |= gpc_bad[:-1, :-1] | gpc_bad[1:, :-1] | gpc_bad[1:, 1:] | gpc_bad[:-1, 1:]
    lengths = np.concatenate([lu.ravel(), lv.ravel()])
    return Degeneracy(
        shape=(m, n), short_u=np.argwhere(short_u), short_v=np.argwhere(short_v),
        flipped=np.argwhere(flip), gpc=np.argwhere(gpc_bad), bad_quads=bad,
        edge_ratio_min=float(lengths.min() / mean) if mean > 0 else 0.0,
        gpc_defect_max=gpc_max, edge_ratio=edge_ratio,
        gpc_limit=gpc_limit)
