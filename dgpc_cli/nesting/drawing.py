"""The drawings of ``nest``: cut sheets and the panel-to-mold map (SPEC §6 nest), in mm, written
by :mod:`dgpc_cli.io.dxf` (R2010, audited, deterministic; previews in the layers' colours).

Sheet (origin at the sheet's lower-left corner), layers of :data:`~dgpc_cli.io.dxf.SHEET_LAYERS`:

* ``SHEET_BORDER`` — only with ``border``: the sheet's border, one closed polyline (plotted:
  a CAM that is given it cuts it, so it is there only when asked for);
* ``CUT`` — one closed outline per part, under its placement;
* ``SCORE`` — open polylines, the rulings (bend/score lines);
* ``LABEL`` (``label_style`` text) or ``ENGRAVE`` (stroke) — the part id inside the part
  between two score lines (:mod:`dgpc_cli.nesting.labels`), or its short id beside it with a
  leader: TEXT, or single-stroke polylines an engraver follows; and on the same layer each
  part's end mark (:mod:`dgpc_cli.nesting.end_mark`): a chevron pointing at the part's
  first-row end and that row's number (``R0``).
"""

from __future__ import annotations

import numpy as np

from ..io.dxf import SHEET_LAYERS, Drawing, Layer
from .end_mark import EndMark, beyond, end_mark
from .geometry import transform
from .labels import place_labels

MAP_LAYERS = {"PROFILE": Layer(7), "AXIS": Layer(8, "CENTER"), "SECTOR": Layer(8),
              "PIECES": Layer(6), "PANELS": Layer(4), "LABEL": Layer(3), "TABLE": Layer(7)}


#: ``nest --label-style``: the layer of the labels in each style.
LABEL_LAYER = {"text": "LABEL", "stroke": "ENGRAVE"}


def sheet_layers(border: bool, label_style: str) -> dict[str, Layer]:
    """The layers of a sheet drawn with ``border`` and ``label_style`` (text or stroke)."""
    names = (["SHEET_BORDER"] if border else []) + ["CUT", "SCORE", LABEL_LAYER[label_style]]
    return {name: SHEET_LAYERS[name] for name in names}


def sheet_drawing(width: float, height: float, placed: list[dict], *, border: bool = False,
                  label_style: str = "text") -> tuple[Drawing, list]:
    """The drawing of one sheet and its labels; ``placed`` items have ``id``, ``outline``,
    ``score``, ``label`` and ``geodesics``, all in sheet mm, already placed."""
    d = Drawing(sheet_layers(border, label_style))
    if border:
        d.polyline("SHEET_BORDER", [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)],
                   closed=True)
    for p in placed:
        d.polyline("CUT", p["outline"], closed=True)
        for line in p["score"]:
            d.polyline("SCORE", line)
    marks = [part_end_mark(p) for p in placed]
    labels = place_labels([{**p, "geodesics": beyond(*p["geodesics"], m)}
                           for p, m in zip(placed, marks, strict=True)], width, height)
    draw_labels(d, labels, label_style)
    draw_end_marks(d, marks, label_style)
    return d, labels


def part_end_mark(part: dict) -> EndMark | None:
    """The end mark (:mod:`dgpc_cli.nesting.end_mark`) of a part ``outline``, ``score``,
    ``geodesics`` and ``row`` (its first end's net row) in mm."""
    A, B = part["geodesics"]
    return end_mark(part["outline"], part["score"], A, B, part.get("row", 0))


def draw_end_marks(d: Drawing, marks: list, label_style: str) -> None:
    """Draw the parts' end marks (None: no mark) on the layer of ``label_style``: the chevron
    as a polyline, the row as the labels are drawn."""
    for m in marks:
        if m is not None:
            d.polyline(LABEL_LAYER[label_style], m.chevron)
    draw_labels(d, [m.label for m in marks if m is not None], label_style)


def draw_labels(d: Drawing, labels: list, label_style: str) -> None:
    """Draw placed labels (:class:`~dgpc_cli.nesting.labels.Label`) and their leaders on the
    layer of ``label_style``: TEXT on ``LABEL``, or single strokes on ``ENGRAVE``."""
    layer = LABEL_LAYER[label_style]
    for lb in labels:
        if label_style == "stroke":
            d.stroke_text(layer, lb.text, lb.at, lb.height, lb.rotation)
        else:
            d.text(layer, lb.text, lb.at, lb.height, lb.rotation)
        if lb.leader is not None:
            d.polyline(layer, lb.leader)


def mold_map_drawing(r_mm: np.ndarray, h_mm: np.ndarray, sector_deg: float,
                     pieces: list[dict], panels: list[dict]) -> Drawing:
    """The panel-to-mold map sheet (mm).

    Left: the meridian profile (x = r, y = h) with the axis. Right: the developed sector — the
    meridian arc length s(u) upwards, the parallel arc r(u)·φ across, centred — with each mold
    piece outlined and named, and on it (layer PANELS) where the panels are pressed: one
    outline per band of mold rows, as wide as its panels' angle (the mold is a surface of
    revolution, so every panel of a band fits the same place), labelled with the rows and the
    number of panels. Right of it: a table, per mold piece its panels, then the flat panels
    (no mold) separately, a few ids a line, in a column about as tall as the drawing (texts
    sized to be read on the sheet and in its preview). Lines shared by the pieces, bands and
    the sector are drawn once (the pieces first).
    """
    r_mm, h_mm = np.asarray(r_mm, float), np.asarray(h_mm, float)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(r_mm), np.diff(h_mm)))])
    phi = np.radians(sector_deg)
    size = float(max(np.ptp(h_mm), r_mm.max(), s[-1], 1e-9))
    text = 0.03 * size
    x0 = float(r_mm.max() + 0.3 * size + 0.5 * r_mm.max() * phi)
    d = Drawing(MAP_LAYERS)
    d.polyline("PROFILE", np.column_stack([r_mm, h_mm]))
    d.line("AXIS", (0.0, float(h_mm.min()) - 0.05 * size),
           (0.0, float(h_mm.max()) + 0.05 * size))
    d.text("LABEL", "meridian profile", (0.0, float(h_mm.max()) + 0.1 * size), text,
           align="MIDDLE_LEFT")
    half = 0.5 * r_mm * phi
    left = np.column_stack([x0 - half, s])
    right = np.column_stack([x0 + half, s])
    for piece in pieces:
        a, b = piece["rows"]
        d.polyline("PIECES", np.concatenate([left[a:b + 1], right[a:b + 1][::-1]]),
                   closed=True)
        d.text("LABEL", piece["id"], (x0, float(s[(a + b) // 2])), text)
    for (a, b), width_deg, count in panel_bands(panels):
        half_p = 0.5 * r_mm[a:b + 1] * np.radians(width_deg)
        d.polyline("PANELS", np.concatenate([np.column_stack([x0 - half_p, s[a:b + 1]]),
                                             np.column_stack([x0 + half_p,
                                                              s[a:b + 1]])[::-1]]),
                   closed=True)
        d.text("LABEL", f"rows {a}-{b}: {count} panels",
               (x0 + float(half.max()) + 0.02 * size, 0.5 * float(s[a] + s[b])),
               min(0.6 * text, 0.8 * float(s[b] - s[a])), align="MIDDLE_LEFT")
    d.polyline("SECTOR", np.concatenate([left, right[::-1]]), closed=True)
    d.text("LABEL", f"developed sector {sector_deg:.4g} deg",
           (x0 - float(half.max()), float(s[-1]) + 0.1 * size), text, align="MIDDLE_LEFT")
    # the table right of the bands' labels, from the top of the drawing down
    top = float(max(h_mm.max(), s[-1])) + 0.1 * size
    sector_label = f"developed sector {sector_deg:.4g} deg"
    x_table = max(x0 + float(half.max()) + 0.02 * size + 22 * 0.6 * 0.6 * text,
                  x0 - float(half.max()) + len(sector_label) * 0.65 * text) + 0.05 * size
    lines = map_table(pieces, panels, per_line=4)
    step = max(1.3 * 0.5 * text, 1.0 * size / max(len(lines), 1))
    step = min(step, 1.3 * 0.6 * text)
    y = top
    for line in lines:
        d.text("TABLE", line, (x_table, y), step / 1.3, align="MIDDLE_LEFT")
        y -= step
    return d


def panel_bands(panels: list[dict]) -> list[tuple[tuple[int, int], float, int]]:
    """The bands of mold rows the curved panels are pressed on: ``((first, last) row, widest
    panel angle in degrees, number of panels)``, by first row."""
    bands: dict[tuple[int, int], list[float]] = {}
    for p in panels:
        if p["piece"] is not None:
            a0, a1 = p["angle_deg"]
            bands.setdefault(tuple(p["rows"]), []).append(abs(a1 - a0))
    return [(rows, max(w), len(w)) for rows, w in sorted(bands.items())]


def map_table(pieces: list[dict], panels: list[dict], per_line: int = 8) -> list[str]:
    """The table of the map: per mold piece its rows and panels, then the flat panels."""
    lines = ["panels per mold piece"]
    for piece in pieces:
        ids = [p["id"] for p in panels if p["piece"] == piece["id"]]
        head = f"{piece['id']} rows {piece['rows'][0]}-{piece['rows'][1]} ({len(ids)} panels):"
        lines += _wrapped(head, ids, per_line)
    flat = [p["id"] for p in panels if p["flat"]]
    lines += _wrapped(f"flat panels, no mold ({len(flat)}):", flat, per_line)
    return lines


def _wrapped(head: str, ids: list[str], per_line: int) -> list[str]:
    if not ids:
        return [f"{head} none"]
    chunks = [", ".join(ids[i:i + per_line]) for i in range(0, len(ids), per_line)]
    return [f"{head} {chunks[0]}"] + [f"    {c}" for c in chunks[1:]]


def placed_part(part, rotation: float, translation) -> dict:
    """A part's outline, score lines, label point and geodesics under its placement (mm),
    and the net row of its first end."""
    return {"id": part.id, "rotation": rotation,
            "outline": transform(part.outline, rotation, translation),
            "score": [transform(s, rotation, translation) for s in part.score],
            "label": transform(part.label, rotation, translation),
            "geodesics": [transform(g, rotation, translation) for g in part.geodesics],
            "row": part.row}
