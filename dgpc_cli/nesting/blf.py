"""Deterministic multi-sheet bottom-left fill over exact no-fit polygons (the default engine).

Units (single parts or interlocked pairs, :mod:`~dgpc_cli.nesting.pairs`) go in a fixed order
(largest area first, ties by id; no randomness, so ``--seed`` only matters to the spyrrow
engine). Each unit goes to the first open sheet where it fits: on a sheet, the feasible
translations of the part with rotation r are the inner-fit rectangle (sheet minus margin) minus
the union of the no-fit polygons of the parts already there (grown by the spacing); the part
takes the feasible point with the least left edge, then the least top, over the allowed
rotations (gravity x: columns fill from the left; gravity y: least top, then least left edge —
rows, which lets congruent bands stagger). A part that fits nowhere opens a new sheet. Exact
geometry, no time limit: the same input gives the same placements.

No-fit polygons come from one cache (:mod:`~dgpc_cli.nesting.nfp`) shared by every sheet and
both fill directions, one per pair of part shapes and relative rotation. Sheets that cannot take
a part are skipped without any: one holding less free area than the part, or one where a probe
box that the part contains (:func:`probe_boxes`) no longer fits.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from .geometry import CLEARANCE_MM, Part, bounds, rotation_matrix, shapes_of
from .nfp import NfpCache, _norm
from .pairs import Unit, expand, make_units

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Placement:
    """Part ``index`` (into the parts list) on ``sheet`` with ``rotation`` (deg) and
    ``translation`` (mm): ``x_sheet = R · x_part + translation``."""

    index: int
    sheet: int
    rotation: float
    translation: tuple[float, float]


@dataclass(frozen=True)
class Sheet:
    """A sheet ``width`` × ``height`` (mm) with ``margin`` and part ``spacing`` (mm)."""

    width: float
    height: float
    margin: float
    spacing: float


def inner_fit(part: Part, rotation: float, sheet: Sheet) -> tuple | None:
    """The translations keeping the rotated part inside the margin: ``(x0, y0, x1, y1)`` or
    None when it does not fit."""
    xmin, ymin, xmax, ymax = bounds(part.outline @ rotation_matrix(rotation).T)
    m = sheet.margin + CLEARANCE_MM
    x0, x1 = m - xmin, sheet.width - m - xmax
    y0, y1 = m - ymin, sheet.height - m - ymax
    if x1 < x0 or y1 < y0:
        return None
    return x0, y0, x1, y1


def _bottom_left(region, env, gravity: str) -> tuple[tuple, tuple[float, float]] | None:
    """The best vertex of ``region`` and its key; ``env`` = rotated part bounds: least
    left edge then least top (gravity x), or least top then least left edge (gravity y)."""
    if region.is_empty:
        return None
    xy = shapely.get_coordinates(region)
    x, y = xy[:, 0], xy[:, 1]
    if gravity == "x":
        keys = (np.round(x + env[0], 6), np.round(y + env[3], 6))
    else:
        keys = (np.round(y + env[3], 6), np.round(x + env[0], 6))
    i = np.lexsort(keys[::-1])[0]
    return tuple(float(k[i]) for k in keys), (float(x[i]), float(y[i]))


class _SheetState:
    def __init__(self, area: float):
        self.placed: list[tuple[Unit, float, tuple[float, float]]] = []
        self.forbidden: dict[tuple, tuple[int, object]] = {}
        self.free = area
        self.probes: dict = {}           # probe → (placed count, the probe no longer fits)


def _box_height(poly: Polygon, width: float) -> float:
    """The height of an axis-aligned box ``width`` wide that ``poly`` contains (centred on
    the middle of its vertical section through the centroid; 0 if none)."""
    cx = poly.centroid.x
    section = poly.intersection(shapely.linestrings([(cx, poly.bounds[1] - 1),
                                                      (cx, poly.bounds[3] + 1)]))
    if section.is_empty:
        return 0.0
    lo, hi = 0.0, float(section.length)
    y0, y1 = section.bounds[1], section.bounds[3]
    cy = 0.5 * (y0 + y1)
    for _ in range(16):
        mid = 0.5 * (lo + hi)
        if poly.contains(box(cx - width / 2, cy - mid / 2, cx + width / 2, cy + mid / 2)):
            lo = mid
        else:
            hi = mid
    return lo


#: Probe boxes are rounded down to this fraction of the sheet's shorter side (few distinct
#: probes, each still inside its parts).
PROBE_GRID = 0.02


def probe_boxes(units: list[Unit], rotations: list[float], sheet: Sheet) -> dict:
    """Per unit key the half sizes of an axis-aligned box the unit contains at each of its
    rotations (half its length, the least height there, rounded down to
    :data:`PROBE_GRID`), or None: a sheet where the box no longer fits cannot take the unit
    (the unit would carry the box with it)."""
    grid = PROBE_GRID * min(sheet.width, sheet.height)
    out: dict = {}
    for u in units:
        if u.key in out:
            continue
        core = u.part.outline[:u.core] if u.core else u.part.outline
        polys = [Polygon(core @ rotation_matrix(r).T) for r in u.part.rotations or rotations]
        if not all(c.is_valid for c in polys):
            out[u.key] = None
            continue
        width = 0.5 * min(c.bounds[2] - c.bounds[0] for c in polys)
        height = min(_box_height(c, width) for c in polys)
        hx, hy = (grid * np.floor(0.5 * v / grid) for v in (width, height))
        out[u.key] = (float(hx), float(hy)) if hx > 0 and hy > 0 else None
    return out


def unit_nfp(nfps: NfpCache, a: Unit, rot_a: float, b: Unit, rot_b: float, cache: dict):
    """NFP of unit b at ``rot_b`` around unit a at ``rot_a`` (at the origin): the union of its
    components' shape no-fit polygons, each moved by the components' offsets."""
    key = (a.key, _norm(rot_a), b.key, _norm(rot_b))
    if key not in cache:
        Ra, Rb = rotation_matrix(rot_a), rotation_matrix(rot_b)
        polys = []
        for ga, ra, oa in a.components:
            for gb, rb, ob in b.components:
                shift = Ra @ np.asarray(oa) - Rb @ np.asarray(ob)
                nfp = nfps.get(ga, rot_a + ra, gb, rot_b + rb)
                polys.append(nfp if not shift.any() else
                             shapely.transform(nfp, lambda xy, s=shift: xy + s))
        cache[key] = polys[0] if len(polys) == 1 else shapely.union_all(polys)
    return cache[key]


class BottomLeftFill:
    """The engine: ``run(units)`` → placements (see the module); ``nfps`` the shared no-fit
    polygon cache (:class:`~dgpc_cli.nesting.nfp.NfpCache`)."""

    def __init__(self, sheet: Sheet, rotations: list[float], nfps: NfpCache,
                 gravity: str = "x"):
        self.sheet = sheet
        self.gravity = gravity
        self.rotations = list(rotations)
        self.nfps = nfps
        self._units: dict = {}
        self.probes: dict = {}

    def _forbidden(self, state: _SheetState, unit: Unit, rot: float):
        key = (unit.key, _norm(rot))
        count, union = state.forbidden.get(key, (0, Polygon()))
        if count < len(state.placed):
            new = [shapely.transform(unit_nfp(self.nfps, u, r, unit, rot, self._units),
                                     lambda xy, t=t: xy + t)
                   for u, r, t in state.placed[count:]]
            union = shapely.union_all([union, *new])
            state.forbidden[key] = (len(state.placed), union)
        return union

    def _closed(self, state: _SheetState, unit: Unit) -> bool:
        """Whether the unit's probe box (:func:`probe_boxes`) no longer fits on the sheet."""
        probe = self.probes.get(unit.key)
        if probe is None:
            return False
        count, closed = state.probes.get(probe, (0, False))
        if closed or count == len(state.placed):
            return closed
        hx, hy = probe
        m = self.sheet.margin + CLEARANCE_MM
        x0, y0, x1, y1 = m + hx, m + hy, self.sheet.width - m - hx, self.sheet.height - m - hy
        polys = []
        for u, r, t in state.placed:
            R = rotation_matrix(r)
            for g, rc, oc in u.components:
                nfp = self.nfps.around_box(g, r + rc, probe)
                if nfp is None:
                    return False
                shift = R @ np.asarray(oc) + np.asarray(t)
                polys.append(shapely.transform(nfp, lambda xy, s=shift: xy + s))
        region = box(x0, y0, x1, y1) if (x1 > x0 and y1 > y0) else \
            shapely.linestrings([(x0, y0), (max(x0, x1), max(y0, y1))])
        closed = region.difference(shapely.union_all(polys)).is_empty
        state.probes[probe] = (len(state.placed), closed)
        return closed

    def _candidate(self, state: _SheetState, unit: Unit):
        part = unit.part
        if state.placed and (part.area > state.free or self._closed(state, unit)):
            return None
        best = None
        for rot in part.rotations or self.rotations:
            ifr = inner_fit(part, rot, self.sheet)
            if ifr is None:
                continue
            x0, y0, x1, y1 = ifr
            rect = box(x0, y0, x1, y1) if (x1 > x0 and y1 > y0) else \
                shapely.points([(x0, y0)])[0] if (x1 == x0 and y1 == y0) else \
                shapely.linestrings([(x0, y0), (x1, y1)])
            region = rect.difference(self._forbidden(state, unit, rot)) if state.placed \
                else rect
            env = bounds(part.outline @ rotation_matrix(rot).T)
            found = _bottom_left(region, env, self.gravity)
            if found is None:
                continue
            key, point = found
            if best is None or key < best[0]:
                best = (key, rot, point)
        return best

    def run(self, units: list[Unit], progress=None, probes=None) -> list[Placement]:
        """Place every unit (a part or a pair, :mod:`~dgpc_cli.nesting.pairs`); returns one
        placement per part, sorted by sheet then part index. ``probes``: the units' probe
        boxes (:func:`probe_boxes`, computed when None)."""
        self.probes = probe_boxes(units, self.rotations, self.sheet) if probes is None \
            else probes
        order = sorted(range(len(units)),
                       key=lambda u: (-round(units[u].part.area, 6), units[u].part.id))
        sheets: list[_SheetState] = []
        out: list[Placement] = []
        inner = self.sheet.width * self.sheet.height
        for u in order:
            unit = units[u]
            for s, state in enumerate([*sheets, None]):
                if state is None:
                    state = _SheetState(inner)
                    sheets.append(state)
                found = self._candidate(state, unit)
                if found is not None:
                    _, rot, point = found
                    state.placed.append((unit, rot, point))
                    state.free -= unit.part.area
                    for m in unit.members:
                        r, t = expand(m, rot, point, self.rotations)
                        out.append(Placement(m.index, s, r, t))
                    break
            else:  # pragma: no cover - a fresh sheet takes any part that passed the checks
                raise AssertionError(unit.part.id)
            if progress is not None:
                progress(len(unit.members))
        log.info("bottom-left fill: %d units on %d sheets (%d no-fit polygons so far)",
                 len(units), len(sheets), self.nfps.computed)
        return sorted(out, key=lambda p: (p.sheet, p.index))


def used_fraction(parts: list[Part], placements: list[Placement], sheet: Sheet,
                  gravity: str) -> float:
    """How far (0…1) the parts on the last sheet reach along the fill direction."""
    last = max(p.sheet for p in placements)
    axis = 0 if gravity == "x" else 1
    reach = max(float(np.max((parts[p.index].outline @ rotation_matrix(p.rotation).T)[:, axis]
                             + p.translation[axis])) for p in placements if p.sheet == last)
    return reach / (sheet.width if axis == 0 else sheet.height)


def fill_sheets(parts: list[Part], sheet: Sheet, rotations: list[float],
                progress=None) -> tuple[list[Placement], dict]:
    """The engine: pair congruent parts, fill sheets with gravity along x (columns) and along
    y (rows), keep the result with fewer sheets, then the shorter last sheet (ties: x).
    Returns the placements and a record of what was tried."""
    nfps = NfpCache(shapes_of(parts), sheet.spacing)
    units = make_units(parts, rotations, sheet.spacing, nfps)
    probes = probe_boxes(units, rotations, sheet)
    tried = {}
    results = {}
    for gravity in ("x", "y"):
        placements = BottomLeftFill(sheet, rotations, nfps, gravity).run(units, progress, probes)
        n = max(p.sheet for p in placements) + 1
        frac = used_fraction(parts, placements, sheet, gravity)
        tried[gravity] = {"sheets": n, "last_sheet_used": frac}
        results[gravity] = (n, round(frac, 9), gravity, placements)
    best = min(results.values(), key=lambda r: r[:3])
    log.info("fill: gravity %s chosen (%s)", best[2], tried)
    return best[3], {"gravity": best[2], "tried": tried,
                     "pairs": sum(len(u.members) == 2 for u in units),
                     "shapes": len(nfps.shapes), "no_fit_polygons": nfps.computed}
