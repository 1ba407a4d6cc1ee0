"""Reading a part's end mark back from a DXF (ezdxf) and judging its direction, independently
of how dgpc places it: the chevron is found by its shape (a symmetric open polyline of three
points whose arms open by 2·atan(0.5/0.6) ≈ 79.6°), the part's axis at its first-row end is
the direction from the midpoint of its first row to the midpoint of its second, and the row's
number is the TEXT matching ``R<row>`` (label style text) or the single strokes beyond the
chevron (style stroke)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from dxf_checks import END_MARK
from shapely.geometry import LineString, Point, Polygon

#: The chevron's opening angle (degrees): arms at ±0.5 h across, 0.6 h along.
OPENING = float(np.degrees(2 * np.arctan2(0.5, 0.6)))
#: The chevron's arm length over the mark's height.
ARM = float(np.hypot(0.5, 0.6))


@dataclass
class MarkReading:
    """What the DXF shows of one part's end mark: the angle (degrees) between the chevron's
    opening and the part's axis into the part (0: pointing straight at the first-row end),
    the angle between the row number's reading direction and the axis (0 or 180: along
    it), the mark's height (mm), whether its apex is nearer the first-row end than the
    last, and the row number's text (style text)."""

    chevron_deg: float
    reading_deg: float
    height: float
    at_first_end: bool
    text: str | None = None


def chevrons(msp, layer: str) -> list[np.ndarray]:
    """Every open polyline of three points on ``layer`` shaped as an end mark's chevron."""
    found = []
    for e in msp.query(f"LWPOLYLINE[layer=='{layer}']"):
        p = np.array(e.get_points("xy"), float)
        if len(p) != 3 or e.closed:
            continue
        a, b = p[0] - p[1], p[2] - p[1]
        la, lb = np.linalg.norm(a), np.linalg.norm(b)
        if not (la > 0 and abs(la - lb) <= 1e-6 * la):
            continue
        angle = np.degrees(np.arccos(np.clip(a @ b / (la * lb), -1, 1)))
        if abs(angle - OPENING) < 0.5:
            found.append(p)
    return found


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return float(np.degrees(np.arccos(np.clip(u @ v / np.linalg.norm(u) / np.linalg.norm(v),
                                              -1.0, 1.0))))


def read_mark(msp, layer: str, outline: np.ndarray, A: np.ndarray, B: np.ndarray
              ) -> MarkReading:
    """The end mark of the part with ``outline`` and geodesics ``A, B`` (DXF coordinates, its
    first row at ``A[0], B[0]``) on ``layer`` (``LABEL`` or ``ENGRAVE``); AssertionError
    unless exactly one chevron and one row number lie inside the part."""
    part = Polygon(outline).buffer(1e-6)
    mine = [c for c in chevrons(msp, layer) if part.contains(LineString(c))]
    assert len(mine) == 1, f"{len(mine)} chevrons inside the part"
    c = mine[0]
    apex, h = c[1], float(np.linalg.norm(c[0] - c[1])) / ARM
    axis = 0.5 * (A[1] + B[1]) - 0.5 * (A[0] + B[0])
    axis = axis / np.linalg.norm(axis)
    across = np.array([-axis[1], axis[0]])
    opening = 0.5 * (c[0] + c[2]) - apex
    first, last = LineString([A[0], B[0]]), LineString([A[-1], B[-1]])
    nearer = Point(apex).distance(first) < Point(apex).distance(last)
    texts = [e for e in msp.query(f"TEXT[layer=='{layer}']")
             if END_MARK.fullmatch(e.dxf.text) and part.contains(Point(_text_at(e)))]
    if texts:
        assert len(texts) == 1, f"{len(texts)} row numbers inside the part"
        r = np.radians(texts[0].dxf.rotation)
        return MarkReading(_angle(opening, axis), _angle(np.array([np.cos(r), np.sin(r)]), axis),
                           h, nearer, texts[0].dxf.text)
    # single strokes: those beyond the chevron along the axis, within the mark's reach
    strokes = []
    for e in msp.query(f"LWPOLYLINE[layer=='{layer}']"):
        p = np.array(e.get_points("xy"), float)
        if p.shape == c.shape and np.allclose(p, c):
            continue
        along, side = (p - apex) @ axis, (p - apex) @ across
        if along.min() > 0.55 * h and along.max() < 5.0 * h and np.abs(side).max() < 0.8 * h:
            strokes.append(np.stack([along, side], axis=1))
    assert strokes, "no row number beside the chevron"
    pts = np.concatenate(strokes)
    extent_along, extent_across = np.ptp(pts[:, 0]), np.ptp(pts[:, 1])
    reading = 0.0 if extent_along > extent_across else 90.0
    return MarkReading(_angle(opening, axis), reading, h, nearer)


def _text_at(e) -> np.ndarray:
    point = e.dxf.align_point if (e.dxf.halign or e.dxf.valign) else e.dxf.insert
    return np.array(point)[:2]


def along_the_part(reading: MarkReading, tolerance_deg: float = 10.0) -> bool:
    """The mark lies on the part's axis: its chevron opens into the part (points at the
    first-row end), its row number reads along the part, and it sits at the first end."""
    return (reading.chevron_deg < tolerance_deg and reading.at_first_end
            and min(reading.reading_deg, 180.0 - reading.reading_deg) < tolerance_deg)
