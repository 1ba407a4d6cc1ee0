"""What a 3-D figure shows, drawn through a :class:`~dgpc_cli.report.camera.View` into 2-D axes.

A scene is a list of layers, drawn in order (each over the ones before):

* :class:`Polygons` — filled polygons ``(k, c, 3)`` (net quads, reference triangles), one colour
  each, sorted far to near within the layer (painter's algorithm);
* :class:`Segments` — line segments ``(k, 2, 3)`` (strain glyphs, laths), one colour each.

Every layer's collection carries the layer's ``gid``, and polygons with ``ids`` carry them as
their urls (in drawing order), so that tests (and SVG readers) find what was drawn. Drawing
never needs a display (matplotlib's Agg backend).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .camera import View

__all__ = ["Polygons", "Segments", "draw", "grid_quads", "scene_points"]


@dataclass
class Polygons:
    """Filled polygons ``polys (k, c, 3)`` with ``facecolors (k, 4)`` RGBA; ``ids`` (k,)
    optional names of the polygons (e.g. the panel each belongs to)."""

    polys: np.ndarray
    facecolors: np.ndarray
    gid: str
    edgecolor: tuple = (0.2, 0.2, 0.2, 0.6)
    linewidth: float = 0.25
    ids: list[str] | None = None
    hatch: str | None = None


@dataclass
class Segments:
    """Line segments ``segs (k, 2, 3)`` with ``colors (k, 4)`` RGBA (or one colour)."""

    segs: np.ndarray
    colors: np.ndarray | tuple
    gid: str
    linewidth: float = 0.8
    label: str | None = None


def grid_quads(f: np.ndarray) -> np.ndarray:
    """The quads of a grid ``f (m, n, 3)`` as ``((m − 1)(n − 1), 4, 3)``, row-major."""
    f = np.asarray(f, float)
    q = np.stack([f[:-1, :-1], f[1:, :-1], f[1:, 1:], f[:-1, 1:]], axis=2)
    return q.reshape(-1, 4, 3)


def scene_points(layers: list) -> np.ndarray:
    """Every point ``(k, 3)`` of the layers (what the camera frames)."""
    pts = [np.asarray(layer.polys if isinstance(layer, Polygons) else layer.segs,
                      float).reshape(-1, 3) for layer in layers]
    return np.concatenate(pts) if pts else np.zeros((0, 3))


def _draw_polygons(ax, view: View, layer: Polygons, zorder: int) -> None:
    from matplotlib.collections import PolyCollection

    polys = np.asarray(layer.polys, float)
    if not len(polys):
        return
    order = np.argsort(view.depth(polys).mean(axis=1), kind="stable")   # far first
    coll = PolyCollection(view.project(polys)[order],
                          facecolors=np.asarray(layer.facecolors, float)[order],
                          edgecolors=[layer.edgecolor], linewidths=layer.linewidth,
                          zorder=zorder, hatch=layer.hatch)
    coll.set_gid(layer.gid)
    if layer.ids is not None:                  # kept as the polygons' urls (SVG links)
        coll.set_urls([layer.ids[i] for i in order])
    ax.add_collection(coll)


def _draw_segments(ax, view: View, layer: Segments, zorder: int) -> None:
    from matplotlib.collections import LineCollection

    segs = np.asarray(layer.segs, float)
    colors = np.asarray(layer.colors, float)
    coll = LineCollection(view.project(segs), colors=colors if colors.ndim == 2 else [colors],
                          linewidths=layer.linewidth, zorder=zorder, capstyle="round")
    coll.set_gid(layer.gid)
    if layer.label:
        coll.set_label(layer.label)
    ax.add_collection(coll)


def draw(ax, view: View, layers: list) -> None:
    """Draw the ``layers`` in order through ``view`` into the 2-D axes ``ax``."""
    for z, layer in enumerate(layers, start=1):
        if isinstance(layer, Polygons):
            _draw_polygons(ax, view, layer, z)
        else:
            _draw_segments(ax, view, layer, z)
