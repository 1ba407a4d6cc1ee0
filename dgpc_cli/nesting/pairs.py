"""Pairing congruent parts before the fill (a deterministic clustering step).

Developed strips of a revolution-isometric net are congruent tapered, curved bands: two of them,
one turned by 180°, interlock into a band of nearly constant width. For every group of
congruent parts (:func:`~dgpc_cli.nesting.geometry.prepare_parts`) the best relative placement
of two copies — rotations ``r1, r2`` from the allowed set and a translation on the boundary of
their no-fit polygon (so at exactly the spacing) — is the one whose bounding box is smallest;
when that box is clearly smaller than two single boxes, the group's members go as pairs
(consecutive in id order; an odd one stays single). A pair is placed as one unit with the
rotations that keep both of its members' rotations allowed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from .geometry import CLEARANCE_MM, Part, bounds, minkowski_nfp, rotation_matrix

#: Pair when the pair's box is at most this fraction of two single boxes.
PAIR_GAIN = 0.97


def _norm(deg: float) -> float:
    return float(np.round(deg % 360.0, 9) % 360.0)


@dataclass(frozen=True)
class Member:
    """Part ``index`` inside a unit: its group's shape turned by ``rotation`` then moved by
    ``offset`` (in the unit's frame); the part ≈ R(shape_rotation) · shape + shape_offset."""

    index: int
    rotation: float
    offset: tuple[float, float]
    shape_rotation: float = 0.0
    shape_offset: tuple[float, float] = (0.0, 0.0)


@dataclass
class Unit:
    """What the fill places: ``part`` (the true outline in the unit's frame, for the sheet's
    margin, and the unit's allowed rotations), ``members``, ``key`` (units with one key have one
    geometry: they share their no-fit polygons) and ``components``: ``(group, rotation,
    offset)`` of each member's shape in the unit's frame."""

    part: Part
    members: list[Member]
    key: tuple = ()
    components: tuple = ()
    core: int = 0          # a pair: its first member's outline is part.outline[:core]


def _box_area(b) -> float:
    return (b[2] - b[0]) * (b[3] - b[1])


def _in_shape_frame(part: Part) -> np.ndarray:
    """The part's true outline in its shape's frame: R(−q) · (outline − offset)."""
    return (part.outline - np.asarray(part.shape_offset)) @ \
        rotation_matrix(-part.shape_rotation).T


def single(index: int, part: Part, rotations: list[float]) -> Unit:
    """A part alone, in its shape's frame: its rotations turned by its shape rotation."""
    q = part.shape_rotation
    geom = Part(id=part.id, strip=part.strip, cls=part.cls, outline=_in_shape_frame(part),
                score=[], label=part.label, geodesics=[], area=part.area, pieces=part.pieces,
                group=part.group, deviation=part.deviation,
                rotations=tuple(_norm(r + q) for r in (part.rotations or rotations)))
    return Unit(geom, [Member(index, 0.0, (0.0, 0.0), q, tuple(part.shape_offset))],
                key=("single", part.group), components=((part.group, 0.0, (0.0, 0.0)),))


def best_pair(part: Part, rotations: list[float], spacing: float, nfps=None):
    """``(r1, r2, t, area)`` of the smallest-box pair of two copies of ``part``'s shape (its
    no-fit polygons from ``nfps``, an :class:`~dgpc_cli.nesting.nfp.NfpCache`), or None."""
    best = None
    for r1 in rotations:
        pa = part.outline @ rotation_matrix(r1).T
        ba = bounds(pa)
        for r2 in rotations:
            pb = part.outline @ rotation_matrix(r2).T
            bb = bounds(pb)
            if nfps is not None:
                nfp = nfps.get(part.group, r1, part.group, r2)
            else:
                clearance = spacing + CLEARANCE_MM + 2 * part.deviation
                nfp = minkowski_nfp(part.pieces, r1, part.pieces, r2, clearance)
            t = shapely.get_coordinates(shapely.get_exterior_ring(
                max(shapely.get_parts(nfp), key=lambda g: g.area)))
            lo = np.minimum(np.array(ba[:2]), np.array(bb[:2]) + t)
            hi = np.maximum(np.array(ba[2:]), np.array(bb[2:]) + t)
            area = np.prod(hi - lo, axis=1)
            k = int(np.lexsort((t[:, 0], t[:, 1], np.round(area, 6)))[0])
            cand = (float(area[k]), r1, r2, (float(t[k, 0]), float(t[k, 1])))
            if best is None or cand[0] < best[0] - 1e-6:
                best = cand
    if best is None:
        return None
    return best[1], best[2], best[3], best[0]


def make_units(parts: list[Part], rotations: list[float], spacing: float,
               nfps=None) -> list[Unit]:
    """Units for the fill: pairs of congruent parts (one group) where pairing pays, else
    single parts. ``nfps``: the no-fit polygon cache of the parts' shapes."""
    allowed = {_norm(r) for r in rotations}
    units: list[Unit] = []
    by_group: dict[int, list[int]] = {}
    for i, p in enumerate(parts):
        by_group.setdefault(p.group, []).append(i)
    for g, idx in sorted(by_group.items()):
        idx = sorted(idx, key=lambda i: parts[i].id)
        lead = parts[idx[0]]
        shape = _in_shape_frame(lead)
        turns = sorted({_norm(r + parts[i].shape_rotation) for i in idx for r in rotations})
        pair = best_pair(Part(**{**lead.__dict__, "outline": shape}), turns, spacing, nfps) \
            if len(idx) >= 2 else None
        single_box = min(_box_area(bounds(shape @ rotation_matrix(r).T)) for r in turns)
        if pair is None or pair[3] > PAIR_GAIN * 2 * single_box:
            units += [single(i, parts[i], rotations) for i in idx]
            continue
        r1, r2, t, _ = pair
        R1, R2 = rotation_matrix(r1), rotation_matrix(r2)
        leftover = list(idx[2 * (len(idx) // 2):])
        for a, b in zip(idx[0::2], idx[1::2], strict=False):
            pa, pb = parts[a], parts[b]
            qa, qb = pa.shape_rotation, pb.shape_rotation
            unit_rots = tuple(r for r in turns if _norm(r + r1 - qa) in allowed
                              and _norm(r + r2 - qb) in allowed)
            if not unit_rots:
                leftover += [a, b]
                continue
            geom = Part(
                id=pa.id, strip=pa.strip, cls=pa.cls,
                outline=np.concatenate([_in_shape_frame(pa) @ R1.T,
                                        _in_shape_frame(pb) @ R2.T + t]),
                score=[], label=pa.label, geodesics=[], area=pa.area + pb.area,
                pieces=lead.pieces, group=g, deviation=lead.deviation, rotations=unit_rots)
            units.append(Unit(geom, [Member(a, r1, (0.0, 0.0), qa, tuple(pa.shape_offset)),
                                     Member(b, r2, t, qb, tuple(pb.shape_offset))],
                              key=("pair", g), components=((g, r1, (0.0, 0.0)), (g, r2, t)),
                              core=len(pa.outline)))
        units += [single(i, parts[i], rotations) for i in sorted(leftover)]
    return units


def expand(member: Member, rotation: float, translation, rotations: list[float]):
    """The member part's own placement from its unit's ``rotation`` and ``translation``: the
    rotation ``rotation + member.rotation − shape_rotation`` as one of the allowed values, the
    translation ``R(rotation)·offset + T − R(part rotation)·shape_offset``."""
    total = _norm(rotation + member.rotation - member.shape_rotation)
    rot = next((r for r in rotations if _norm(r) == total), total)
    t = (rotation_matrix(rotation) @ np.asarray(member.offset) + np.asarray(translation)
         - rotation_matrix(total) @ np.asarray(member.shape_offset))
    return float(rot), (float(t[0]), float(t[1]))
