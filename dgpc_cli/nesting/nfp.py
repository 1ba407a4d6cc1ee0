"""No-fit polygons by the reduced convolution of two outlines, cached by part shape.

The no-fit polygon of part b around part a (both at the origin, a rotated by α, b by β) is the
Minkowski sum ``a_α ⊕ D ⊕ (−b_β)``, ``D`` a 32-gon containing the disk of the clearance: the
translations of b that bring it closer than the clearance to a. For two simple polygons P, Q
(counter-clockwise) the boundary of P ⊕ Q lies on the *reduced convolution* (Behar & Lien,
"Fast and robust 2D Minkowski sum using reduced convolution", 2011): the segments ``e + q`` of
every edge e of one polygon translated by every convex vertex q of the other whose normal cone
holds e's direction. Every such segment lies inside P ⊕ Q, so the faces its noded arrangement
encloses fill P ⊕ Q up to its holes: the polygon returned is P ⊕ Q with any hole filled (a
part is never placed inside a pocket of another; conservative). A handful of vectorized
segments per edge replace the union of every pairwise sum of convex pieces (hundreds of hulls
for two developed strips); where the result fails the Brunn–Minkowski area bound (a degenerate
arrangement) the exact union of convex piece sums is used instead.

Cache: ``NFP(a_α, b_β) = R(α) · NFP(a_0, b_(β−α))``, so one polygon per shape pair and relative
rotation serves every sheet, both fill directions and every congruent copy (the parts'
shapes, :func:`~dgpc_cli.nesting.geometry.prepare_parts`).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon

from .geometry import CLEARANCE_MM, disk, minkowski_nfp, rotation_matrix

#: Relative tolerance (sine of an angle) of the normal-cone test: directions this close to a
#: cone's side count as inside (an extra segment inside P ⊕ Q is harmless, a missing one is not).
CONE_TOL = 1e-6


def _norm(deg: float) -> float:
    return float(np.round(deg % 360.0, 9) % 360.0)


def _ccw(points: np.ndarray) -> np.ndarray:
    x, y = points[:, 0], points[:, 1]
    area2 = float((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())
    return points if area2 > 0 else points[::-1]


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.hypot(v[..., :1], v[..., 1:]), 1e-300)


def _sin(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a, b = _unit(a), _unit(b)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _edge_vertex(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Segments ``(k, 2, 2)``: edges of P translated by the convex vertices of Q whose normal
    cone (between Q's incoming and outgoing edge directions) holds the edge's direction."""
    dP = np.concatenate([P[1:], P[:1]]) - P
    d_out = np.concatenate([Q[1:], Q[:1]]) - Q
    d_in = np.concatenate([d_out[-1:], d_out[:-1]])
    convex = _sin(d_in, d_out) >= -CONE_TOL
    inside = ((_sin(d_in[None, :], dP[:, None]) >= -CONE_TOL)
              & (_sin(dP[:, None], d_out[None, :]) >= -CONE_TOL)
              & ((_unit(dP)[:, None] * (_unit(d_in) + _unit(d_out))[None, :]).sum(-1) > 0))
    i, j = np.nonzero(inside & convex[None, :])
    return np.stack([P[i] + Q[j], P[(i + 1) % len(P)] + Q[j]], axis=1)


def minkowski_sum(P: np.ndarray, Q: np.ndarray) -> Polygon | None:
    """``P ⊕ Q`` of two simple polygons ``(n, 2)``, ``(m, 2)`` with its holes filled, by the
    reduced convolution (see the module); None when the arrangement is degenerate."""
    P, Q = _ccw(np.asarray(P, float)), _ccw(np.asarray(Q, float))
    segs = np.concatenate([_edge_vertex(P, Q), _edge_vertex(Q, P)])
    noded = shapely.union_all(shapely.linestrings(segs))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
    if len(faces) == 0:
        return None
    filled = shapely.union_all([Polygon(g.exterior) for g in
                                shapely.get_parts(shapely.union_all(faces))])
    bound = (np.sqrt(Polygon(P).area) + np.sqrt(Polygon(Q).area)) ** 2
    if filled.geom_type != "Polygon" or filled.area < bound * (1 - 1e-9):
        return None
    return filled


class NfpCache:
    """No-fit polygons of shapes ``shapes[g] = (outline (n, 2), pieces (k, 4, 2), deviation)``
    (mm) at ``spacing``: :meth:`get` rotates the one polygon per shape pair and relative
    rotation; ``computed`` counts those polygons."""

    def __init__(self, shapes: dict, spacing: float):
        self.shapes = shapes
        self.spacing = spacing
        self._base: dict[tuple, Polygon] = {}
        self._rotated: dict[tuple, Polygon] = {}
        self._grown: dict[tuple, Polygon | None] = {}

    @property
    def computed(self) -> int:
        return len(self._base)

    def _clearance(self, ga: int, gb: int) -> float:
        return (self.spacing + CLEARANCE_MM + self.shapes[ga][2] + self.shapes[gb][2])

    def _grown_of(self, g: int, clearance: float) -> Polygon | None:
        """Shape ``g`` grown by the 32-gon around the disk of ``clearance`` (turned with the
        shape, the 32-gon still holds the disk)."""
        if (g, clearance) not in self._grown:
            self._grown[(g, clearance)] = minkowski_sum(self.shapes[g][0], disk(clearance)) \
                if clearance > 0 else Polygon(self.shapes[g][0])
        return self._grown[(g, clearance)]

    def _base_nfp(self, ga: int, gb: int, rel: float) -> Polygon:
        key = (ga, gb, rel)
        if key not in self._base:
            clearance = self._clearance(ga, gb)
            a, b = self.shapes[ga], self.shapes[gb]
            grown = self._grown_of(ga, clearance)
            moving = -(b[0] @ rotation_matrix(rel).T)
            nfp = None if grown is None else minkowski_sum(
                np.asarray(grown.exterior.coords)[:-1], moving)
            if nfp is None:
                nfp = minkowski_nfp(a[1], 0.0, b[1], rel, clearance)
            self._base[key] = nfp
        return self._base[key]

    def around_box(self, g: int, rot: float, half: tuple[float, float]) -> Polygon | None:
        """NFP of the axis-aligned box ``±half`` (a probe inside every part, clearance without
        any deviation of its own) around shape ``g`` at ``rot``; None if degenerate."""
        key = ("box", g, _norm(rot), half)
        if key not in self._rotated:
            grown = self._grown_of(g, self.spacing + CLEARANCE_MM + self.shapes[g][2])
            hx, hy = half
            box = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
            self._rotated[key] = None if grown is None else minkowski_sum(
                np.asarray(grown.exterior.coords)[:-1] @ rotation_matrix(rot).T, box)
        return self._rotated[key]

    def get(self, ga: int, rot_a: float, gb: int, rot_b: float) -> Polygon:
        """NFP of shape ``gb`` at ``rot_b`` around shape ``ga`` at ``rot_a`` (degrees)."""
        key = (ga, _norm(rot_a), gb, _norm(rot_b))
        if key not in self._rotated:
            base = self._base_nfp(ga, gb, _norm(rot_b - rot_a))
            R = rotation_matrix(key[1])
            self._rotated[key] = base if key[1] == 0.0 else \
                shapely.transform(base, lambda xy: xy @ R.T)
        return self._rotated[key]
