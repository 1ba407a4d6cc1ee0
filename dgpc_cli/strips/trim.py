"""Strips clipped to the reference's outline (``planarize-strips --trim``): a net that runs past
its reference (``init --extend``, paper Fig. 14) is a cladding layout, and every developed part
must end where the reference ends.

Each planar-quad strip ``A_u, A_(u+1), B_(u+1), B_u`` is parametrized by ``(t, s)``: ``t`` in
``[0, m − 1]`` along the strip (row u at t = u), ``s`` in ``[0, 1]`` across it (A at 0, B at 1),
bilinear on every quad — exact for planar quads, and the same map carries a quad's points to its
development, which is congruent to it (``strips.develop``). On a fine grid of ``(t, s)`` the
signed distance to the outline is measured: within the reference, the distance along it to the
reference's boundary; beyond it, minus the distance to the boundary (a point over the
reference projects to its interior, a point beyond it onto its boundary). The parts are the
regions where it is not negative (contourpy's filled contours, linear along the grid edges),
as polygons in ``(t, s)``: their end cuts follow the outline, and the rulings ``t = u`` inside
them stay score lines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Grid steps per quad along the strip and across it, for the signed distance.
ALONG, ACROSS = 8, 8


@dataclass(frozen=True)
class TrimPart:
    """One piece of a strip inside the outline: ``outline (k, 2)`` in ``(t, s)``, counter-
    clockwise, not closed; its extent ``t_range`` along the strip."""

    outline: np.ndarray

    @property
    def t_range(self) -> tuple[float, float]:
        return float(self.outline[:, 0].min()), float(self.outline[:, 0].max())

    @property
    def quads(self) -> float:
        """Length along the strip, in quads."""
        lo, hi = self.t_range
        return hi - lo


def strip_points(A: np.ndarray, B: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """Points ``(k, d)`` of the strip ``A, B (m, d)`` at parameters ``ts (k, 2)`` (bilinear on
    the quad ``floor(t)``; works for the 3-D strip and for its development alike)."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    ts = np.asarray(ts, float).reshape(-1, 2)
    m = A.shape[0]
    u = np.clip(np.floor(ts[:, 0]).astype(np.int64), 0, m - 2)
    a = (ts[:, 0] - u)[:, None]
    s = ts[:, 1][:, None]
    lo = (1 - s) * A[u] + s * B[u]
    hi = (1 - s) * A[u + 1] + s * B[u + 1]
    return (1 - a) * lo + a * hi


def through_rows(ring: np.ndarray) -> np.ndarray:
    """The ring ``(k, 2)`` in ``(t, s)`` with a point added wherever one of its edges (the
    closing one too) crosses a row ``t = u`` strictly inside it: mapped by
    :func:`strip_points`, a side along a boundary geodesic then bends at every row, as the
    geodesic does (a rectangle's four corners alone would map to chords)."""
    ring = np.asarray(ring, float)
    nxt = np.roll(ring, -1, axis=0)
    t0, t1 = ring[:, 0], nxt[:, 0]
    first = np.floor(np.minimum(t0, t1)) + 1.0
    last = np.ceil(np.maximum(t0, t1)) - 1.0
    count = np.maximum(last - first + 1.0, 0.0).astype(np.int64)
    if not count.any():
        return ring
    e = np.repeat(np.arange(len(ring)), count)
    j = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    u = np.where(t1[e] > t0[e], first[e] + j, last[e] - j)
    a = (u - t0[e]) / (t1[e] - t0[e])
    added = ring[e] + a[:, None] * (nxt[e] - ring[e])
    added[:, 0] = u
    order = np.argsort(np.concatenate([np.arange(len(ring), dtype=float), e + a]),
                       kind="stable")
    return np.concatenate([ring, added])[order]


def part_area(A2: np.ndarray, B2: np.ndarray, ring: np.ndarray) -> float:
    """Area of the part ``ring (k, 2)`` (in ``(t, s)``) of the developed strip ``A2, B2``."""
    from dgpc_cli.strips.develop import signed_area

    return abs(signed_area(strip_points(A2, B2, through_rows(ring))))


def part_length(A: np.ndarray, B: np.ndarray, ring: np.ndarray) -> float:
    """Length of the part ``ring (k, 2)`` (in ``(t, s)``) of the strip ``A, B (m, d)``: the
    mean of its boundary geodesics' lengths over the part's extent along the strip (as
    :func:`developed_part` measures it)."""
    ring = np.asarray(ring, float)
    t0, t1 = float(ring[:, 0].min()), float(ring[:, 0].max())
    ts = np.unique(np.concatenate([[t0, t1], np.arange(np.ceil(t0), np.floor(t1) + 1)]))
    return 0.5 * sum(float(np.linalg.norm(np.diff(strip_points(
        A, B, np.column_stack([ts, np.full_like(ts, s)])), axis=0), axis=1).sum())
        for s in (0.0, 1.0))


def signed_outline_distance(reference, points: np.ndarray) -> np.ndarray:
    """``(k,)``: for points over ``reference`` (a ``core.reference.ReferenceSurface``) the
    distance along it to its boundary, for points beyond it minus their distance to the
    boundary; zero on the outline."""
    P = np.asarray(points, float).reshape(-1, 3)
    on, _ = reference.closest(P)
    foot, _ = reference.closest_on_boundary(P)
    d_surface = np.linalg.norm(P - on, axis=1)
    d_boundary = np.linalg.norm(P - foot, axis=1)
    inside = d_boundary - d_surface > 1e-9 * reference.bbox_diagonal
    along = np.sqrt(np.maximum(d_boundary ** 2 - d_surface ** 2, 0.0))
    return np.where(inside, along, -d_boundary)


def trim_strip(A: np.ndarray, B: np.ndarray, reference) -> list[TrimPart]:
    """The parts of the planar-quad strip ``A, B (m, 3)`` inside the outline of
    ``reference`` (see the module), in order along the strip; empty when none is."""
    from contourpy import contour_generator

    m = A.shape[0]
    t = np.linspace(0.0, m - 1.0, ALONG * (m - 1) + 1)
    s = np.linspace(0.0, 1.0, ACROSS + 1)
    T, S = np.meshgrid(t, s)                                      # (ny = s, nx = t)
    g = signed_outline_distance(reference, strip_points(A, B, np.stack([T, S], -1)))
    g = g.reshape(T.shape)
    if (g >= 0).all():
        return [TrimPart(through_rows(np.array([[0.0, 0.0], [m - 1.0, 0.0], [m - 1.0, 1.0],
                                                 [0.0, 1.0]])))]
    if not (g > 0).any():
        return []
    gen = contour_generator(T, S, g, fill_type="OuterOffset")
    points, offsets = gen.filled(0.0, float(g.max()) + 1.0)
    parts = []
    for pts, off in zip(points, offsets, strict=True):
        ring = np.asarray(pts[off[0]:off[1]], float)
        if len(ring) > 1 and np.allclose(ring[0], ring[-1]):
            ring = ring[:-1]
        if len(ring) < 3:
            continue
        x, y = ring[:, 0], ring[:, 1]
        area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        if area < 0:
            ring = ring[::-1]
        if abs(area) > 0:
            parts.append(TrimPart(ring))
    parts.sort(key=lambda p: p.t_range[0])
    return parts


def developed_part(A2: np.ndarray, B2: np.ndarray, ring: np.ndarray) -> dict:
    """A trimmed part of the developed strip ``A2, B2 (m, 2)`` (``strips.develop``), its
    outline ``ring (k, 2)`` in ``(t, s)``: the 2-D ``outline`` (counter-clockwise), the
    rulings inside it as ``score`` lines, a ``label`` point inside, the ``geodesics`` (the
    developed boundary geodesics A and B over the part's extent along the strip), their
    ``length`` (mean) and the outline's ``area``."""
    from shapely.geometry import LineString, Polygon

    from dgpc_cli.strips.develop import signed_area, straightness

    ring = through_rows(ring)
    outline = strip_points(A2, B2, ring)
    if signed_area(outline) < 0:
        outline = outline[::-1]
    param = Polygon(ring)
    t0, t1 = float(ring[:, 0].min()), float(ring[:, 0].max())
    score = []
    for u in range(int(np.floor(t0)) + 1, int(np.ceil(t1))):   # the rulings crossing it
        cut = param.intersection(LineString([(u, -1.0), (u, 2.0)]))
        for seg in getattr(cut, "geoms", [cut]):
            if seg.geom_type == "LineString" and seg.length > 0:
                score.append(strip_points(A2, B2, np.asarray(seg.coords)))
    ts = np.unique(np.concatenate([[t0, t1], np.arange(np.ceil(t0), np.floor(t1) + 1)]))
    geodesics = [strip_points(A2, B2, np.column_stack([ts, np.full_like(ts, s)]))
                 for s in (0.0, 1.0)]
    inner = param.representative_point()
    label = strip_points(A2, B2, np.array([[inner.x, inner.y]]))[0]
    lengths = [float(np.linalg.norm(np.diff(g, axis=0), axis=1).sum()) for g in geodesics]
    return {"outline": outline, "score": score, "label": label, "geodesics": geodesics,
            "straightness": [straightness(g) for g in geodesics],
            "length": 0.5 * (lengths[0] + lengths[1]), "area": signed_area(outline)}
