"""Strips with more rows than their net (``planarize-strips --refine K``; issue "Strips that
build the design").

A strip's boundary vertices sit on the net's geodesics; with one ruling per net row, the
neighbours' copies of a shared geodesic put their vertices at different places along it and
each copy's chords cut under the curve by their sag (0.5–0.7 % of the strip width on the
pipelines' 21-row walls): a seam step no fit removes. With K rulings per net row the sag falls
about K²-fold. The refined net has K − 1 new rows between every two net rows: along every
geodesic (a column of the net) a cubic spline through its vertices by arc length (not-a-knot),
sampled at equal arc lengths between neighbouring vertices; across the strip the refined net's
bilinear quads. Row ``K u`` of the refined net is the net's row ``u`` exactly, so refined row
``t`` is net row ``t / K`` (:func:`net_rows`).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

__all__ = ["net_rows", "refine_rows"]


def refine_rows(f: np.ndarray, K: int) -> np.ndarray:
    """The net ``f (m, n, 3)`` with ``K − 1`` rows between every two of its rows: shape
    ``((m − 1) K + 1, n, 3)``, every column a cubic spline by arc length through the column's
    vertices (see the module), sampled at ``K`` equal steps of arc length of every chord.
    ``K = 1`` gives ``f``."""
    f = np.asarray(f, dtype=float)
    if K < 1:
        raise ValueError(f"refinement {K} is not an integer ≥ 1")
    if K == 1:
        return f
    m, n, _ = f.shape
    chords = np.linalg.norm(np.diff(f, axis=0), axis=-1)                   # (m-1, n)
    s = np.concatenate([np.zeros((1, n)), np.cumsum(chords, axis=0)])       # (m, n)
    steps = np.arange(K) / K
    t = np.concatenate([(s[:-1, None] + steps[None, :, None] * chords[:, None]).reshape(-1, n),
                        s[-1:]])                                            # ((m-1) K + 1, n)
    out = np.empty((t.shape[0], n, 3))
    for v in range(n):                                   # one spline per geodesic (column)
        out[:, v] = CubicSpline(s[:, v], f[:, v], axis=0, bc_type="not-a-knot")(t[:, v])
    out[::K] = f                                         # the net's rows exactly
    return out


def net_rows(t, K: int):
    """The net rows of the refined rows ``t`` (whole or fractional): ``t / K``."""
    return np.asarray(t, dtype=float) / K
