"""The meridian profile as a DXF drawing in mm, what a mold shop machines (SPEC §6, §9 ezdxf).

DXF R2010, ``$INSUNITS`` = 4 (mm). The drawing lies in the (r, h) half plane, x = r, y = h:

* layer ``PROFILE`` — the meridian polyline (LWPOLYLINE, open) through (r(u), h(u));
* layer ``AXIS`` — the axis of revolution, the line x = 0 a little beyond both ends, CENTER
  linetype;
* layer ``PIECES`` — a short tick across the profile at each end of each mold piece, and the
  piece id beside it (layer ``LABEL``).

Bytes are deterministic: ezdxf's fixed metadata (dates, GUIDs) is used while writing.
"""

from __future__ import annotations

import io
from contextlib import contextmanager

import ezdxf
import numpy as np
from ezdxf import units
from ezdxf.document import Drawing

#: Length units the net may be in, and their size in mm.
UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "ft": 304.8}

LAYERS = {"PROFILE": 7, "AXIS": 1, "PIECES": 3, "LABEL": 2}


@contextmanager
def _fixed_metadata():
    """ezdxf writes dates and random GUIDs unless this option is set; set it while writing."""
    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def profile_dxf(r: np.ndarray, h: np.ndarray, unit: str,
                pieces: list[tuple[str, int, int]] = ()) -> bytes:
    """DXF bytes of the meridian ``r (m,)``, ``h (m,)`` given in ``unit``, drawn in mm.

    ``pieces`` are ``(id, first row, last row)`` of the mold pieces, marked by ticks.
    """
    with _fixed_metadata():                 # creation and writing both stamp dates and GUIDs
        doc = _profile_doc(np.asarray(r, dtype=float) * UNIT_MM[unit],
                           np.asarray(h, dtype=float) * UNIT_MM[unit], pieces)
        stream = io.StringIO()
        doc.write(stream)
    return doc.encode(stream.getvalue())


def _profile_doc(r_mm: np.ndarray, h_mm: np.ndarray, pieces) -> Drawing:
    doc = ezdxf.new("R2010", setup=["linetypes"], units=units.MM)
    doc.header["$INSUNITS"] = units.MM
    doc.header["$MEASUREMENT"] = 1
    for name, color in LAYERS.items():
        doc.layers.add(name, color=color)
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
