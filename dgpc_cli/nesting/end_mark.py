"""The end mark of a part (SPEC §6 nest, unfold templates): which end of the part is its first
row's, so an installer does not mount a part end-for-end (its taper and rulings reversed
against its neighbours).

The mark lies inside the part's first cell (the quad between its first-row end and its first
score line; the second where the first is too short, within the part's first half), on the
labels' layer, on the part's axis whatever the part's aspect ratio: a chevron whose apex
points along the part at its first-row end, and beyond it, along the part, the row's number
(``R0``) read upright (beside the chevron, across the part, only where neither cell has room
for it along the part: cells a few mm long). The axis is the mean direction of the part's two
geodesics over its first cell (:func:`_frame`). Where the first cell is short on one side (a
slanted ruling: a trapezoid) the mark moves across the part towards its long side
(:data:`ACROSS`) rather than turn. It is as large as the part's width at that end allows
(:data:`WIDTH_FRACTION`, capped at the labels' :data:`MAX_TEXT_MM`), shrunk until it keeps
the labels' clearance (:data:`CLEARANCE_MM` plus :data:`CLEARANCE_H` of its height) from the
cut outline and every score line; on a part of one cell it keeps to the first
:data:`ONE_CELL_REACH` of the cell. A part too small for a mark of :data:`MIN_MARK_MM` gets
none. The part's id label then goes beyond the mark (:func:`beyond`).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from ..io.dxf import text_box
from .labels import CLEARANCE_H, CLEARANCE_MM, MAX_TEXT_MM, Label, upright

#: Height of the mark (its row number's text, and the chevron's width) as a fraction of the
#: part's width at its first-row end.
WIDTH_FRACTION = 0.3
#: Least height (mm) of a mark; a part without room for it gets none.
MIN_MARK_MM = 1.5
#: On a part of one cell, the mark keeps to this fraction of its length from the first row.
ONE_CELL_REACH = 0.45
#: Tried heights: the largest times these factors, largest first.
SHRINK = 0.85 ** np.arange(24)
#: Tried offsets of the mark across the part, as fractions of its width at the first end,
#: nearest the axis first.
ACROSS = np.array([0.0, 0.125, -0.125, 0.25, -0.25, 0.375, -0.375])


@dataclass(frozen=True)
class EndMark:
    """A part's end mark: the ``chevron`` polyline ``(3, 2)`` pointing at its first-row end,
    the row's ``label``, ``reach`` how far (mm) from that end, along the part, it and its
    clearance extend, and the ``cell`` it lies in (0 the first)."""

    chevron: np.ndarray
    label: Label
    reach: float
    cell: int = 0


def _frame(A: np.ndarray, B: np.ndarray):
    """The first-row end's midpoint, the unit direction into the part along its axis (the
    mean of its two geodesics' directions over the first cell), the unit normal, the end's
    width."""
    e = 0.5 * (A[0] + B[0])
    d = np.zeros(2)
    for t in (A[1] - A[0], B[1] - B[0]):
        size = float(np.linalg.norm(t))
        if size > 0:                           # a pointed end: the other geodesic only
            d = d + t / size
    if not np.linalg.norm(d) > 1e-9:           # degenerate: the midpoints' direction
        d = 0.5 * (A[1] + B[1]) - e
    d = d / np.linalg.norm(d)
    n = np.array([-d[1], d[0]])
    return e, d, n, float(abs((B[0] - A[0]) @ n))


def _shapes(e, d, n, t: float, s: float, h: float, text: str, beside: bool = False):
    """The chevron (apex at ``e + t d + s n``, opening along ``d``) and the row's label at
    height ``h``: beyond it along the part, reading along the part; or, ``beside`` it (the
    last resort of a cell too short for that), across the part."""
    apex = e + t * d + s * n
    gap = CLEARANCE_MM + CLEARANCE_H * h
    chevron = np.array([apex + 0.6 * h * d + 0.5 * h * n, apex, apex + 0.6 * h * d - 0.5 * h * n])
    along = np.degrees(np.arctan2(d[1], d[0]))
    rotation = upright(along + 90.0 if beside else along)
    box = text_box(text, h, (0.0, 0.0), rotation)
    if beside:
        half = 0.5 * float(np.ptp(box @ n))
        center = apex + 0.3 * h * d + (0.5 * h + gap + half) * n
    else:
        half = 0.5 * float(np.ptp(box @ d))
        center = apex + (0.6 * h + gap + half) * d
    at = center - box.mean(axis=0)
    return chevron, Label(text, (float(at[0]), float(at[1])), h, rotation)


def row_text(row: float) -> str:
    """The end mark's text for the first row ``row``: ``R4``, or ``R3.55`` where a joint cuts
    the part inside a quad (a fractional row, to two decimals)."""
    return "R" + f"{float(row):.2f}".rstrip("0").rstrip(".")


def end_mark(outline, score, A, B, row: float) -> EndMark | None:
    """The end mark of a part (``outline``, ``score`` lines, geodesics ``A, B (m, 2)`` in mm,
    its first row ``row`` at ``A[0], B[0]``, fractional where a joint cuts it inside a quad)
    in its first cell, or in its second where the first (a board's end cut just short of a
    ruling) is too short, never beyond the part's half-length; None when no mark of
    :data:`MIN_MARK_MM` fits."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    if len(A) < 2:
        return None
    e, d, n, width = _frame(A, B)
    room = Polygon(np.asarray(outline, float))
    if not room.is_valid:
        room = room.buffer(0)
    lines = [LineString(np.asarray(s, float)) for s in score if len(s) >= 2]
    scored = shapely.union_all(lines) if lines else None
    top = min(WIDTH_FRACTION * width, MAX_TEXT_MM)
    half = 0.5 * min(float((A[-1] - e) @ d), float((B[-1] - e) @ d))
    cells = []
    for k in (0, 1) if len(A) >= 3 else (0,):
        cell = Polygon([A[k], A[k + 1], B[k + 1], B[k]]).buffer(0).buffer(1e-9)
        near = max(float((A[k] - e) @ d), float((B[k] - e) @ d))    # past a slanted end
        # to the cell's far side where it is longest: across the part the mark moves there
        # (the cell itself bounds it)
        limit = max(float((A[k + 1] - e) @ d), float((B[k + 1] - e) @ d))
        if len(A) == 2:
            limit = near + ONE_CELL_REACH * (limit - near)
        limit = min(limit, half)                     # nearer the first end than the other
        cells.append((k, cell, near, limit))
    # the number along the part in the first cell, else the second; only where neither has
    # room for that, beside the chevron (a cell a few mm long: a scale model's)
    for beside, (k, cell, near, limit) in product((False, True), cells):
        found = _fit(e, d, n, top, width, near, limit, row_text(row), room, cell, scored,
                     beside)
        if found is not None:
            return EndMark(*found, cell=k)
    return None


def _fit(e, d, n, top, width, near, limit, text, room, cell, scored, beside=False):
    """``(chevron, label, reach)`` of the largest mark from ``near`` to ``limit`` along ``d``
    inside ``room`` and ``cell`` with its clearance, crossing no ``scored`` line, at an offset
    across the part of :data:`ACROSS` × ``width`` (its label ``beside`` the chevron or not,
    :func:`_shapes`); None."""
    for h in min(top, (limit - near) / 0.7) * SHRINK:    # the chevron alone is 0.6 h deep
        if h < MIN_MARK_MM:
            return None
        gap = CLEARANCE_MM + CLEARANCE_H * h
        for s, t in product(ACROSS * width, near + gap + h * np.arange(0.0, 4.0, 0.25)):
            chevron, label = _shapes(e, d, n, t, s, h, text, beside)
            far = float(np.max(np.concatenate([chevron, label.box()]) @ d - e @ d)) + gap
            if far > limit:
                continue
            zone = shapely.union_all([LineString(chevron), Polygon(label.box())]).buffer(gap)
            if room.contains(zone) and cell.contains(zone) and \
                    (scored is None or not scored.intersects(zone)):
                return chevron, label, far
    return None


def beyond(A, B, mark: EndMark | None):
    """The geodesics ``A, B`` the part's id label may use: from the ``mark``'s cell on,
    without the part of that cell the mark takes (without the cell when it takes it all)."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    if mark is None or mark.cell >= len(A) - 1:                 # not in these cells
        return A, B
    e, d, _, _ = _frame(A, B)
    A, B = A[mark.cell:], B[mark.cell:]
    cut = []
    for G in (A, B):
        step = float((G[1] - G[0]) @ d)
        f = (mark.reach - float((G[0] - e) @ d)) / step if step > 0 else 1.0
        cut.append(f)
    f = max(cut)
    if f >= 1.0 - 1e-9:
        return (A[1:], B[1:]) if len(A) > 2 else (A, B)
    f = max(f, 0.0)
    A2, B2 = A.copy(), B.copy()
    A2[0], B2[0] = A[0] + f * (A[1] - A[0]), B[0] + f * (B[1] - B[0])
    return A2, B2
