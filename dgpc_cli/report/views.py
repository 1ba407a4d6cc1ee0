"""The 3-D figure of a model: three standard views, each framed on the model, with a scale bar
in the artifact's unit, a colour bar with its unit and a legend.

Layout (:data:`VIEWS_SIZE` inches): the axonometric view large on the left, the plan and the
elevation on the right, the legend (when the figure has one) in the lower left corner beside the
colour bar (when it has one), the title on top. Every view's axes span exactly its frame
(:meth:`~dgpc_cli.report.camera.View.frame`, equal scales), carry the gid ``view-<name>`` and
have a scale bar under them: a round length (1, 2 or 5 × 10^k of the unit) about a quarter of
the frame's width.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..io.units import nice_length
from .camera import model_frame, standard_views
from .render import figure
from .scene import draw, scene_points

__all__ = ["VIEWS_SIZE", "ColourBar", "one_scale", "view_axes", "views_figure"]

#: Size of the figure (inches).
VIEWS_SIZE = (10.0, 6.4)
#: The views' region in figure coordinates: from the top (under the title) down to the bottom,
#: or to the colour bar's space; the axonometric view's share of the width.
TOP, BOTTOM, BAR_SPACE, AXO_WIDTH = 0.93, 0.01, 0.13, 0.58
#: Room in a view's cell (figure coordinates) for its title above and its scale bar below.
TITLE_ROOM, BAR_ROOM = 0.035, 0.075
#: Font sizes (points): title, view titles and labels, ticks.
TITLE_PT, LABEL_PT, TICK_PT = 11, 9, 8


@dataclass
class ColourBar:
    """A colour bar: ``norm`` and ``cmap`` of the colours, ``label`` with the unit."""

    norm: object
    cmap: object
    label: str


def _length_text(length: float, unit: str) -> str:
    return f"{length:g} {unit}"


def scale_bar_at(ax, x0: float, y: float, length: float, unit: str,
                 fontsize: float = LABEL_PT) -> None:
    """A scale bar of ``length`` (in ``unit``) from ``(x0, y)`` in the data coordinates of a
    2-D drawing (gid ``scale-bar``), its length written a few points under its middle."""
    ax.plot([x0, x0 + length], [y, y], color="k", lw=2.5, solid_capstyle="butt",
            clip_on=False, gid="scale-bar")
    ax.annotate(_length_text(length, unit), (x0 + 0.5 * length, y), xytext=(0, -4),
                textcoords="offset points", ha="center", va="top", fontsize=fontsize,
                annotation_clip=False)


def scale_bar(ax, frame, unit: str) -> None:
    """A scale bar under the axes: a round length about a quarter of the frame's width."""
    from matplotlib.lines import Line2D

    x0, x1 = frame[0], frame[1]
    length = nice_length(0.25 * (x1 - x0))
    trans = ax.get_xaxis_transform()         # x in data, y in axes coordinates
    start = x0 + 0.02 * (x1 - x0)
    bar = Line2D([start, start + length], [-0.025, -0.025], transform=trans, color="k",
                 lw=2.5, solid_capstyle="butt", clip_on=False)
    bar.set_gid("scale-bar")
    ax.add_line(bar)
    ax.text(start + 0.5 * length, -0.045, _length_text(length, unit), transform=trans,
            ha="center", va="top", fontsize=LABEL_PT, clip_on=False, gid="scale-bar-label")


def view_axes(fig, rect, view, layers: list, points, *, unit: str, up=(0.0, 0.0, 1.0),
              front=None, frame=None, bar: bool = True):
    """Axes at ``rect`` (figure coordinates; gid ``view-<name>``) showing ``layers`` through
    ``view``, spanning exactly the view's frame on ``points`` (or ``frame``; equal scales),
    with the view's title above and (``bar``) a scale bar in ``unit`` under them."""
    ax = fig.add_axes(rect)
    ax.set_gid(f"view-{view.name}")
    draw(ax, view, layers)
    if frame is None:
        frame = model_frame(view, points, up, front)
    ax.set_xlim(frame[0], frame[1])
    ax.set_ylim(frame[2], frame[3])
    ax.set_aspect("equal", adjustable="box", anchor="C")
    ax.set_axis_off()
    ax.set_title(view.title, fontsize=LABEL_PT, pad=3)
    if bar:
        scale_bar(ax, frame, unit)
    return ax


def one_scale(fig, rects: list, frames: list) -> list[tuple[float, float, float, float]]:
    """The ``frames`` widened about their centres so that, drawn into the axes ``rects``
    (figure coordinates) of ``fig``, they all have one scale (the smallest that shows each
    whole): one scale bar then speaks for every view."""
    W, H = fig.get_size_inches()
    per_inch = max(max((f[1] - f[0]) / (r[2] * W), (f[3] - f[2]) / (r[3] * H))
                   for f, r in zip(frames, rects, strict=True))
    out = []
    for (x0, x1, y0, y1), r in zip(frames, rects, strict=True):
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        hw, hh = 0.5 * per_inch * r[2] * W, 0.5 * per_inch * r[3] * H
        out.append((cx - hw, cx + hw, cy - hh, cy + hh))
    return out


def _cells(bottom: float) -> dict[str, tuple[float, float, float, float]]:
    """``(left, bottom, width, height)`` of every view's axes in figure coordinates."""
    height = TOP - bottom
    cells = {"axonometric": (0.01, bottom, AXO_WIDTH - 0.02, height),
             "plan": (AXO_WIDTH, bottom + 0.5 * height, 0.99 - AXO_WIDTH, 0.5 * height),
             "elevation": (AXO_WIDTH, bottom, 0.99 - AXO_WIDTH, 0.5 * height)}
    return {name: (x, y + BAR_ROOM, w, h - BAR_ROOM - TITLE_ROOM)
            for name, (x, y, w, h) in cells.items()}


def views_figure(layers: list, *, title: str, unit: str, up=(0.0, 0.0, 1.0), front=None,
                 colour_bar: ColourBar | None = None, legend: list | None = None,
                 plan_title: str = "plan (from above)", points=None,
                 instead_of_plan: tuple[str, list] | None = None):
    """The figure of the scene ``layers`` (:mod:`.scene`) in the three standard views, framed
    on ``points`` (default: every point of the layers) seen with ``up`` and ``front``
    (:func:`~dgpc_cli.report.camera.standard_views`); ``legend`` a list of matplotlib handles.
    ``instead_of_plan = (title, layers)``: the plan's cell shows those layers through the
    axonometric camera instead (gid ``view-second``), framed on the same points."""
    from dataclasses import replace

    pts = scene_points(layers) if points is None else np.asarray(points, float).reshape(-1, 3)
    fig = figure(*VIEWS_SIZE)
    cells = _cells(BOTTOM + (BAR_SPACE if colour_bar is not None or legend else 0.0))
    views = standard_views(pts, up, front, plan_title=plan_title)
    for view in views:
        if view.name == "plan" and instead_of_plan is not None:
            second_title, second_layers = instead_of_plan
            second = replace(views[0], name="second", title=second_title)
            view_axes(fig, cells["plan"], second, second_layers, pts, unit=unit, up=up,
                      front=front)
            continue
        view_axes(fig, cells[view.name], view, layers, pts, unit=unit, up=up, front=front)
    fig.suptitle(title, fontsize=TITLE_PT, y=0.985)
    if colour_bar is not None:
        from matplotlib.cm import ScalarMappable

        cax = fig.add_axes((0.42, 0.075, 0.54, 0.025))
        bar = fig.colorbar(ScalarMappable(norm=colour_bar.norm, cmap=colour_bar.cmap),
                           cax=cax, orientation="horizontal")
        bar.set_label(colour_bar.label, fontsize=LABEL_PT)
        bar.ax.tick_params(labelsize=TICK_PT)
        bar.formatter.set_powerlimits((-3, 4))
        bar.formatter.set_useOffset(False)     # ticks are values, not offsets from one
        bar.update_ticks()
    if legend:
        fig.legend(handles=legend, loc="lower left", bbox_to_anchor=(0.005, 0.005),
                   fontsize=LABEL_PT, frameon=True, framealpha=0.9)
    return fig
