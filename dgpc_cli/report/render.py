"""Matplotlib figures rendered to PNG bytes, deterministically.

Agg backend, no pyplot state, fixed sizes and resolution, matplotlib's own default style
(:func:`style`: a user's ``matplotlibrc`` changes nothing) with a fixed ``svg.hashsalt``, and
no ``Software`` text chunk (the only metadata matplotlib writes into a PNG that names its
version); Agg writes no timestamp, so the same figure gives the same bytes on every run of the
same matplotlib.
"""

from __future__ import annotations

import io
from collections.abc import Iterator
from contextlib import contextmanager

#: PNG resolution (dots per inch).
DPI = 120
#: rcParams on top of matplotlib's defaults.
RC = {"svg.hashsalt": "dgpc", "font.family": "DejaVu Sans", "axes.unicode_minus": True}


@contextmanager
def style() -> Iterator[None]:
    """Meanwhile: matplotlib's default style with :data:`RC` (figures are made and saved
    inside it)."""
    import matplotlib
    import matplotlib.style

    with matplotlib.style.context("default"), matplotlib.rc_context(RC):
        yield


def figure(width: float, height: float):
    """A matplotlib Figure of ``width × height`` inches at :data:`DPI`, outside pyplot."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), dpi=DPI)


def png_bytes(fig) -> bytes:
    """The figure as PNG bytes (Agg), without the ``Software`` metadata chunk."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    return buf.getvalue()
