"""Panels, their mold patches, flat panels and mold pieces (paper §6.2.3, Fig. 16, 17).

A panel is a K×K block of net quads (the last blocks of a row or column may be smaller); block
(i, j) covers the quads ``[iK, (i+1)K) × [jK, (j+1)K)`` and the vertex rows ``iK … (i+1)K``.
Its mold patch is the same block of the mold grid (:func:`dgpc_cli.mold.profile.mold_grid`):
quad (u, v) of the net goes to quad (u, v) of the discrete surface of revolution.

* Isometry error of a panel: the largest relative difference ``|L_net − L_mold| / L_mold`` over
  the edges and both diagonals of its quads (four points and their six distances fix a quad up
  to a rigid motion, so 0 means every quad is congruent to its mold quad).
* Flat panel: the discrete Gaussian curvature of (1), made dimensionless with the local meridian
  step, ``κ = K l² = −δ_uu w / w`` (the paper's form in arc-length parametrization; see
  :func:`dgpc_cli.metrics.curvature.gaussian_curvature`), is at most ``flat_tol`` in absolute
  value on every vertex of the panel: the panel is a developable piece of sheet, no mold.
* Mold pieces: the sector of the surface of revolution, just wide enough for the widest panel,
  is cut along the meridian at panel-row boundaries into pieces no longer than a maximum length;
  rows whose panels are all flat get no piece.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.curvature import gaussian_curvature
from dgpc_cli.metrics.frames import edge_lengths


def block_starts(count: int, size: int) -> np.ndarray:
    """Start indices of the blocks of ``size`` over ``count`` quads: ``0, K, 2K, …``."""
    return np.arange(0, count, size)


def block_max(a: np.ndarray, size: int) -> np.ndarray:
    """Max of a quad field ``a (m−1, n−1)`` over K×K blocks, shape ``(⌈(m−1)/K⌉, ⌈(n−1)/K⌉)``."""
    rows = np.maximum.reduceat(a, block_starts(a.shape[0], size), axis=0)
    return np.maximum.reduceat(rows, block_starts(a.shape[1], size), axis=1)


def _relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):      # a collapsed edge: b = 0
        return np.abs(a - b) / b


def quad_isometry_error(f: np.ndarray, mold: np.ndarray) -> np.ndarray:
    """Per quad, the largest relative difference of its 4 edges and 2 diagonals between the net
    ``f (m, n, 3)`` and the mold patch ``mold (m, n, 3)``, shape ``(m−1, n−1)``."""
    lu, lv = edge_lengths(f)
    mu, mv = edge_lengths(mold)
    eu = _relative(lu, mu)                                  # (m-1, n)
    ev = _relative(lv, mv)                                  # (m, n-1)
    d1 = _relative(np.linalg.norm(f[1:, 1:] - f[:-1, :-1], axis=-1),
                   np.linalg.norm(mold[1:, 1:] - mold[:-1, :-1], axis=-1))
    d2 = _relative(np.linalg.norm(f[1:, :-1] - f[:-1, 1:], axis=-1),
                   np.linalg.norm(mold[1:, :-1] - mold[:-1, 1:], axis=-1))
    return np.max(np.stack([eu[:, :-1], eu[:, 1:], ev[:-1], ev[1:], d1, d2]), axis=0)


def dimensionless_curvature(f: np.ndarray) -> np.ndarray:
    """κ = K·l² per vertex row and strip, ``(m, n−1)``: K from the Jacobi equation (1)
    (:func:`gaussian_curvature`), l the mean meridian step of the strip around the row, so that
    κ = −δ_uu w / w for equal u-edges. NaN on the rows 0 and m−1."""
    K = gaussian_curvature(f)
    lu, _ = edge_lengths(f)
    lstrip = 0.5 * (lu[:, :-1] + lu[:, 1:])                 # (m-1, n-1)
    kappa = np.full(K.shape, np.nan)
    kappa[1:-1] = K[1:-1] * (0.5 * (lstrip[1:] + lstrip[:-1])) ** 2
    return kappa


def quad_curvature(f: np.ndarray) -> np.ndarray:
    """Per quad the largest |κ| at its four vertices (rows u and u+1 of its strip),
    ``(m−1, n−1)``; ``-inf`` where neither row has a value (nets of two rows)."""
    k = np.abs(dimensionless_curvature(f))
    q = np.fmax(k[:-1], k[1:])
    return np.where(np.isnan(q), -np.inf, q)


def panel_id(i: int, j: int, width: int, prefix: str = "") -> str:
    """Stable panel id ``[prefix]P-u03-v07`` of block (i, j) (zero-padded to ``width``)."""
    return f"{prefix}P-u{i:0{width}d}-v{j:0{width}d}"


@dataclass(frozen=True)
class Piece:
    """A mold piece: the sector between the vertex rows ``start`` and ``stop`` (inclusive)."""

    id: str
    start: int
    stop: int
    length: float


def cut_pieces(block_rows: np.ndarray, needs_mold: np.ndarray, l: np.ndarray,  # noqa: E741
               max_length: float | None) -> tuple[list[Piece], np.ndarray]:
    """Cut the sector into pieces at panel-row boundaries.

    ``block_rows (B, 2)`` are the vertex-row ranges ``[start, stop]`` of the panel rows,
    ``needs_mold (B,)`` whether a row of panels holds a curved panel, ``l (m−1,)`` the meridian
    segments. Consecutive panel rows that need a mold are packed greedily into pieces whose
    meridian length is at most ``max_length`` (no limit for None). Returns the pieces and, per
    panel row, the index of its piece (−1: no mold). DgpcError on ``--mold-max-length`` when a
    single panel row is longer than the limit.
    """
    lengths = np.add.reduceat(l, block_rows[:, 0])          # meridian length per panel row
    piece_of = np.full(len(block_rows), -1)
    limit = np.inf if max_length is None else float(max_length)
    too_long = needs_mold & (lengths > limit * (1 + 1e-12))
    if too_long.any():
        b = int(np.argmax(too_long))
        raise DgpcError(f"panel row {b} (vertex rows {block_rows[b, 0]}-{block_rows[b, 1]}) is "
                        f"{lengths[b]:.6g} long along the meridian, more than the limit "
                        f"{limit:g}; use smaller panels (--panel-size) or a longer limit",
                        source="--mold-max-length")
    bounds: list[list[int]] = []                            # [first block, last block, length]
    for b in np.flatnonzero(needs_mold).tolist():          # a loop over panel rows, not vertices
        last = bounds[-1] if bounds else None
        if last is not None and last[1] == b - 1 and last[2] + lengths[b] <= limit * (1 + 1e-12):
            last[1], last[2] = b, last[2] + lengths[b]
        else:
            bounds.append([b, b, float(lengths[b])])
    width = max(2, len(str(len(bounds))))
    pieces = []
    for k, (b0, b1, length) in enumerate(bounds):
        pieces.append(Piece(f"M{k + 1:0{width}d}", int(block_rows[b0, 0]),
                            int(block_rows[b1, 1]), float(length)))
        piece_of[b0:b1 + 1] = k
    return pieces, piece_of
