"""Where a part's id goes on its sheet (SPEC §6 nest): inside the part, between two score lines.

A developed strip is a row of cells, the quads ``A_u A_(u+1) B_(u+1) B_u`` between its rulings
(the score lines) and its outline. A label is a text box (:func:`dgpc_cli.io.dxf.text_box`)
inside one cell, at least :data:`CLEARANCE_MM` plus :data:`CLEARANCE_H` of its height away from
the cell's sides, so it crosses no cut or score line. It goes into the cell nearest the part's
middle that allows nearly (:data:`NEAR_BEST`) the largest height any cell allows, with the
largest height that cell allows, capped at :data:`MAX_TEXT_MM`; the text runs along the strip,
or across it where that allows twice the height (:data:`ACROSS`), and always reads upright. A
cell's largest box is exact for a convex cell (the box's corners against every side's half
plane; a non-convex cell gets the box within all of its sides' half planes, which lies inside
it).

When no cell holds the id at :data:`MIN_TEXT_MM`, the short id (the id without ``S-v``) is
tried; when that does not fit either, the short id goes beside the part, at the minimum
height, where its box meets no part, label or the sheet's edge, with a leader from the box to
the part's label point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon, box
from shapely.ops import nearest_points

from ..io.dxf import text_box

#: Least text height of a label (mm): ids smaller than this are not readable once cut.
MIN_TEXT_MM = 3.0
#: Largest text height of a label (mm).
MAX_TEXT_MM = 50.0
#: A label goes to the cell nearest the middle of its part that allows this fraction of the
#: largest height any cell allows.
NEAR_BEST = 0.9
#: A label runs across its strip only where that allows a height more than 1/ACROSS times the
#: height along it.
ACROSS = 0.5
#: Free space around a label's box: this much (mm) plus this fraction of its height.
CLEARANCE_MM, CLEARANCE_H = 0.5, 0.1
#: Candidate directions and steps (× the text height) of a label beside its part.
AROUND_DIRECTIONS, AROUND_STEPS = 16, 40


@dataclass(frozen=True)
class Label:
    """A label: ``text`` centred at ``at`` with ``height`` and ``rotation`` (degrees), and a
    ``leader`` polyline ``(2, 2)`` when it lies beside its part (None inside)."""

    text: str
    at: tuple[float, float]
    height: float
    rotation: float
    leader: np.ndarray | None = None

    def box(self) -> np.ndarray:
        return text_box(self.text, self.height, self.at, self.rotation)


def upright(deg: float) -> float:
    """A text angle in (−90°, 90°] so labels never read upside down."""
    a = (float(deg) + 90.0) % 180.0 - 90.0
    return 90.0 if a == -90.0 else a


def short_id(part_id: str) -> str:
    """The id without its ``S-v`` prefix (``S-v07.2`` → ``07.2``); in a text of several ids
    separated by spaces, each id's."""
    return " ".join(w[3:] if w.startswith("S-v") else w for w in part_id.split(" "))


def cells(A: np.ndarray, B: np.ndarray) -> list[np.ndarray]:
    """The quads ``(4, 2)`` between consecutive rulings of a developed strip ``A, B (m, 2)``,
    counter-clockwise."""
    out = []
    for u in range(len(A) - 1):
        q = np.array([A[u], A[u + 1], B[u + 1], B[u]])
        x, y = q[:, 0], q[:, 1]
        if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) < 0:
            q = q[::-1]
        out.append(q)
    return out


def largest_height(cell: np.ndarray, center: np.ndarray, text: str, rotation: float) -> float:
    """The largest height of ``text`` turned by ``rotation`` whose box, centred at ``center``
    and with its clearance, lies within every side's half plane of the ccw polygon ``cell``."""
    q = text_box(text, 1.0, (0.0, 0.0), rotation)                  # box at unit height
    q = q - q.mean(axis=0)                                          # ... centred
    edges = np.roll(cell, -1, axis=0) - cell
    normals = np.column_stack([edges[:, 1], -edges[:, 0]])          # outward for ccw
    lengths = np.linalg.norm(normals, axis=1)
    ok = lengths > 0
    normals = normals[ok] / lengths[ok, None]
    offsets = np.einsum("ij,ij->i", normals, cell[ok]) - CLEARANCE_MM - normals @ center
    reach = normals @ q.T + CLEARANCE_H                              # (sides, corners)
    if np.any(offsets < 0):
        return 0.0
    with np.errstate(divide="ignore"):
        bounds = np.where(reach > 0, offsets[:, None] / reach, np.inf)
    return float(bounds.min())


def _inside(text: str, quads: list[np.ndarray], middle: int) -> Label | None:
    """A label of ``text`` inside one of the cells ``quads``: of the cells that allow at least
    :data:`NEAR_BEST` of the largest height, the one nearest the ``middle`` one; None when no
    cell allows the minimum height."""
    options = []
    for u, q in enumerate(quads):
        axis = 0.5 * (q[1] + q[2]) - 0.5 * (q[0] + q[3])
        along = np.degrees(np.arctan2(axis[1], axis[0]))
        center = np.asarray(Polygon(q).centroid.coords[0])
        for rotation, weight in ((upright(along), 1.0), (upright(along + 90.0), ACROSS)):
            h = min(largest_height(q, center, text, rotation), MAX_TEXT_MM)
            if h >= MIN_TEXT_MM:
                options.append((weight * h, -abs(u - middle), u, h, rotation, center))
    if not options:
        return None
    best = max(o[0] for o in options)
    _, _, _, h, rotation, center = max((o for o in options if o[0] >= NEAR_BEST * best),
                                       key=lambda o: (o[1], o[0], -o[2]))
    # the text's point so that its box is centred on the cell's centroid
    at = center - text_box(text, h, (0.0, 0.0), rotation).mean(axis=0)
    return Label(text, (float(at[0]), float(at[1])), h, rotation)


def _with_leader(text: str, at, h: float, anchor: np.ndarray) -> Label:
    end = nearest_points(Polygon(text_box(text, h, at)), Point(anchor))[0]
    return Label(text, (float(at[0]), float(at[1])), h, 0.0, np.array([anchor, [end.x, end.y]]))


def _beside(text: str, anchor: np.ndarray, obstacles, sheet: Polygon) -> Label:
    """The short id at the minimum height beside its part: the nearest free spot on the sheet
    (away from every part and label) around ``anchor``, with a leader to it; right of the
    sheet when the sheet has no room."""
    h = MIN_TEXT_MM
    gap = CLEARANCE_MM + CLEARANCE_H * h
    for step in range(1, AROUND_STEPS + 1):
        for k in range(AROUND_DIRECTIONS):
            a = 2 * np.pi * k / AROUND_DIRECTIONS
            at = anchor + step * h * np.array([np.cos(a), np.sin(a)])
            poly = Polygon(text_box(text, h, at)).buffer(gap)
            if sheet.contains(poly) and not obstacles.intersects(poly):
                return _with_leader(text, at, h, anchor)
    x0, _, x1, _ = sheet.bounds
    at = (x1 + 2 * gap + 0.5 * len(text) * h, float(anchor[1]))
    return _with_leader(text, at, h, anchor)


def place_labels(parts: list[dict], width: float, height: float) -> list[Label]:
    """Labels of the parts placed on one sheet: each ``{"id", "geodesics": (A, B), "outline",
    "score", "label"}`` in sheet mm. Parts whose id fits inside are labelled first; the others
    beside them, clear of every part and of the labels already placed."""
    labels: list[Label | None] = []
    for p in parts:
        A, B = (np.asarray(g, float) for g in p["geodesics"])
        quads = cells(A, B)
        middle = (len(quads) - 1) // 2
        labels.append(_inside(p["id"], quads, middle) or _inside(short_id(p["id"]), quads,
                                                                  middle))
    if all(lb is not None for lb in labels):
        return labels
    shapes = [Polygon(p["outline"]) for p in parts] + \
        [LineString(s) for p in parts for s in p["score"]] + \
        [Polygon(lb.box()) for lb in labels if lb is not None]
    obstacles = shapely.union_all(shapes)
    sheet = box(0.0, 0.0, width, height)
    for i, p in enumerate(parts):
        if labels[i] is None:
            labels[i] = _beside(short_id(p["id"]), np.asarray(p["label"], float), obstacles,
                                sheet)
            obstacles = obstacles.union(Polygon(labels[i].box()))
    return labels
