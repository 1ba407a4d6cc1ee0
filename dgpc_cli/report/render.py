"""Matplotlib figures rendered to PNG bytes, deterministically.

Agg backend, no pyplot state, fixed size and resolution, and no ``Software`` text chunk (the
only metadata matplotlib writes into a PNG that names its version); Agg writes no timestamp, so
the same figure gives the same bytes on every run of the same matplotlib.
"""

from __future__ import annotations

import io

#: PNG resolution (dots per inch).
DPI = 120


def figure(width: float, height: float):
    """A matplotlib Figure of ``width × height`` inches at :data:`DPI`, outside pyplot."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), dpi=DPI)


def png_bytes(fig) -> bytes:
    """The figure as PNG bytes (Agg), without the ``Software`` metadata chunk."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()
