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
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from .geometry import CLEARANCE_MM, Part, bounds, minkowski_nfp, rotation_matrix
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
    def __init__(self):
        self.placed: list[tuple[Part, float, tuple[float, float]]] = []
        self.forbidden: dict[tuple[int, float], tuple[int, object]] = {}


class BottomLeftFill:
    """The engine: ``run(parts)`` → placements (see the module)."""

    def __init__(self, sheet: Sheet, rotations: list[float], gravity: str = "x"):
        self.sheet = sheet
        self.gravity = gravity
        self.rotations = list(rotations)
        self._nfp: dict[tuple, Polygon] = {}

    def _nfp_of(self, fixed: Part, rot_f: float, moving: Part, rot_m: float) -> Polygon:
        key = (fixed.group, rot_f, moving.group, rot_m)
        if key not in self._nfp:
            clearance = (self.sheet.spacing + CLEARANCE_MM + fixed.deviation
                         + moving.deviation)
            self._nfp[key] = minkowski_nfp(fixed.pieces, rot_f, moving.pieces, rot_m,
                                           clearance)
        return self._nfp[key]

    def _forbidden(self, state: _SheetState, part: Part, rot: float):
        key = (part.group, rot)
        count, union = state.forbidden.get(key, (0, Polygon()))
        if count < len(state.placed):
            new = [shapely.transform(self._nfp_of(p, r, part, rot), lambda xy, t=t: xy + t)
                   for p, r, t in state.placed[count:]]
            union = shapely.union_all([union, *new])
            state.forbidden[key] = (len(state.placed), union)
        return union

    def _candidate(self, state: _SheetState, part: Part):
        best = None
        for rot in part.rotations or self.rotations:
            ifr = inner_fit(part, rot, self.sheet)
            if ifr is None:
                continue
            x0, y0, x1, y1 = ifr
            rect = box(x0, y0, x1, y1) if (x1 > x0 and y1 > y0) else \
                shapely.points([(x0, y0)])[0] if (x1 == x0 and y1 == y0) else \
                shapely.linestrings([(x0, y0), (x1, y1)])
            region = rect.difference(self._forbidden(state, part, rot)) if state.placed \
                else rect
            env = bounds(part.outline @ rotation_matrix(rot).T)
            found = _bottom_left(region, env, self.gravity)
            if found is None:
                continue
            key, point = found
            if best is None or key < best[0]:
                best = (key, rot, point)
        return best

    def run(self, units: list[Unit], progress=None) -> list[Placement]:
        """Place every unit (a part or a pair, :mod:`~dgpc_cli.nesting.pairs`); returns one
        placement per part, sorted by sheet then part index."""
        order = sorted(range(len(units)),
                       key=lambda u: (-round(units[u].part.area, 6), units[u].part.id))
        sheets: list[_SheetState] = []
        out: list[Placement] = []
        for u in order:
            part = units[u].part
            for s, state in enumerate([*sheets, None]):
                if state is None:
                    state = _SheetState()
                    sheets.append(state)
                found = self._candidate(state, part)
                if found is not None:
                    _, rot, point = found
                    state.placed.append((part, rot, point))
                    for m in units[u].members:
                        r, t = expand(m, rot, point, self.rotations)
                        out.append(Placement(m.index, s, r, t))
                    break
            else:  # pragma: no cover - a fresh sheet takes any part that passed the checks
                raise AssertionError(part.id)
            if progress is not None:
                progress(len(units[u].members))
        log.info("bottom-left fill: %d units on %d sheets (%d no-fit polygons)", len(units),
                 len(sheets), len(self._nfp))
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
    units = make_units(parts, rotations, sheet.spacing)
    tried = {}
    results = {}
    for gravity in ("x", "y"):
        placements = BottomLeftFill(sheet, rotations, gravity).run(units, progress)
        n = max(p.sheet for p in placements) + 1
        frac = used_fraction(parts, placements, sheet, gravity)
        tried[gravity] = {"sheets": n, "last_sheet_used": frac}
        results[gravity] = (n, round(frac, 9), gravity, placements)
    best = min(results.values(), key=lambda r: r[:3])
    log.info("fill: gravity %s chosen (%s)", best[2], tried)
    return best[3], {"gravity": best[2], "tried": tried,
                     "pairs": sum(len(u.members) == 2 for u in units)}
