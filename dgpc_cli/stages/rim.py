"""The rim of a net kept where it starts during a fit (issue: "``fit`` keeps the area the initial
net covered"): approximation lets vertices slide along the reference, so under fairness (second
differences shorten a curved net) a rim draws in, whatever made the net. Rim vertices on the
reference's boundary stay on it (``boundary`` term, ``stages.optimize.boundary_vertices``); the
rest of the rim of a net that is already nearly gpc (angle defect (6) within
:data:`~dgpc_cli.metrics.degenerate.GPC_LIMIT`, as every net ``init`` makes on a mesh) stays on
the input net's own rim, a guide curve the same term holds them to (free to slide along it). A
net far from gpc (a twisted start, paper Fig. 11) must move its rim to become one: only its
vertices on the reference's boundary are held."""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.degenerate import GPC_LIMIT
from dgpc_cli.metrics.residuals import gpc_angle_defect_max
from dgpc_cli.stages.optimize import boundary_vertices

#: Pieces per rim edge of the guide curve, their ends on the reference.
GUIDE_PIECES = 8


def rim_loop(m: int, n: int) -> np.ndarray:
    """Vertex ids of the rim of an ``m × n`` grid as one closed loop ``(2(m + n) − 4,)``: row 0,
    then column n − 1, row m − 1 backwards, column 0 backwards."""
    vid = np.arange(m * n).reshape(m, n)
    return np.concatenate([vid[0, :-1], vid[:-1, -1], vid[-1, :0:-1], vid[:0:-1, 0]])


def held_rim(f: np.ndarray, surface, guide: bool = True):
    """``(ids, surface, guides)``: every rim vertex of the net ``f (m, n, 3)``, the reference
    ``surface`` with the guide segments added to its boundary (``with_guides``), and those
    segments ``(g, 2, 3)`` — the rim edges of ``f`` not lying along the reference's boundary
    (both ends on it) — or None when the whole rim lies on the boundary. For a net far from
    gpc, or without ``guide`` (a net that runs past its reference, ``init --extend``: its rim
    lies beyond the reference, its overhang covers it): the rim vertices on the reference's
    boundary, the surface as it is, and None."""
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    loop = rim_loop(m, n)
    held = boundary_vertices(f, surface)
    defect = gpc_angle_defect_max(f)
    if not guide or defect is None or defect > GPC_LIMIT:
        return held, surface, None
    on = np.isin(loop, held)
    free = ~(on & np.roll(on, -1))
    if not free.any():
        return np.sort(loop), surface, None
    P = f.reshape(-1, 3)
    a, b = P[loop[free]], P[np.roll(loop, -1)[free]]
    # each rim edge as GUIDE_PIECES segments between points on the reference: a chord of a
    # curved surface would hold the rim off it (against the approximation term)
    t = np.linspace(0.0, 1.0, GUIDE_PIECES + 1)
    pts = a[:, None] + t[None, :, None] * (b - a)[:, None]                 # (g, k + 1, 3)
    inner, _ = surface.closest(pts[:, 1:-1].reshape(-1, 3))
    pts[:, 1:-1] = inner.reshape(len(a), GUIDE_PIECES - 1, 3)
    a, b = pts[:, :-1].reshape(-1, 3), pts[:, 1:].reshape(-1, 3)
    return np.sort(loop), surface.with_guides(a, b), np.stack([a, b], axis=1)
