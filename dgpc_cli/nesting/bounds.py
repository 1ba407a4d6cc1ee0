"""Lower bounds on the number of sheets a set of parts needs (whatever the engine): what the
benchmark prints beside each engine's count, to tell a short search from a full sheet.

* Area: the parts' area over one sheet's area.
* Centre line: a part longer (along x, in every allowed rotation) than half the sheet's inner
  width crosses the sheet's vertical centre line wherever it lies. Along that line the parts'
  sections are disjoint and at least the spacing apart, so a sheet holds at most ``k`` of them,
  ``k`` the most of the smallest sections that fit in the inner height; with ``n`` such parts
  the sheets are at least ``⌈n / k⌉``. A part's section is the least over every position where
  it can cross the line (its ends included), so the bound holds for any layout.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from .geometry import CLEARANCE_MM, Part, rotation_matrix


def _least_section(part: Part, rotation: float, width: float, margin: float) -> float | None:
    """The least length of the part's section by the vertical centre line of a sheet ``width``
    wide over every position inside the margin; None when the part need not cross it, inf
    when it does not fit across the sheet in this rotation (it is never placed so)."""
    o = part.outline @ rotation_matrix(rotation).T
    o = o - o.min(axis=0)
    length, half = float(o[:, 0].max()), 0.5 * width - margin
    if length > width - 2 * margin:
        return np.inf
    if length <= half:
        return None
    # the line crosses the part at u from its left end, u in [length - half, half]; the
    # section's length is linear in u between the vertices' x (each edge it crosses is), so
    # its least is at an end of that range or beside a vertex (both sides: a vertical edge)
    lo, hi = length - half, half
    xs = o[:, 0][(o[:, 0] > lo) & (o[:, 0] < hi)]
    u = np.unique(np.clip(np.concatenate([[lo, hi], xs - 1e-6, xs + 1e-6]), lo, hi))
    top = float(o[:, 1].max()) + 1.0
    lines = shapely.linestrings(np.stack([np.column_stack([u, np.full_like(u, -1.0)]),
                                          np.column_stack([u, np.full_like(u, top)])], axis=1))
    return float(shapely.length(shapely.intersection(lines, Polygon(o))).min())


def sheet_lower_bounds(parts: list[Part], width: float, height: float, margin: float,
                       spacing: float, rotations: list[float]) -> dict:
    """``{"area": ..., "centre_line": ..., "sheets": max of both}`` (see the module)."""
    area = math.ceil(sum(p.area for p in parts) / (width * height) - 1e-9)
    m = margin + CLEARANCE_MM
    sections = []
    for p in parts:
        least = [_least_section(p, r, width, m) for r in rotations]
        if least and all(s is not None for s in least) and min(least) < np.inf:
            sections.append(min(least))
    sections.sort()
    inner = height - 2 * m
    k, used = 0, -spacing
    for s in sections:
        if used + spacing + s > inner:
            break
        k, used = k + 1, used + spacing + s
    line = math.ceil(len(sections) / k) if sections and k else 0
    if sections and k:
        total = (sum(sections) + spacing * len(sections)) / (inner + spacing)
        line = max(line, math.ceil(total - 1e-9))
    return {"area": area, "centre_line": line, "sheets": max(area, line)}
