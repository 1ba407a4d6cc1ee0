"""Deterministic DXF writing shared by the mold profile and the nesting sheets (SPEC §3, §9).

ezdxf stamps creation dates and random GUIDs into a drawing, both when it is created and when
it is written, unless its option ``write_fixed_meta_data_for_testing`` is set: every drawing
is built and serialized inside :func:`fixed_metadata`. ezdxf also adds a CLASS per entity type
in use by iterating a ``set`` of type names, whose order follows Python's per-process string
hashing: :func:`dxf_bytes` sorts the CLASSES section before writing. The same input then gives
the same bytes in every process.
All drawings are DXF R2010 with ``$INSUNITS`` = 4 (mm).
"""

from __future__ import annotations

import io
from collections.abc import Callable
from contextlib import contextmanager

import ezdxf
from ezdxf import units
from ezdxf.document import Drawing

#: Length units a net may be in, and their size in mm.
UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "ft": 304.8}


@contextmanager
def fixed_metadata():
    """ezdxf writes dates and random GUIDs unless this option is set; set it meanwhile."""
    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def new_mm_document(layers: dict[str, int], setup=("linetypes",)) -> Drawing:
    """A new R2010 drawing in mm with ``layers`` (name → ACI colour); call inside
    :func:`fixed_metadata`."""
    doc = ezdxf.new("R2010", setup=list(setup), units=units.MM)
    doc.header["$INSUNITS"] = units.MM
    doc.header["$MEASUREMENT"] = 1
    for name, color in layers.items():
        doc.layers.add(name, color=color)
    return doc


def _sorted_classes(doc: Drawing) -> None:
    """Make the CLASSES section come out sorted by name whenever ezdxf completes it."""
    section = doc.classes
    complete = section.add_required_classes

    def add_required_classes(dxfversion: str) -> None:
        complete(dxfversion)
        ordered = sorted(section.classes.items())
        section.classes.clear()
        section.classes.update(ordered)

    section.add_required_classes = add_required_classes


def dxf_bytes(build: Callable[[], Drawing]) -> bytes:
    """The bytes of the drawing made by ``build()``, created and written with fixed metadata
    and a sorted CLASSES section."""
    with fixed_metadata():                 # creation and writing both stamp dates and GUIDs
        doc = build()
        _sorted_classes(doc)
        stream = io.StringIO()
        doc.write(stream)
    return doc.encode(stream.getvalue())
