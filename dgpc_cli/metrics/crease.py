"""Creases across the geodesics: where a drag bends a row of the net sharply (the third
difference of the vertices along a row, in mean edge lengths)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.problem import mean_edge_length

#: A row whose third difference exceeds this many mean edge lengths is creased (a smooth push
#: of a 21×21 sphere-zone row stays near 0.02; a push held too stiffly at its corners bends
#: the row three columns from them at 0.2).
CREASE_LIMIT = 0.05


def crease(f) -> np.ndarray:
    """‖δ_vvv f‖ (f(v+3) − 3 f(v+2) + 3 f(v+1) − f(v)) divided by the mean edge length, shape
    ``(m, n − 3)`` (empty for n < 4): the bend of every run of four vertices across the
    geodesics. A circle sampled at step h has O(h³/ρ²); a kink of angle α, about α."""
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    if n < 4:
        return np.zeros((m, 0))
    d3 = f[:, 3:] - 3.0 * f[:, 2:-1] + 3.0 * f[:, 1:-2] - f[:, :-3]
    return np.linalg.norm(d3, axis=-1) / mean_edge_length(f)


def creased_vertices(f, limit: float = CREASE_LIMIT) -> np.ndarray:
    """Boolean ``(m, n)``: the two middle vertices of every run of four whose crease exceeds
    ``limit``."""
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    out = np.zeros((m, n), dtype=bool)
    bad = crease(f) > limit
    out[:, 1:-2] |= bad
    out[:, 2:-1] |= bad
    return out
