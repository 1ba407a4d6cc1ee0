"""``dgpc report`` for a flat artifact: figures of the developed strips (paper Fig. 18 bottom).

* overlay: every part aligned on its class representative (Fig. 18 bottom-right: "Overlay of all
  strips ... implying congruent strips"), one panel per class;
* strips: the parts side by side, each with its rulings (score lines) and id (Fig. 18
  bottom-left).

Rendered with matplotlib's Agg backend, without metadata that would change between runs.
"""

from __future__ import annotations

import io

import numpy as np

#: PNG resolution.
DPI = 120


def _figure(width, height):
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), dpi=DPI)


def _png(fig) -> bytes:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()


def _closed(ring):
    ring = np.asarray(ring, float)
    return np.concatenate([ring, ring[:1]])


def _aligned_points(part, points):
    al = part["alignment"]
    R, t = np.asarray(al["matrix"], float), np.asarray(al["translation"], float)
    return np.asarray(points, float) @ R.T + t


def overlay_png(parts: list[dict], classes: list[dict]) -> bytes:
    """PNG of all parts aligned on their class representatives, one panel per class."""
    by_id = {p["id"]: p for p in parts}
    k = len(classes)
    fig = _figure(8.0, 2.2 * k + 0.6)
    for row, cls in enumerate(classes):
        ax = fig.add_subplot(k, 1, row + 1)
        for pid in cls["members"]:
            part = by_id[pid]
            ax.plot(*_closed(_aligned_points(part, part["outline"])).T, lw=0.6, alpha=0.7)
            for seg in part["score"]:
                ax.plot(*_aligned_points(part, seg).T, lw=0.3, color="0.5", alpha=0.5)
        ax.set_aspect("equal")
        ax.set_title(f"{cls['id']}: {cls['quantity']} × {cls['representative']}, max error "
                     f"{cls['max_relative_error']:.2e} of the length", fontsize=8)
        ax.tick_params(labelsize=6)
    fig.tight_layout()
    return _png(fig)


def strips_png(parts: list[dict]) -> bytes:
    """PNG of the parts side by side (stacked across their length), with rulings and ids."""
    fig = _figure(8.0, min(2.0 + 0.35 * len(parts), 40.0))
    ax = fig.add_subplot(1, 1, 1)
    offset = 0.0
    for part in parts:
        outline = np.asarray(part["outline"], float)
        lo, hi = outline[:, 1].min(), outline[:, 1].max()
        shift = np.array([0.0, offset - lo])
        ax.fill(*(outline + shift).T, facecolor="0.92", edgecolor="k", lw=0.5)
        for seg in part["score"]:
            ax.plot(*(np.asarray(seg, float) + shift).T, lw=0.3, color="tab:blue")
        lx, ly = np.asarray(part["label"], float) + shift
        ax.text(lx, ly, f"{part['id']} ({part['class']})", fontsize=5, ha="center",
                va="center")
        offset += (hi - lo) * 1.25
    ax.set_aspect("equal")
    ax.tick_params(labelsize=6)
    fig.tight_layout()
    return _png(fig)
