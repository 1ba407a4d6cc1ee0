"""The meridian profile as a DXF drawing in mm, what a mold shop machines (SPEC §6, §9 ezdxf).

The drawing lies in the (r, h) half plane, x = r, y = h, in mm (written by
:mod:`dgpc_cli.io.dxf`: R2010, audited, deterministic):

* layer ``PROFILE`` — the meridian polyline (open) through (r(u), h(u));
* layer ``AXIS`` — the axis of revolution, the line x = 0 a little beyond both ends, CENTER
  linetype, grey;
* layer ``PIECES`` — a short tick across the profile at each end of each mold piece, and the
  piece id beside it (layer ``LABEL``, green).
"""

from __future__ import annotations

import numpy as np

from ..io.dxf import Drawing, Layer
from ..io.units import to_mm

__all__ = ["LAYERS", "profile_dxf"]

LAYERS = {"PROFILE": Layer(7), "AXIS": Layer(8, "CENTER"), "PIECES": Layer(6),
          "LABEL": Layer(3)}


def profile_drawing(r_mm: np.ndarray, h_mm: np.ndarray,
                    pieces: list[tuple[str, int, int]] = ()) -> Drawing:
    """The drawing of the meridian ``r_mm, h_mm (m,)`` with the ticks of ``pieces``."""
    d = Drawing(LAYERS)
    d.polyline("PROFILE", np.column_stack([r_mm, h_mm]))
    size = float(max(np.ptp(h_mm), r_mm.max(), 1e-9))
    margin = 0.05 * size
    d.line("AXIS", (0.0, float(h_mm.min()) - margin), (0.0, float(h_mm.max()) + margin))
    tick = 0.02 * size
    for pid, start, stop in pieces:
        for row in (start, stop):
            d.line("PIECES", (float(r_mm[row]) - tick, float(h_mm[row])),
                   (float(r_mm[row]) + tick, float(h_mm[row])))
        mid = (start + stop) // 2
        d.text("LABEL", pid, (float(r_mm[mid]) + 2 * tick, float(h_mm[mid])), tick,
               align="MIDDLE_LEFT")
    return d


def profile_dxf(r: np.ndarray, h: np.ndarray, units: str,
                pieces: list[tuple[str, int, int]] = ()) -> bytes:
    """DXF bytes of the meridian ``r (m,)``, ``h (m,)`` given in ``units``, drawn in mm.

    ``pieces`` are ``(id, first row, last row)`` of the mold pieces, marked by ticks.
    """
    return profile_drawing(to_mm(r, units), to_mm(h, units), pieces).to_bytes("profile DXF")
