"""Independent checks of a DXF that goes to a CAM as it is (issue 14): read back by ezdxf and by
a second reader (dxfgrabber), geometry checked with shapely.

What a CAM needs: every layer plotted (a CAM that skips unplotted layers would still cut them
where another does not), closed outlines on CUT and on SHEET_BORDER (only with ``nest
--border``), single open strokes on ENGRAVE (``--label-style stroke``) crossing no cut or score
line, header extents equal to the drawing's as ezdxf measures them.

A segment is a pair of end points rounded to 1e-6 mm; a text's box comes from ezdxf's own font
measurement (``ezdxf.bbox`` of the text turned upright, turned back about its alignment point),
not from dgpc's estimate.
"""

from __future__ import annotations

import re
from collections import Counter

import dxfgrabber
import ezdxf
import numpy as np
from ezdxf import bbox
from shapely.geometry import LineString, Polygon

QUANTUM = 1e-6


#: The text of a part's end mark (its first row's number, ``R0``), drawn with the labels.
END_MARK = re.compile(r"R\d+(\.\d+)?")

def _rounded(p) -> tuple[int, int]:
    return int(round(p[0] / QUANTUM)), int(round(p[1] / QUANTUM))


def grabber_polylines(path) -> list[tuple[str, np.ndarray, bool]]:
    """``(layer, points (k, 2), closed)`` of every LWPOLYLINE, POLYLINE and LINE, read by
    dxfgrabber."""
    out = []
    for e in dxfgrabber.readfile(str(path)).entities:
        if e.dxftype in ("LWPOLYLINE", "POLYLINE"):
            pts = np.array([p[:2] for p in e.points], float)
            out.append((e.layer, pts, bool(e.is_closed)))
        elif e.dxftype == "LINE":
            out.append((e.layer, np.array([e.start[:2], e.end[:2]], float), False))
    return out


def ezdxf_polylines(doc) -> list[tuple[str, np.ndarray, bool]]:
    """The same from ezdxf's model space."""
    out = []
    for e in doc.modelspace():
        if e.dxftype() == "LWPOLYLINE":
            out.append((e.dxf.layer, np.array(e.get_points("xy"), float), bool(e.closed)))
        elif e.dxftype() == "LINE":
            a, b = e.dxf.start, e.dxf.end
            out.append((e.dxf.layer, np.array([(a.x, a.y), (b.x, b.y)]), False))
    return out


def segment_faults(polylines) -> tuple[int, int]:
    """``(duplicates, zero-length)`` segments over all polylines (any layers, either way)."""
    seen: Counter = Counter()
    zero = 0
    for _, pts, closed in polylines:
        ring = np.concatenate([pts, pts[:1]]) if closed else pts
        for a, b in zip(ring[:-1], ring[1:], strict=True):
            ka, kb = _rounded(a), _rounded(b)
            if ka == kb:
                zero += 1
            seen[(ka, kb) if ka <= kb else (kb, ka)] += 1
    return sum(c - 1 for c in seen.values()), zero


def text_boxes(doc, layer: str = "LABEL") -> list[tuple[str, Polygon]]:
    """``(text, box)`` of every TEXT on ``layer`` by ezdxf's font measurement."""
    out = []
    for e in doc.modelspace().query(f"TEXT[layer=='{layer}']"):
        upright = e.copy()
        upright.dxf.rotation = 0.0
        box = bbox.extents([upright], fast=False)
        point = e.dxf.align_point if e.dxf.halign or e.dxf.valign else e.dxf.insert
        at = np.array([point.x, point.y])
        (x0, y0), (x1, y1) = (box.extmin.x, box.extmin.y), (box.extmax.x, box.extmax.y)
        corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]) - at
        a = np.radians(e.dxf.rotation)
        R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        out.append((e.dxf.text, Polygon(corners @ R.T + at)))
    return out


def check_cam_ready(path) -> dict:
    """Assert what a CAM needs of the DXF at ``path``; returns a summary (counts by layer)."""
    doc = ezdxf.readfile(path)
    assert doc.dxfversion == "AC1024", path                                  # R2010
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1, path   # mm
    auditor = doc.audit()
    assert not auditor.has_errors, (path, [str(e) for e in auditor.errors])
    grabbed = dxfgrabber.readfile(str(path))
    assert grabbed.header["$INSUNITS"] == 4
    lines_ez, lines_gr = ezdxf_polylines(doc), grabber_polylines(path)
    assert len(lines_ez) == len(lines_gr), path
    for polylines in (lines_ez, lines_gr):
        assert segment_faults(polylines) == (0, 0), path
        for layer, _, closed in polylines:
            if layer in ("CUT", "SHEET_BORDER"):
                assert closed, path                 # CUT, the border: closed outlines only
            if layer == "ENGRAVE":
                assert not closed, path             # single strokes, followed once
    # every layer is plotted (a CAM that skips unplotted layers would still cut them)
    assert all(layer.dxf.plot for layer in doc.layers if layer.dxf.name != "Defpoints"), path
    assert "SHEET" not in doc.layers, path          # the old unplotted border layer
    assert len([1 for layer, _, _ in lines_ez if layer == "SHEET_BORDER"]) <= 1, path
    # extents set (not ezdxf's ±1e20 default): those of the drawing as ezdxf measures it
    lo = np.array(grabbed.header["$EXTMIN"][:2])
    hi = np.array(grabbed.header["$EXTMAX"][:2])
    assert np.array_equal(lo, np.array(doc.header["$EXTMIN"][:2]))
    pts = np.concatenate([p for _, p, _ in lines_gr])
    assert np.all(lo <= pts.min(axis=0) + 1e-9) and np.all(pts.max(axis=0) <= hi + 1e-9), path
    drawn = bbox.extents(doc.modelspace(), fast=False)
    size = float(np.max(hi - lo))
    assert np.allclose(lo, [drawn.extmin.x, drawn.extmin.y], atol=1e-6 * size), path
    assert np.allclose(hi, [drawn.extmax.x, drawn.extmax.y], atol=1e-6 * size), path
    # no label's text box crosses a cut or score line
    cuts = [LineString(np.concatenate([p, p[:1]]) if c else p)
            for layer, p, c in lines_ez if layer in ("CUT", "SCORE")]
    for text, box in text_boxes(doc):
        assert not any(box.intersects(line) for line in cuts), (path, text)
    # no engraved letter crosses a cut or score line (a leader, one straight segment, does)
    for layer, p, _ in lines_ez:
        if layer == "ENGRAVE" and len(p) > 2:
            assert not any(LineString(p).intersects(line) for line in cuts), path
    counts = Counter(f"{e.dxf.layer}:{e.dxftype()}" for e in doc.modelspace())
    return dict(sorted(counts.items()))
