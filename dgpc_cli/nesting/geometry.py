"""Parts to nest, in mm, and the geometry of placing them (SPEC §6 nest).

A placement is a rotation by ``rotation`` degrees about the part's own origin followed by a
translation: ``x_sheet = R(rotation) · x_part + translation`` with ``x_part`` the flat part's
coordinates already scaled to mm (``x_part = k · x_model``, ``k = scale · mm per unit``).
Sheet coordinates: origin at the sheet's lower-left corner, x along the width, y along the
height.

No-fit polygons come from a convex decomposition of each part (the developed strip's quads
``A_u A_(u+1) B_(u+1) B_u``, or a constrained triangulation) and pairwise convex Minkowski sums,
all vectorized with shapely.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import Polygon

from ..io.flat import first_row
from ..io.sheets import rotation_matrix, transform

__all__ = ["rotation_matrix", "transform"]  # the placement of the sheets artifact, used here

#: Clearance added to every spacing and margin (mm): keeps touching parts apart by more than
#: floating-point noise, far below any cutter's precision.
CLEARANCE_MM = 1e-4

#: Parts whose outlines (in their own coordinates, same vertex count) differ by at most this
#: (mm) share their no-fit polygons; the difference is added to the spacing.
GROUP_TOL_MM = 1e-3
#: ... or by at most this fraction of the spacing: congruent strips of a large part differ by
#: a few tenths of a mm after unfolding; sharing their no-fit polygons (and pairing them) costs
#: at most that much extra gap and saves a no-fit polygon per pair of parts.
GROUP_SPACING_FRACTION = 0.25


#: An outline with more vertices than this (a strip trimmed along a curved edge of the
#: reference) is simplified for its no-fit polygons (never for the cut): a no-fit polygon sums
#: every pair of convex pieces, so hundreds of triangles per part made one take minutes.
MAX_PIECE_VERTICES = 64


def group_tolerance(spacing: float) -> float:
    """How far (mm) two parts' outlines may differ to share no-fit polygons."""
    return max(GROUP_TOL_MM, GROUP_SPACING_FRACTION * spacing)


@dataclass
class Part:
    """One flat part in mm: ``outline (n, 2)`` ccw, ``score`` open polylines, ``label`` point,
    ``geodesics`` its two developed geodesics ``A, B (m, 2)``, ``pieces (k, 4, 2)`` convex
    pieces (triangles repeat a vertex), ``group`` index of parts sharing no-fit polygons and
    ``deviation``: how far (mm) the outline may lie from the shape its no-fit polygons use
    (its group leader's, of a simplified outline where it is long; added to the spacing);
    ``nfp_outline`` the outline the no-fit polygons use (simplified where long), and
    ``shape_rotation``, ``shape_offset``: the part ≈ R(shape_rotation) · leader + offset, the
    leader's ``nfp_outline`` and ``pieces`` being its group's shape; ``row`` the net row of
    its first end (``A[0], B[0]``), which its end mark names."""

    id: str
    strip: int
    cls: str
    outline: np.ndarray
    score: list
    label: np.ndarray
    geodesics: list
    area: float
    pieces: np.ndarray = field(repr=False)
    group: int = 0
    deviation: float = 0.0
    rotations: tuple | None = None
    nfp_outline: np.ndarray | None = field(default=None, repr=False)
    shape_rotation: float = 0.0
    shape_offset: tuple = (0.0, 0.0)
    row: float = 0.0


def _convex(poly: np.ndarray) -> bool:
    p = Polygon(poly)
    return p.is_valid and abs(p.convex_hull.area - p.area) <= 1e-12 * max(p.area, 1e-300)


def convex_pieces(outline: np.ndarray, geodesics=None) -> np.ndarray:
    """Convex pieces ``(k, 4, 2)`` covering ``outline`` exactly: the strip's quads when the
    outline is A forwards then B backwards, else a constrained Delaunay triangulation."""
    outline = np.asarray(outline, float)
    area = Polygon(outline).area
    if geodesics is not None:
        A, B = (np.asarray(g, float) for g in geodesics)
        if len(A) == len(B) and np.array_equal(np.concatenate([A, B[::-1]]), outline):
            quads = np.stack([A[:-1], A[1:], B[1:], B[:-1]], axis=1)
            pieces = []
            for q in quads:
                if _convex(q):
                    pieces.append(q)
                else:
                    pieces += [q[[0, 1, 2, 2]], q[[0, 2, 3, 3]]]
            pieces = np.asarray(pieces)
            if abs(sum(Polygon(p).area for p in pieces) - area) <= 1e-9 * area:
                return pieces
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(Polygon(outline)))
    coords = np.stack([shapely.get_coordinates(t)[:3] for t in tris])
    return coords[:, [0, 1, 2, 2]]


def piece_outline(outline: np.ndarray) -> tuple[np.ndarray, float]:
    """The outline the no-fit polygons use and how far (mm) it lies from ``outline``: the
    outline itself up to :data:`MAX_PIECE_VERTICES` vertices, else its Douglas–Peucker
    simplification (topology kept) with the smallest tolerance, doubled from 1e-4 of the
    diagonal, that brings it within that count. Every vertex of either outline is within the
    tolerance of the other (the simplified one keeps a subset of the vertices), so adding it
    to the spacing keeps the true outlines apart."""
    outline = np.asarray(outline, float)
    if len(outline) <= MAX_PIECE_VERTICES:
        return outline, 0.0
    poly = Polygon(outline)
    tol = 1e-4 * float(np.linalg.norm(np.ptp(outline, axis=0)))
    while True:
        simple = poly.simplify(tol, preserve_topology=True)
        coords = np.asarray(simple.exterior.coords)[:-1]
        if len(coords) <= MAX_PIECE_VERTICES or not simple.is_valid:
            break
        tol *= 2.0
    if not simple.is_valid or simple.is_empty:
        return outline, 0.0
    return coords, tol


#: Most points an outline is cut into when two are compared (:func:`_rings_apart`): a 6 m
#: strip's outline at a quarter of a 0.75 mm grouping tolerance takes 64,000.
MAX_SAMPLES = 1 << 17


def _rings_apart(a: np.ndarray, b: np.ndarray, step: float, limit: float = np.inf) -> float:
    """An upper bound (mm) of the Hausdorff distance between the closed outlines ``a`` and
    ``b``: the largest distance of corresponding vertices where they have as many (when that is
    within ``limit``); else both cut into pieces no longer than ``step`` (at most
    :data:`MAX_SAMPLES`), the largest distance of a point of one to the other, plus half the
    step (the distance is 1-Lipschitz along an edge); inf where the vertices alone are farther
    apart than ``limit``."""
    if len(a) == len(b):
        # outlines built alike (same vertex count, corresponding vertices): a point of one edge
        # lies as far from the other outline as at most the farther of its edge's ends lies
        # from the corresponding vertex, so the vertex correspondence bounds the distance
        paired = float(np.linalg.norm(a - b, axis=1).max())
        if paired <= limit:
            return paired
    ra, rb = shapely.linearrings(a), shapely.linearrings(b)
    # at most MAX_SAMPLES points per outline: a tolerance far below the outline's size would
    # cut it into millions of pieces (the bound then grows with the step, and the shapes are
    # not grouped: grouping only saves work)
    step = max(step, max(ra.length, rb.length) / MAX_SAMPLES)
    if max(shapely.distance(shapely.points(a), rb).max(),
           shapely.distance(shapely.points(b), ra).max()) > limit:
        return np.inf                                   # the vertices alone are too far
    pa = shapely.get_coordinates(shapely.segmentize(ra, step))
    pb = shapely.get_coordinates(shapely.segmentize(rb, step))
    # a point of one outline lies within step/2 of a sample of it, and a sample's distance to
    # the other outline's samples bounds its distance to that outline from above
    return float(max(cKDTree(pb).query(pa)[0].max(),
                     cKDTree(pa).query(pb)[0].max())) + 0.5 * step


def _match(part: Part, leader: Part, turns: list[float], tol: float, centroid: dict,
           perimeter: dict):
    """``(turn, offset, distance)`` placing the leader's shape on ``part`` (its centroid on the
    part's, turned by one of ``turns``) within ``tol`` (mm), or None. ``centroid``,
    ``perimeter``: of each part by id."""
    if abs(part.area - leader.area) > perimeter[id(part)] * tol:
        return None
    for q in turns:
        R = rotation_matrix(q)
        d = centroid[id(part)] - R @ centroid[id(leader)]
        dist = _rings_apart(part.outline, leader.outline @ R.T + d, max(0.25 * tol, 1e-6), tol)
        if dist <= tol:
            return q, (float(d[0]), float(d[1])), dist
    return None


def prepare_parts(flat_parts: list[dict], k: float, tol: float = GROUP_TOL_MM,
                  turns: tuple = (0.0, 180.0)) -> list[Part]:
    """The flat artifact's part records scaled by ``k`` (mm per model unit), grouped by shape:
    a part joins the first group whose leader, turned by one of ``turns`` (degrees) and moved
    centroid onto centroid, lies within ``tol`` (mm) of its outline (leaders of its own
    congruence class tried first). The group's deviation (the largest of its members') is added
    to the spacing of its no-fit polygons."""
    parts = []
    for rec in flat_parts:
        outline = k * np.asarray(rec["outline"], float)
        geod = [k * np.asarray(g, float) for g in rec["geodesics"]]
        poly = Polygon(outline)
        simple, simplified_by = piece_outline(outline)
        pieces = convex_pieces(outline, geod) if simplified_by == 0.0 else convex_pieces(simple)
        parts.append(Part(
            id=rec["id"], strip=int(rec["strip"]), cls=rec["class"], outline=outline,
            score=[k * np.asarray(s, float) for s in rec["score"]],
            label=k * np.asarray(rec["label"], float), geodesics=geod,
            area=float(poly.area), pieces=pieces, deviation=simplified_by,
            nfp_outline=simple, row=first_row(rec)))
    polys = [Polygon(p.outline) for p in parts]
    centroid = {id(p): np.asarray(g.centroid.coords[0]) for p, g in zip(parts, polys, strict=True)}
    perimeter = {id(p): g.length for p, g in zip(parts, polys, strict=True)}
    leaders: list[int] = []
    for i, p in enumerate(parts):
        order = sorted(range(len(leaders)), key=lambda g: (parts[leaders[g]].cls != p.cls, g))
        for g in order:
            leader = parts[leaders[g]]
            found = _match(p, leader, list(turns), tol, centroid, perimeter)
            if found is not None:
                q, d, dist = found
                p.group, p.shape_rotation, p.shape_offset = g, q, d
                p.deviation = leader.deviation + dist
                break
        else:
            p.group = len(leaders)
            leaders.append(i)
    worst: dict[int, float] = {}
    for p in parts:
        worst[p.group] = max(worst.get(p.group, 0.0), p.deviation)
    for p in parts:
        p.deviation = worst[p.group]
    return parts


def shapes_of(parts: list[Part]) -> dict[int, tuple]:
    """``group → (nfp_outline, pieces, deviation)`` of each group's leader (its first part)."""
    out: dict[int, tuple] = {}
    for p in parts:
        if p.group not in out:
            out[p.group] = (p.nfp_outline, p.pieces, p.deviation)
    return out


def disk(radius: float, sides: int = 32) -> np.ndarray:
    """A regular polygon ``(sides, 2)`` circumscribing the circle of ``radius`` (its edges
    touch the circle, so it contains the disk)."""
    a = (np.arange(sides) + 0.5) * (2 * np.pi / sides)
    return (radius / np.cos(np.pi / sides)) * np.column_stack([np.cos(a), np.sin(a)])


def _hull_vertices(points: np.ndarray) -> np.ndarray:
    """The convex hulls' vertices ``(k, h, 2)`` of ``k`` point sets ``(k, ..., 2)``, each
    padded to the longest hull by repeating its first vertex (the hull is unchanged)."""
    hulls = shapely.convex_hull(shapely.linestrings(points.reshape(len(points), -1, 2)))
    coords, index = shapely.get_coordinates(hulls, return_index=True)
    counts = np.bincount(index, minlength=len(points))
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    h = counts.max()
    take = start[:, None] + np.minimum(np.arange(h)[None, :], counts[:, None] - 1)
    take = np.where(np.arange(h)[None, :] < counts[:, None], take, start[:, None])
    return coords[take]


def minkowski_nfp(pieces_a: np.ndarray, rot_a: float, pieces_b: np.ndarray, rot_b: float,
                  clearance: float) -> Polygon:
    """No-fit polygon of part b (rotated ``rot_b``) around part a (rotated ``rot_a``, at the
    origin): the translations of b that bring it closer than ``clearance`` to a.

    ``(a ⊕ D ⊕ −b)`` with ``D`` a polygon containing the disk of radius ``clearance``, as the
    union of the convex hulls of all pairwise piece sums (exact up to ``D``; GEOS's buffer
    is not used: it simplifies its input by 1 % of the distance).
    """
    pa = pieces_a @ rotation_matrix(rot_a).T                    # (na, 4, 2)
    if clearance > 0:
        pa = _hull_vertices(pa[:, :, None, :] + disk(clearance)[None, None, :, :])
    pb = -(pieces_b @ rotation_matrix(rot_b).T)                 # (nb, 4, 2)
    sums = (pa[:, None, :, None, :] + pb[None, :, None, :, :]).reshape(
        len(pa) * len(pb), -1, 2)
    hulls = shapely.convex_hull(shapely.linestrings(sums))
    return shapely.union_all(hulls)


def bounds(points: np.ndarray) -> tuple[float, float, float, float]:
    """``(xmin, ymin, xmax, ymax)`` of ``points (n, 2)``."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])
