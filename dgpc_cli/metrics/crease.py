"""Crease across the geodesics (issue: drags that feel right): how sharply a row bends.

A smooth row of a net is a sampled smooth curve: its third differences along the row are
O(h³/ρ²), small and slowly varying (0.016 mean edges on the 21×21 meridian net of a sphere zone
spanning 120°). Where a drag bends a row sharply — at a held vertex, say — the second difference
(the row's turning) jumps, and the third difference there stands out. A coarse net of a curved
surface has large third differences of its own (0.10 on a 9×7 sphere net spanning 90°), so a
drag is judged by how much it adds to its start net's (:func:`creased_vertices`). Pure and
vectorized.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import as_grid, edge_lengths

__all__ = ["CREASE_LIMIT", "crease", "creased_vertices"]

#: A run of four vertices whose third difference grew by more than this many mean edge lengths
#: over the start net's is creased (a smooth push of a 21×21 sphere-zone row stays near 0.02; a
#: push held too stiffly at its corners bends the row three columns from them at 0.2).
CREASE_LIMIT = 0.05


def crease(f) -> np.ndarray:
    """Third differences across the geodesics along each row, shape ``(m, n − 3)`` (empty for
    n < 4), in units of the net's mean edge length:
    ``‖f(u, v+3) − 3 f(u, v+2) + 3 f(u, v+1) − f(u, v)‖ / mean edge``, between the vertices
    v … v+3 of row u.
    """
    f = as_grid(f)
    m, n, _ = f.shape
    if n < 4:
        return np.zeros((m, 0))
    d3 = f[:, 3:] - 3.0 * f[:, 2:-1] + 3.0 * f[:, 1:-2] - f[:, :-3]
    lu, lv = edge_lengths(f)
    mean = (lu.sum() + lv.sum()) / (lu.size + lv.size)
    return np.linalg.norm(d3, axis=-1) / mean


def creased_vertices(f, limit: float = CREASE_LIMIT, start=None) -> np.ndarray:
    """Boolean ``(m, n)``: the two middle vertices of every run of four whose :func:`crease`
    exceeds ``limit`` — beyond the crease of the ``start`` net (same shape) when one is given,
    so that a coarse net's own curvature is not taken for a crease."""
    f = as_grid(f)
    m, n, _ = f.shape
    out = np.zeros((m, n), dtype=bool)
    amount = crease(f)
    if start is not None:
        amount = amount - crease(start)
    bad = amount > limit
    out[:, 1:-2] |= bad
    out[:, 2:-1] |= bad
    return out
