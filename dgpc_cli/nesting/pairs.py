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
    """Part ``index`` inside a unit: rotation ``rotation`` then translation ``offset``."""

    index: int
    rotation: float
    offset: tuple[float, float]


@dataclass
class Unit:
    """What the fill places: ``part`` (the geometry, possibly of two parts) and its members."""

    part: Part
    members: list[Member]


def _box_area(b) -> float:
    return (b[2] - b[0]) * (b[3] - b[1])


def best_pair(part: Part, rotations: list[float], spacing: float):
    """``(r1, r2, t, area)`` of the smallest-box pair of two copies of ``part``, or None."""
    clearance = spacing + CLEARANCE_MM + 2 * part.deviation
    best = None
    for r1 in rotations:
        pa = part.outline @ rotation_matrix(r1).T
        ba = bounds(pa)
        for r2 in rotations:
            pb = part.outline @ rotation_matrix(r2).T
            bb = bounds(pb)
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


def make_units(parts: list[Part], rotations: list[float], spacing: float) -> list[Unit]:
    """Units for the fill: pairs of congruent parts where pairing pays, else single parts."""
    allowed = {_norm(r) for r in rotations}
    units: list[Unit] = []
    by_group: dict[int, list[int]] = {}
    for i, p in enumerate(parts):
        by_group.setdefault(p.group, []).append(i)
    next_group = max(by_group) + 1 if by_group else 0
    for _, idx in sorted(by_group.items()):
        idx = sorted(idx, key=lambda i: parts[i].id)
        lead = parts[idx[0]]
        pair = best_pair(lead, rotations, spacing) if len(idx) >= 2 else None
        single = min(_box_area(bounds(lead.outline @ rotation_matrix(r).T)) for r in rotations)
        unit_rots = ()
        if pair is not None:
            r1, r2, t, area = pair
            unit_rots = tuple(r for r in rotations
                              if _norm(r + r1) in allowed and _norm(r + r2) in allowed)
        if pair is None or area > PAIR_GAIN * 2 * single or not unit_rots:
            units += [Unit(parts[i], [Member(i, 0.0, (0.0, 0.0))]) for i in idx]
            continue
        R1, R2 = rotation_matrix(r1), rotation_matrix(r2)
        for a, b in zip(idx[0::2], idx[1::2], strict=False):
            pa, pb = parts[a], parts[b]
            geom = Part(
                id=pa.id, strip=pa.strip, cls=pa.cls,
                outline=np.concatenate([pa.outline @ R1.T, pb.outline @ R2.T + t]),
                score=[], label=pa.label, geodesics=[], area=pa.area + pb.area,
                pieces=np.concatenate([pa.pieces @ R1.T, pb.pieces @ R2.T + t]),
                group=next_group, deviation=max(pa.deviation, pb.deviation),
                rotations=unit_rots)
            units.append(Unit(geom, [Member(a, r1, (0.0, 0.0)), Member(b, r2, t)]))
        if len(idx) % 2:
            units.append(Unit(parts[idx[-1]], [Member(idx[-1], 0.0, (0.0, 0.0))]))
        next_group += 1
    return units


def expand(member: Member, rotation: float, translation, rotations: list[float]):
    """The member's own placement from its unit's ``rotation`` and ``translation``: the
    rotation as one of the allowed values, the translation ``R(rotation)·offset + T``."""
    total = _norm(rotation + member.rotation)
    rot = next((r for r in rotations if _norm(r) == total), total)
    t = rotation_matrix(rotation) @ np.asarray(member.offset) + np.asarray(translation)
    return float(rot), (float(t[0]), float(t[1]))
