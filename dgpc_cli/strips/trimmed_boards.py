"""Boards of stock length cut from strips trimmed to the reference's outline
(``planarize-strips --trim`` then ``unfold --stock-length``; SPEC §6 unfold).

A trimmed part is a polygon in the strip's ``(t, s)`` (:mod:`dgpc_cli.strips.trim`): ``t``
along the strip (row u at t = u), ``s`` across it. It is cut at rulings ``t = u`` that cross it
once (one segment: a joint then splits it in two), as a whole strip is
(:func:`dgpc_cli.strips.boards.split_run`): each board as long as the stock allows, joints
staggered from those of the strip beside it. The end cuts along the outline stay on the end
boards. A board needs stock as long as its developed outline's extent along the mid-curve chord
of the rows it spans, which is how ``unfold`` lays it out (the development of those rows; of
its own rows, fractional at a joint inside a quad, where no outline cuts it). Where no ruling
lies within the stock the joint is cut inside the quad, at ``t = u + f``
(:func:`dgpc_cli.strips.boards.cut_inside`).
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import LineString, Polygon, box

from .boards import board_extent as whole_extent
from .boards import split_run
from .develop import Development
from .trim import strip_points


def cuts_once(part: Polygon, u: float) -> bool:
    """Whether the ruling ``t = u`` (or the joint there, inside a quad) crosses the part (in
    ``(t, s)``) in one segment."""
    cut = part.intersection(LineString([(u, -1.0), (u, 2.0)]))
    return cut.geom_type == "LineString" and cut.length > 0


def board_ring(part: Polygon, a: float, b: float) -> np.ndarray | None:
    """The board of the part between ``t = a`` and ``t = b``: its ring ``(k, 2)`` in
    ``(t, s)``, counter-clockwise, not closed; None when the part falls apart there."""
    piece = part.intersection(box(a, -1.0, b, 2.0))
    if piece.geom_type != "Polygon" or piece.is_empty:
        return None
    ring = np.asarray(piece.exterior.coords)[:-1]
    return ring if Polygon(ring).exterior.is_ccw else ring[::-1]


def whole(ring: np.ndarray, a: float, b: float) -> bool:
    """Whether the board ring ``(k, 2)`` (in ``(t, s)``) from ``t = a`` to ``b`` is the whole
    strip there (no end cut along the outline)."""
    return abs(Polygon(ring).area - (b - a)) <= 1e-9 * (b - a)


def board_extent(dev: Development, part: Polygon, a: float, b: float) -> float:
    """Stock length the board ``a … b`` of the trimmed part needs (see the module); inf when
    the part falls apart there."""
    ring = board_ring(part, a, b)
    if ring is None:
        return np.inf
    if whole(ring, a, b):
        return whole_extent(dev, a, b)
    mid = 0.5 * (dev.A + dev.B)
    chord = mid[int(np.ceil(b))] - mid[int(np.floor(a))]
    x = strip_points(dev.A, dev.B, ring) @ (chord / np.linalg.norm(chord))
    return float(x.max() - x.min())


def split_trimmed(dev: Development, ring: np.ndarray, stock: float, forbidden: np.ndarray,
                  stagger: float, positions: np.ndarray, name: str, relax: bool = False
                  ) -> list[float]:
    """Joint rows of the trimmed part ``ring`` (in ``(t, s)``) of the developed strip ``dev``
    (:func:`~dgpc_cli.strips.boards.split_run`)."""
    part = Polygon(ring)
    t0, t1 = float(ring[:, 0].min()), float(ring[:, 0].max())
    rows = [u for u in range(int(np.floor(t0)) + 1, int(np.ceil(t1))) if cuts_once(part, u)]
    return split_run(lambda a, b: board_extent(dev, part, a, b), t0, t1, rows, stock,
                     forbidden, stagger, positions, name, relax,
                     cuttable=lambda t: cuts_once(part, t))
