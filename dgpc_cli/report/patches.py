"""The figure of a net made on one patch of its reference (``init --patches``): the whole mesh
(light grey), the net's patch (pale blue), the net's quads, and the cut curves that split the
mesh (red, gid ``cuts``) in the three standard views, so that the user sees where and along
what the reference was split, and which patch the net clads."""

from __future__ import annotations

import numpy as np

from .scene import Polygons, Segments, grid_quads
from .views import views_figure

__all__ = ["patches_figure"]

#: Colours: the whole mesh, the net's patch, the net's quads, the cut curves.
WHOLE, PATCH, NET, CUT = ((0.75, 0.75, 0.75, 0.35), (0.55, 0.75, 0.95, 0.45),
                          (0.2, 0.2, 0.2, 0.15), (0.85, 0.05, 0.05, 1.0))


def cut_segments(curves: list) -> np.ndarray:
    """The polylines ``curves`` (each ``(k, 3)``) as segments ``(s, 2, 3)``."""
    segs = [np.stack([p[:-1], p[1:]], axis=1) for p in (np.asarray(c, float) for c in curves)
            if p.ndim == 2 and len(p) > 1]
    return np.concatenate(segs) if segs else np.zeros((0, 2, 3))


def patches_figure(f: np.ndarray, patch: tuple[np.ndarray, np.ndarray] | None,
                   whole: tuple[np.ndarray, np.ndarray] | None, curves: list, *, title: str,
                   unit: str, up=(0.0, 0.0, 1.0), front=None):
    """The net ``f (m, n, 3)`` on its ``patch`` (vertices, faces) within the ``whole`` mesh
    (either may be None: a file no longer there), and the cut ``curves`` (polylines)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch as LegendPatch

    layers, legend = [], []
    for mesh, colour, name, label in ((whole, WHOLE, "whole", "the whole mesh"),
                                      (patch, PATCH, "patch", "this net's patch")):
        if mesh is None:
            continue
        V, F = mesh
        layers.append(Polygons(np.asarray(V, float)[np.asarray(F)],
                               np.tile(colour, (len(F), 1)), name, edgecolor=(0, 0, 0, 0),
                               linewidth=0.0))
        legend.append(LegendPatch(facecolor=colour, edgecolor="0.5", label=label))
    quads = grid_quads(f)
    layers.append(Polygons(quads, np.tile(NET, (len(quads), 1)), "net"))
    segs = cut_segments(curves)
    layers.append(Segments(segs, CUT, "cuts", linewidth=1.6))
    legend.append(Line2D([], [], color=CUT, lw=1.6, label="cut curves"))
    return views_figure(layers, title=title, unit=unit, up=up, front=front, legend=legend)
