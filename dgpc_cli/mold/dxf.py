"""The meridian profile as a DXF drawing in mm, what a mold shop machines (SPEC §6, §9 ezdxf).

DXF R2010, ``$INSUNITS`` = 4 (mm). The drawing lies in the (r, h) half plane, x = r, y = h:

* layer ``PROFILE`` — the meridian polyline (LWPOLYLINE, open) through (r(u), h(u));
* layer ``AXIS`` — the axis of revolution, the line x = 0 a little beyond both ends, CENTER
  linetype;
* layer ``PIECES`` — a short tick across the profile at each end of each mold piece, and the
  piece id beside it (layer ``LABEL``).

Bytes are deterministic (:func:`dgpc_cli.io.dxf.dxf_bytes`: ezdxf's fixed metadata).
"""

from __future__ import annotations

import numpy as np
from ezdxf.document import Drawing

from ..io.dxf import UNIT_MM, dxf_bytes, new_mm_document

__all__ = ["LAYERS", "UNIT_MM", "profile_dxf"]

LAYERS = {"PROFILE": 7, "AXIS": 1, "PIECES": 3, "LABEL": 2}


def profile_dxf(r: np.ndarray, h: np.ndarray, unit: str,
                pieces: list[tuple[str, int, int]] = ()) -> bytes:
    """DXF bytes of the meridian ``r (m,)``, ``h (m,)`` given in ``unit``, drawn in mm.

    ``pieces`` are ``(id, first row, last row)`` of the mold pieces, marked by ticks.
    """
    return dxf_bytes(lambda: _profile_doc(np.asarray(r, dtype=float) * UNIT_MM[unit],
                                          np.asarray(h, dtype=float) * UNIT_MM[unit], pieces))


def _profile_doc(r_mm: np.ndarray, h_mm: np.ndarray, pieces) -> Drawing:
    doc = new_mm_document(LAYERS)
    msp = doc.modelspace()
    msp.add_lwpolyline(np.column_stack([r_mm, h_mm]).tolist(), format="xy",
                       dxfattribs={"layer": "PROFILE"})
    size = float(max(np.ptp(h_mm), r_mm.max(), 1e-9))
    margin = 0.05 * size
    msp.add_line((0.0, float(h_mm.min()) - margin), (0.0, float(h_mm.max()) + margin),
                 dxfattribs={"layer": "AXIS", "linetype": "CENTER"})
    tick = 0.02 * size
    for pid, start, stop in pieces:
        for row in (start, stop):
            msp.add_line((float(r_mm[row]) - tick, float(h_mm[row])),
                         (float(r_mm[row]) + tick, float(h_mm[row])),
                         dxfattribs={"layer": "PIECES"})
        mid = (start + stop) // 2
        msp.add_text(pid, height=tick, dxfattribs={"layer": "LABEL"}).set_placement(
            (float(r_mm[mid]) + 2 * tick, float(h_mm[mid])))
    return doc
