"""Figures of the developed parts (paper Fig. 18, bottom): the overlay per congruence class and
the parts laid out like sheets, both on one page with labels legible at 100 %.

Every drawing turns a part (or a class) so that its longest extent runs across the page (the
principal axis of its outline); the parts of a flat artifact are long strips, and a strip laid
across needs the least height.

* :func:`overlay_figure`: one cell per congruence class in a grid chosen to fit
  :data:`PAGE` (the cells as large as the page allows); in each cell every member of the class
  moved onto the representative (its recorded alignment), outlines and rulings, the title naming
  the class, its quantity, representative and largest error.
* :func:`layout_figure`: the parts in rows like a sheet (shelf layout in id order, the row width
  chosen so that the layout's shape is the page's), each outline with its rulings and its id and
  class at its label point, and a scale bar.
"""

from __future__ import annotations

import math

import numpy as np

from ..io.units import mm_per_unit, nice_length
from .render import figure
from .views import scale_bar_at
from .words import counted

__all__ = ["PAGE", "error_text", "layout_figure", "overlay_figure", "principal_rotation"]

#: Page width and largest page height (inches): a portrait sheet of paper.
PAGE = (8.0, 10.5)
#: Font sizes (points): titles, labels.
TITLE_PT, LABEL_PT, SMALL_PT = 11, 8, 7
#: Colours: outline (cut), rulings (score), fill.
CUT, SCORE, FILL = (0.8, 0.0, 0.0), (0.0, 0.0, 0.85), (0.95, 0.95, 0.95)
#: Gap between parts in the layout, as a fraction of the tallest part.
GAP = 0.35
#: Height (inches) of the band under the overlay's cells that holds its scale bar.
BAR_BAND = 0.45
#: Narrowest overlay cell (inches): with more classes than fit so, the overlay draws those of
#: the largest quantity and says how many it leaves out (every class is in the cut list).
MIN_CELL = 0.8
#: Least height (inches) of a part's drawing in an overlay cell (over the cell's title).
MIN_DRAWING = 0.06


def principal_rotation(points: np.ndarray) -> np.ndarray:
    """The 2×2 rotation that turns the principal axis of ``points (k, 2)`` onto x (the sign
    fixed so that the result is deterministic)."""
    p = np.asarray(points, float)
    q = p - p.mean(axis=0)
    _, vecs = np.linalg.eigh(q.T @ q)
    axis = vecs[:, 1]
    if axis[int(np.argmax(np.abs(axis)))] < 0:
        axis = -axis
    c, s = axis
    return np.array([[c, s], [-s, c]])


def _closed(ring: np.ndarray) -> np.ndarray:
    return np.concatenate([ring, ring[:1]])


def _aligned(part: dict, points) -> np.ndarray:
    al = part["alignment"]
    R, t = np.asarray(al["matrix"], float), np.asarray(al["translation"], float)
    return np.asarray(points, float) @ R.T + t


def _grid_shape(count: int, aspect: float) -> tuple[int, int, float]:
    """``(columns, rows, cell width in inches)`` of the grid of ``count`` cells of drawing
    ``aspect`` (width / height) plus a title line, largest cells that fit :data:`PAGE`."""
    best = (1, count, 0.0)
    title = 0.32
    for cols in range(1, count + 1):
        rows = math.ceil(count / cols)
        width = PAGE[0] / cols
        height = width / aspect + title
        if rows * height > PAGE[1] - 0.6:
            width = ((PAGE[1] - 0.6) / rows - title) * aspect
            if width <= 0:
                continue
        if width > best[2]:
            best = (cols, rows, width)
    return best


def shown_classes(classes: list[dict], aspect: float) -> list[dict]:
    """The classes the overlay draws: all of them where every cell fits :data:`PAGE` at least
    :data:`MIN_CELL` wide (its drawing :data:`MIN_DRAWING` tall), else as many as do, those of
    the largest quantity first (ties by id), in their own order."""

    def legible(count: int) -> bool:
        width = _grid_shape(count, aspect)[2]
        return width >= MIN_CELL and width / aspect >= MIN_DRAWING

    count = len(classes)
    while count > 1 and not legible(count):
        count -= 1
    keep = {id(c) for c in sorted(classes, key=lambda c: -c["quantity"])[:count]}
    return [c for c in classes if id(c) in keep]


def error_text(error: float, units: str) -> str:
    """A class's largest error ``error`` (in ``units``) as a length in mm, e.g. ``0.031 mm``
    (errors of congruent parts are well under a millimetre, whatever the model's unit)."""
    mm = float(error) * mm_per_unit(units)
    return "0 mm" if mm == 0 else f"{mm:.2g} mm"


def overlay_figure(parts: list[dict], classes: list[dict], units: str):
    """All parts aligned on their class representatives, one cell (axes gid ``class-<id>``)
    per congruence class, every cell at one scale, with a scale bar (gid ``scale-bar``) under
    the grid; the score lines are the representative's (a class whose copies are scored each
    for its own bending says so in its title)."""

    by_id = {p["id"]: p for p in parts}
    drawings = []
    for cls in classes:
        rep = by_id[cls["representative"]]
        R = principal_rotation(np.asarray(rep["outline"], float))
        members = [by_id[pid] for pid in cls["members"]]
        outlines = [_aligned(p, p["outline"]) @ R.T for p in members]
        scores = [[_aligned(p, seg) @ R.T for seg in p["score"]] for p in members]
        drawings.append((cls, outlines, scores))
    extents = [np.ptp(np.concatenate(o), axis=0) for _, o, _ in drawings]
    aspect = max(max(e[0] / max(e[1], 1e-12 * e[0]) for e in extents), 1.0)
    every, classes = classes, shown_classes(classes, aspect)
    shown = {id(c) for c in classes}
    kept = [k for k, (c, _, _) in enumerate(drawings) if id(c) in shown]
    drawings, extents = [drawings[k] for k in kept], [extents[k] for k in kept]
    cols, rows, width = _grid_shape(len(classes), aspect)
    cell_h = width / aspect + 0.32
    fig = figure(PAGE[0], min(PAGE[1], rows * cell_h + 0.9) + BAR_BAND)
    W, H = fig.get_size_inches()
    span = max(float(e[0]) for e in extents)                 # one scale for every class
    ratio = (cell_h - 0.36) / (width - 0.1)                  # the axes' height over width
    # the longest part fills the width, and no part is taller than the axes (a part whose
    # height fills the cell would lose its top edge to the axes' frame): one half height for
    # every cell, so that every cell has the same scale
    half_h = max(0.52 * span * ratio, 0.52 * max(float(e[1]) for e in extents))
    half_w = half_h / ratio
    for k, (cls, outlines, scores) in enumerate(drawings):
        r, c = divmod(k, cols)
        left = (c * width + 0.05) / W
        bottom = (H - 0.55 - (r + 1) * cell_h + 0.04) / H
        ax = fig.add_axes((left, bottom, (width - 0.1) / W, (cell_h - 0.36) / H))
        ax.set_gid(f"class-{cls['id']}")
        for outline in outlines:
            ax.plot(*_closed(outline).T, lw=1.0, color=CUT, alpha=0.8)
        # the representative's score lines once: shared ones coincide on every copy, and a
        # copy's own ones (``per copy``) are on its own DXF, not stacked here
        for seg in scores[cls["members"].index(cls["representative"])]:
            ax.plot(*seg.T, lw=0.6, color=SCORE, alpha=0.8)
        allp = np.concatenate(outlines)
        mid = 0.5 * (allp.min(axis=0) + allp.max(axis=0))
        ax.set_xlim(mid[0] - half_w, mid[0] + half_w)
        ax.set_ylim(mid[1] - half_h, mid[1] + half_h)
        ax.set_aspect("equal", adjustable="box")
        ax.set_axis_off()
        per_copy = cls.get("score_lines") == "per copy"
        scored = (f" (each scored for its bending, {cls['representative']}'s shown)"
                  if per_copy and cls["quantity"] > 1 else "")
        ax.set_title(f"{cls['id']}: {cls['quantity']} × {cls['representative']}{scored}, "
                     f"error ≤ {error_text(cls['max_error'], units)}", fontsize=LABEL_PT,
                     pad=2)
    # the scale bar, in an axes as wide as a cell and at the cells' scale
    bar_ax = fig.add_axes((0.05 / W, 0.1 / H, (width - 0.1) / W, 0.3 / H))
    bar_ax.set_gid("scale-bar-axes")
    bar_ax.set_xlim(0.0, 2 * half_w)
    bar_ax.set_ylim(0.0, 1.0)
    bar_ax.set_axis_off()
    scale_bar_at(bar_ax, 0.05 * half_w, 0.75, nice_length(0.25 * span), units, LABEL_PT)
    left_out = (f" ({len(classes)} of the largest quantity shown, {len(every) - len(classes)} "
                "more in the cut list)" if len(classes) < len(every) else "")
    fig.suptitle(f"{counted(len(parts), 'part')} in "
                 f"{counted(len(every), 'congruence class', 'congruence classes')}{left_out}, "
                 "each overlaid on "
                 f"its representative (one scale, length of the longest "
                 f"{span:.4g} {units}; error: largest distance between matching outline "
                 "points)", fontsize=TITLE_PT - 1, y=0.995, wrap=True)
    _cut_score_legend(fig, H, "outlines (cut)", "rulings (score)")
    return fig


def _cut_score_legend(fig, height: float, cut: str, score: str) -> None:
    """The legend of the CUT and SCORE line colours, top right of a figure ``height`` inches
    tall."""
    from matplotlib.lines import Line2D

    fig.legend(handles=[Line2D([], [], color=CUT, lw=1, label=cut),
                        Line2D([], [], color=SCORE, lw=1, label=score)],
               loc="upper right", bbox_to_anchor=(0.995, 1.0 - 0.3 / height), ncol=2,
               fontsize=SMALL_PT, frameon=False)


def _shelves(sizes: np.ndarray, width: float, gap: float) -> tuple[np.ndarray, float, float]:
    """Lower-left corners ``(k, 2)`` of boxes ``sizes (k, 2)`` in rows no wider than
    ``width`` (in the given order, each row as tall as its tallest box), the layout's width
    and height."""
    corners = np.zeros_like(sizes)
    x = y = row_h = used = 0.0
    for i, (w, h) in enumerate(sizes):
        if x > 0 and x + w > width:
            y += row_h + gap
            x = row_h = 0.0
        corners[i] = (x, y)
        x += w + gap
        used = max(used, x - gap)
        row_h = max(row_h, h)
    return corners, used, y + row_h


def layout_figure(parts: list[dict], units: str):
    """The parts in rows like a sheet (:func:`_shelves`), each turned across the page, with
    rulings, id and class (texts of gid ``part-label:<id>``)."""

    turned = []
    for p in parts:
        outline = np.asarray(p["outline"], float)
        R = principal_rotation(outline)
        o = outline @ R.T
        lo = o.min(axis=0)
        turned.append((p, o - lo, [np.asarray(s, float) @ R.T - lo for s in p["score"]],
                       np.asarray(p["label"], float) @ R.T - lo))
    sizes = np.array([np.ptp(o, axis=0) for _, o, _, _ in turned])
    order = sorted(range(len(parts)), key=lambda i: parts[i]["id"])
    gap = GAP * float(sizes[:, 1].max())
    target = PAGE[0] / (PAGE[1] - 1.0)
    best = None
    for width in np.unique(np.concatenate([sizes[:, 0], np.cumsum(sizes[order, 0])])):
        if width < sizes[:, 0].max():
            continue
        corners, w, h = _shelves(sizes[order], float(width), gap)
        score = abs(math.log((w / h) / target))
        if best is None or score < best[0] - 1e-12:
            best = (score, corners, w, h)
    _, corners, w, h = best
    fig_h = min(PAGE[1], max(3.0, PAGE[0] * h / w + 1.0))
    fig = figure(PAGE[0], fig_h)
    ax = fig.add_axes((0.02, 0.02, 0.96, 1.0 - 0.9 / fig_h))
    ax.set_gid("layout")
    # rows run down the page: a part's corner measured from the top, the y axis kept upright
    # (an inverted axis would draw every part mirror-imaged against the DXF)
    corners = np.column_stack([corners[:, 0], h - corners[:, 1] - sizes[order, 1]])
    for (p, o, segs, label), corner in zip([turned[i] for i in order], corners, strict=True):
        ax.fill(*(o + corner).T, facecolor=FILL, edgecolor=CUT, lw=0.6, gid=f"part:{p['id']}")
        for seg in segs:
            ax.plot(*(seg + corner).T, lw=0.35, color=SCORE)
        lx, ly = label + corner
        ax.text(lx, ly, f"{p['id']} ({p['class']})", fontsize=LABEL_PT, ha="center",
                va="center", gid=f"part-label:{p['id']}",
                bbox={"boxstyle": "square,pad=0.1", "facecolor": FILL, "edgecolor": "none",
                      "alpha": 0.8})
    ax.set_xlim(-gap, w + gap)
    ax.set_ylim(-gap, h + gap)                           # first row on top, y up
    ax.set_aspect("equal", adjustable="box")
    ax.set_axis_off()
    scale_bar_at(ax, 0.0, -0.6 * gap, nice_length(w / 4), units, LABEL_PT)
    fig.suptitle(f"{len(parts)} developed parts laid out like a sheet (in id order), "
                 f"with rulings, id and class", fontsize=TITLE_PT - 1, y=0.995)
    _cut_score_legend(fig, fig_h, "outline (cut)", "ruling (score)")
    return fig
