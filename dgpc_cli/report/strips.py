"""Figures of a strips artifact after the paper's Fig. 18: every developed strip overlaid on the
template (the first strip's development), and the 3-D strips coloured by their deviation from
the net with the seams where neighbouring strips step apart.

* :func:`template_overlay_figure`: the developments (``strips.develop``), each moved onto the
  template by the Kabsch alignment of its outline (``strips.congruence.align``) and turned so
  that the template runs across the page; on top the whole strips, below them the two ends
  magnified (where strips ended on their own slanted rulings differ most), outlines in the cut
  colour, the template in black, rulings in the score colour; scale bars in mm.
* :func:`deviation_figure`: the strips in the three standard views (:mod:`.views`), each quad
  coloured by its largest distance from the net strip (mm), the shared geodesics drawn in red
  where the seam step exceeds a threshold and in grey elsewhere.
"""

from __future__ import annotations

import numpy as np

from ..io.units import nice_length
from .flat import CUT, PAGE, SCORE, principal_rotation
from .render import figure
from .scene import Polygons, Segments
from .views import ColourBar, scale_bar_at, views_figure

__all__ = ["SEAM_OK", "SEAM_STEPPED", "TEMPLATE_SIZE", "deviation_figure", "quad_widths",
           "template_overlay_figure"]

#: Colours of the template's outline and of the seams (stepped above the threshold, or not).
TEMPLATE, SEAM_STEPPED, SEAM_OK = (0.0, 0.0, 0.0), (0.85, 0.0, 0.0, 1.0), (0.45, 0.45, 0.45, 1.0)
#: Font sizes (points): title, labels, small.
TITLE_PT, LABEL_PT, SMALL_PT = 11, 9, 8
#: Size of the overlay figure (inches).
TEMPLATE_SIZE = (PAGE[0], 5.6)
#: Length of each magnified end, in template widths.
END_WIDTHS = 2.5


def _ring(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    return np.concatenate([A, B[::-1], A[:1]])


def _scale_bar(ax, span: float, y: float) -> None:
    """A round length (mm) about a quarter of ``span``, at height ``y`` (data) under the
    drawing's left end."""
    scale_bar_at(ax, ax.get_xlim()[0] + 0.03 * span, y, nice_length(0.25 * span), "mm",
                 SMALL_PT)


def template_overlay_figure(parts: list[tuple[str, np.ndarray, np.ndarray]], *,
                            title: str, outlines: list | None = None):
    """The developed strips ``(id, A, B)`` (2-D, mm, already aligned on the template, the
    first one) overlaid: the whole strips on top, the two ends magnified below. Every outline
    is one line with gid ``outline:<id>`` in the top axes (gid ``overlay``): the ring of A and
    B, or of the edges ``outlines[k] = (A', B')`` each part is cut along when given (a
    shared-outline template's curves); the rulings join A_u and B_u."""
    from matplotlib.lines import Line2D

    _, A0, B0 = parts[0]
    R = principal_rotation(np.concatenate([A0, B0]))
    turned = [(pid, A @ R.T, B @ R.T) for pid, A, B in parts]
    pts = np.concatenate([np.concatenate([A, B]) for _, A, B in turned])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    width = float(np.mean(np.linalg.norm(B0 - A0, axis=1)))
    fig = figure(*TEMPLATE_SIZE)
    top = fig.add_axes((0.03, 0.62, 0.94, 0.26))
    top.set_gid("overlay")
    ends = [fig.add_axes((0.03, 0.08, 0.45, 0.44)), fig.add_axes((0.52, 0.08, 0.45, 0.44))]
    ends[0].set_gid("overlay-start")
    ends[1].set_gid("overlay-end")
    for ax, gid in ((top, "outline"), (ends[0], "start"), (ends[1], "end")):
        for k, (pid, A, B) in enumerate(turned):
            for u in range(1, len(A) - 1):
                ax.plot([A[u, 0], B[u, 0]], [A[u, 1], B[u, 1]], color=SCORE, lw=0.4,
                        alpha=0.5)
            ring = _ring(*outlines[k]) if outlines is not None else _ring(A, B)
            line, = ax.plot(*ring.T, color=TEMPLATE if k == 0 else CUT,
                            lw=1.3 if k == 0 else 0.7, alpha=1.0 if k == 0 else 0.75,
                            zorder=3 if k == 0 else 2)
            line.set_gid(f"{gid}:{pid}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_axis_off()
    pad = 0.04 * (hi[0] - lo[0])
    top.set_xlim(lo[0] - pad, hi[0] + pad)
    top.set_ylim(lo[1] - 0.5 * width, hi[1] + 0.3 * width)
    top.set_aspect("equal", adjustable="box")
    _scale_bar(top, hi[0] - lo[0], lo[1] - 0.3 * width)
    reach = END_WIDTHS * width
    mid_y = 0.5 * (lo[1] + hi[1])
    half_h = 0.5 * (hi[1] - lo[1]) + 0.4 * width
    for ax, (x0, x1), name in ((ends[0], (lo[0] - 0.1 * reach, lo[0] + reach), "start"),
                               (ends[1], (hi[0] - reach, hi[0] + 0.1 * reach), "end")):
        box = ax.get_position()
        ratio = box.height * fig.get_figheight() / (box.width * fig.get_figwidth())
        half_w = max(0.5 * (x1 - x0), half_h / ratio)
        cx = 0.5 * (x0 + x1)
        ax.set_xlim(cx - half_w, cx + half_w)
        ax.set_ylim(mid_y - half_w * ratio, mid_y + half_w * ratio)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(f"{name} of the strips, magnified", fontsize=LABEL_PT, pad=2)
        _scale_bar(ax, 2 * half_w, mid_y - 0.9 * half_w * ratio)
    fig.suptitle(title, fontsize=TITLE_PT - 1, y=0.985)
    fig.legend(handles=[Line2D([], [], color=TEMPLATE, lw=1.3, label=f"template ({parts[0][0]})"),
                        Line2D([], [], color=CUT, lw=0.8, label="other strips' outlines"),
                        Line2D([], [], color=SCORE, lw=0.8, label="rulings (score lines)")],
               loc="upper center", bbox_to_anchor=(0.5, 0.955), ncol=3, fontsize=SMALL_PT,
               frameon=False)
    return fig


def quad_widths(grid: np.ndarray) -> np.ndarray:
    """The width of a strip ``grid (m, 2, d)`` (its two geodesics ``A = grid[:, 0]``, ``B =
    grid[:, 1]``) per quad ``(m − 1, 1)``: the quad's area over its mean length along the strip
    (the mean of its two geodesic edges), the distance across the strip whatever the slant of
    its rulings."""
    A, B = np.asarray(grid[:, 0], float), np.asarray(grid[:, 1], float)
    a0, a1, b0, b1 = A[:-1], A[1:], B[:-1], B[1:]
    area = 0.5 * (np.linalg.norm(np.cross(a1 - a0, b0 - a0), axis=-1)
                  + np.linalg.norm(np.cross(b1 - b0, a1 - b1), axis=-1))
    along = 0.5 * (np.linalg.norm(a1 - a0, axis=-1) + np.linalg.norm(b1 - b0, axis=-1))
    return (area / np.where(along > 0, along, np.inf))[:, None]


def deviation_figure(strips: list[tuple[np.ndarray, np.ndarray]], deviation: list[np.ndarray],
                     seams: list[tuple[np.ndarray, np.ndarray]], *, threshold_mm: float,
                     title: str, unit: str, up=(0.0, 0.0, 1.0), front=None):
    """The strips ``(A, B)`` (3-D, in ``unit``) in the standard views, quad ``u`` of strip ``i``
    coloured by ``deviation[i][u]`` (mm; gid ``strips``), with the seams: each shared geodesic
    ``(X (k, 3), step (k,))`` (mm at its vertices) as segments, red (gid ``seams-stepped``)
    where the step at either end exceeds ``threshold_mm``, grey (``seams``) elsewhere."""
    from matplotlib import colormaps
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D

    quads = np.concatenate([np.stack([A[:-1], A[1:], B[1:], B[:-1]], axis=1)
                            for A, B in strips])
    values = np.concatenate([np.asarray(d, float) for d in deviation])
    top = float(values.max()) if values.size and values.max() > 0 else 1.0
    norm, cmap = Normalize(0.0, top), colormaps["YlOrRd"]
    layers = [Polygons(quads, np.asarray(cmap(norm(values)), float), "strips")]
    stepped, ok = [], []
    for X, step in seams:
        segs = np.stack([X[:-1], X[1:]], axis=1)
        hot = np.maximum(step[:-1], step[1:]) > threshold_mm
        stepped.append(segs[hot])
        ok.append(segs[~hot])
    stepped = np.concatenate(stepped) if stepped else np.zeros((0, 2, 3))
    ok = np.concatenate(ok) if ok else np.zeros((0, 2, 3))
    layers += [Segments(ok, SEAM_OK, "seams", linewidth=1.0),
               Segments(stepped, SEAM_STEPPED, "seams-stepped", linewidth=2.2)]
    legend = [Line2D([], [], color=SEAM_STEPPED, lw=2.2,
                     label=f"seam, step > {threshold_mm:.3g} mm ({len(stepped)} edges)"),
              Line2D([], [], color=SEAM_OK, lw=1.0,
                     label=f"seam, step ≤ {threshold_mm:.3g} mm ({len(ok)} edges)")]
    return views_figure(layers, title=title, unit=unit, up=up, front=front,
                        colour_bar=ColourBar(norm, cmap, "deviation from the net strip [mm]"),
                        legend=legend)
