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
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..io.dxf import Drawing
from .drawing import draw_labels, sheet_layers
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


def template_drawing(part: dict, cls: dict, label_style: str = "text") -> Drawing:
    """The template drawing of ``part`` (a flat part record in mm: ``outline``, ``score``,
    ``label``, ``geodesics``), the representative of class ``cls``, labelled in
    ``label_style`` (``text`` or ``stroke``); see the module."""
    outline = np.asarray(part["outline"], float)
    room = ROOM * MIN_TEXT_MM
    shift = room - outline.min(axis=0)               # labelled on a sheet with room around
    outline = outline + shift
    score = [np.asarray(s, float) + shift for s in part["score"]]
    A, B = (np.asarray(g, float) + shift for g in part["geodesics"])
    texts = template_texts(cls, len(A) - 1)
    pieces = [{"id": text, "outline": outline, "score": score,
               "label": np.asarray(part["label"], float) + shift,
               "geodesics": (A[a:b + 1], B[a:b + 1])}
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
    return d
