"""The drawing of one cutting template (``unfold``: ``FLAT.C01.dxf``, SPEC §6): a congruence
class's representative alone, in mm, drawn as a part on a cut sheet (:mod:`.drawing`: ``CUT``
its closed outline, ``SCORE`` its rulings, the labels as TEXT on ``LABEL`` or single strokes on
``ENGRAVE`` by the label style), for shops that nest the parts themselves. The part lies with
the lower-left corner of its bounding box at the origin; no sheet border.

Its labels (:func:`template_texts`) name the class and its quantity (``C01 x12``) and then its
copies' ids, a few a line; each goes into its own run of the part's cells (the quads between
two score lines; :func:`cell_runs`, the first run the class's), placed there as a sheet places
a part's id
(:func:`~dgpc_cli.nesting.labels.place_labels`: inside the part clear of every cut and score
line, else its short form, else beside the part with a leader).

A class whose copies do not share their score lines (the strips of a shared-outline template,
each bent along its own rulings) gets one drawing per copy instead (:func:`copy_drawing`:
``FLAT.C01.S-v03.dxf``): the same outline in the same place in every copy's file, the copy's
own score lines, labelled with the copy's id and ``C01 copy 3 of 12``. One file with every
copy's score lines on layers of their own would be scored whole on every copy by a CAM that
takes all layers.

Every drawing carries the part's end mark (:mod:`.end_mark`: a chevron pointing at the part's
first-row end and that row's number), as a sheet does.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..io.dxf import Drawing
from ..io.flat import first_row
from .drawing import draw_end_marks, draw_labels, part_end_mark, sheet_layers
from .end_mark import beyond
from .labels import MIN_TEXT_MM, place_labels

#: Room (× the least label height) around the part where a label that does not fit inside it
#: may go.
ROOM = 20.0
#: Most copies' ids on one label line.
IDS_PER_LINE = 4


def template_texts(cls: dict, cells: int) -> list[str]:
    """The label lines of the template of class ``cls`` (``id``, ``quantity``, ``members``)
    whose part has ``cells`` cells: ``C01 x12`` and the copies' ids, at most
    :data:`IDS_PER_LINE` a line and at most one line per other cell (all on the class's line
    when the part has one cell)."""
    head = f"{cls['id']} x{cls['quantity']}"
    ids = list(cls["members"])
    if cells < 2:
        return [f"{head}: {' '.join(ids)}"]
    lines = min(cells - 1, -(-len(ids) // IDS_PER_LINE))
    per = -(-len(ids) // lines)
    return [head] + [" ".join(ids[i:i + per]) for i in range(0, len(ids), per)]


def cell_runs(A: np.ndarray, B: np.ndarray, k: int) -> list[tuple[int, int]]:
    """``k`` runs ``(first, last)`` of consecutive rows of the part ``A, B (m, 2)`` that cover
    its cells, in order, each around one of the ``k`` cells longest along the part (the
    shorter of its two geodesic edges; nearer the middle first on a tie): a label line placed
    in a run then has a roomy cell."""
    along = np.minimum(np.linalg.norm(np.diff(A, axis=0), axis=1),
                       np.linalg.norm(np.diff(B, axis=0), axis=1))
    middle = 0.5 * (len(along) - 1)
    best = sorted(sorted(range(len(along)), key=lambda u: (-along[u], abs(u - middle)))[:k])
    cuts = [0] + [(a + b) // 2 + 1 for a, b in zip(best[:-1], best[1:], strict=True)]
    ends = cuts[1:] + [len(along)]
    return [(a, b) for a, b in zip(cuts, ends, strict=True)]


def copy_texts(cls: dict, part_id: str, cells: int) -> list[str]:
    """The label lines of the drawing of one copy ``part_id`` of class ``cls`` (whose copies
    have their own score lines) on a part of ``cells`` cells: the copy's id, as on a sheet,
    then ``C01 copy 3 of 12`` (one line on a part of one cell)."""
    k = list(cls["members"]).index(part_id) + 1
    lines = [part_id, f"{cls['id']} copy {k} of {cls['quantity']}"]
    return lines if cells > 1 else [" ".join(lines)]


def template_drawing(part: dict, cls: dict, label_style: str = "text") -> Drawing:
    """The template drawing of ``part`` (a flat part record in mm: ``outline``, ``score``,
    ``label``, ``geodesics``), the representative of class ``cls``, labelled in
    ``label_style`` (``text`` or ``stroke``) with the class, its quantity and its copies' ids;
    see the module."""
    outline = np.asarray(part["outline"], float)
    cells = len(part["geodesics"][0]) - 1
    return _drawing(part, outline.min(axis=0), template_texts(cls, cells), label_style)


def copy_drawing(part: dict, rep: dict, cls: dict, label_style: str = "text") -> Drawing:
    """The drawing of one copy ``part`` of class ``cls`` whose representative is ``rep`` (flat
    part records in mm), for a class whose copies do not share their score lines: the copy's
    own outline and score lines carried onto the representative by its ``alignment`` (the
    motion unfold found for the class), in the representative's drawing's frame, so every
    copy's file has the same cut outline and its own score lines; labelled with its id and
    class (:func:`copy_texts`)."""
    R = np.asarray(part["alignment"]["matrix"], float)
    t = np.asarray(part["alignment"]["translation"], float)

    def move(x):
        return np.asarray(x, float) @ R.T + t

    outline = move(part["outline"])
    moved = {"outline": outline[::-1] if np.linalg.det(R) < 0 else outline,
             "score": [move(s) for s in part["score"]], "label": move(part["label"]),
             "geodesics": [move(g) for g in part["geodesics"]], "rows": part.get("rows", [0])}
    low = np.asarray(rep["outline"], float).min(axis=0)
    texts = copy_texts(cls, part["id"], len(part["geodesics"][0]) - 1)
    return _drawing(moved, low, texts, label_style)


def _drawing(part: dict, low: np.ndarray, texts: list[str], label_style: str) -> Drawing:
    """One part (``outline``, ``score``, ``label``, ``geodesics`` in mm) drawn with ``low`` at
    the origin, the label lines ``texts`` each in its own run of cells."""
    room = ROOM * MIN_TEXT_MM
    shift = room - np.asarray(low, float)            # labelled on a sheet with room around
    outline = np.asarray(part["outline"], float) + shift
    score = [np.asarray(s, float) + shift for s in part["score"]]
    A, B = (np.asarray(g, float) + shift for g in part["geodesics"])
    mark = part_end_mark({"outline": outline, "score": score, "geodesics": (A, B),
                          "row": first_row(part)})
    pieces = [{"id": text, "outline": outline, "score": score,
               "label": np.asarray(part["label"], float) + shift,
               "geodesics": beyond(A[a:b + 1], B[a:b + 1], mark if a == 0 else None)}
              for text, (a, b) in zip(texts, cell_runs(A, B, len(texts)), strict=True)]
    width, height = np.ptp(outline, axis=0) + 2 * room
    labels = [replace(lb, at=(lb.at[0] - room, lb.at[1] - room),
                      leader=None if lb.leader is None else lb.leader - room)
              for lb in place_labels(pieces, width, height)]
    d = Drawing(sheet_layers(False, label_style))
    d.polyline("CUT", outline - room, closed=True)
    for line in score:
        d.polyline("SCORE", line - room)
    draw_labels(d, labels, label_style)
    if mark is not None:
        draw_end_marks(d, [replace(mark, chevron=mark.chevron - room,
                                   label=replace(mark.label, at=(mark.label.at[0] - room,
                                                                 mark.label.at[1] - room)))],
                       label_style)
    return d
