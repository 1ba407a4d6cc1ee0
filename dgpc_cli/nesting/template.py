"""The drawing of one cutting template (``unfold``: ``FLAT.C01.dxf``, SPEC §6): a congruence
class's representative alone, in mm, on the layers of the cut sheets
(:data:`~dgpc_cli.io.dxf.SHEET_LAYERS`: ``CUT`` its closed outline, ``SCORE`` its rulings,
``LABEL`` the class id placed as on a sheet, :mod:`dgpc_cli.nesting.labels`), for shops that
nest the parts themselves. The part lies with the lower-left corner of its bounding box at the
origin; no sheet border.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..io.dxf import SHEET_LAYERS, Drawing
from .labels import MIN_TEXT_MM, place_labels

#: Room (× the least label height) around the part where a label that does not fit inside it
#: may go.
ROOM = 20.0


def template_drawing(part: dict, text: str) -> Drawing:
    """The template drawing of ``part`` (a flat part record in mm: ``outline``, ``score``,
    ``label``, ``geodesics``) labelled ``text``; see the module."""
    shift = -np.asarray(part["outline"], float).min(axis=0)
    room = ROOM * MIN_TEXT_MM
    placed = {"id": text,
              "outline": np.asarray(part["outline"], float) + shift,
              "score": [np.asarray(s, float) + shift for s in part["score"]],
              "label": np.asarray(part["label"], float) + shift,
              "geodesics": [np.asarray(g, float) + shift for g in part["geodesics"]]}
    width, height = np.ptp(placed["outline"], axis=0)
    moved = {**placed, **{k: [x + room for x in placed[k]] for k in ("score", "geodesics")},
             "outline": placed["outline"] + room, "label": placed["label"] + room}
    (label,) = place_labels([moved], width + 2 * room, height + 2 * room)
    label = replace(label, at=(label.at[0] - room, label.at[1] - room),
                    leader=None if label.leader is None else label.leader - room)
    d = Drawing(SHEET_LAYERS)
    d.polyline("CUT", placed["outline"], closed=True)
    for line in placed["score"]:
        d.polyline("SCORE", line)
    d.text("LABEL", label.text, label.at, label.height, label.rotation)
    if label.leader is not None:
        d.polyline("LABEL", label.leader)
    return d
