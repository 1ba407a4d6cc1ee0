"""Figures of a sheets artifact: each sheet's preview and the panel-to-mold map, with a legend of
their layers.

``dgpc nest`` renders every DXF it writes into a PNG preview in the layers' colours on white
(:func:`dgpc_cli.io.dxf.previews`). :func:`preview_figure` shows such a preview pixel for pixel
(``figimage``: no resampling, so its colours are the layers' own) under a title and beside a
legend naming each layer's colour and what it holds (cut red, score blue, labels green, sheet
grey, for the cut sheets).
"""

from __future__ import annotations

import io

import numpy as np

from .render import DPI, figure

__all__ = ["LEGEND_WIDTH", "preview_figure"]

#: Width (inches) of the legend column right of the preview; height of the title band.
LEGEND_WIDTH, TITLE_HEIGHT = 2.9, 0.55
TITLE_PT, LABEL_PT = 11, 9


def preview_figure(png: bytes, layers: list[tuple[str, tuple, str]], *,
                   title: str | None = None):
    """The preview ``png`` at 100 % (``dgpc nest`` titles its previews and gives them a scale
    bar) with ``title`` above, if any, and a legend of ``layers``: ``(name, rgb in 0–1, what it
    holds)`` each."""
    from matplotlib.lines import Line2D
    from PIL import Image

    image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
    h, w = image.shape[:2]
    band = TITLE_HEIGHT if title else 0.1
    fig = figure(w / DPI + LEGEND_WIDTH, max(h / DPI, 2.0) + band)
    H = fig.get_size_inches()[1] * DPI
    fig.figimage(image, xo=0, yo=int(round(H - band * DPI - h)), origin="upper")
    handles = [Line2D([], [], color=rgb, lw=3, label=f"{name}: {what}")
               for name, rgb, what in layers]
    fig.legend(handles=handles, loc="upper left",
               bbox_to_anchor=(w / DPI / fig.get_size_inches()[0] + 0.01,
                               1.0 - (band + 0.4) / fig.get_size_inches()[1]),
               fontsize=LABEL_PT, frameon=False, title="layers", title_fontsize=LABEL_PT)
    if title:
        fig.suptitle(title, fontsize=TITLE_PT, x=0.01, ha="left", y=0.99)
    return fig
