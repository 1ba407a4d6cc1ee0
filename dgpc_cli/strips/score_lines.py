"""Whether the copies of a cutting template share its score lines (issue "Strips that build
the design", item 4; SPEC §6 unfold).

Copies of one template share its outline; their score lines (the rulings, the bend lines)
need not coincide: the strips of a shared-outline template are each bent along their own
rulings (paper Fig. 18), and the boards of such strips too. A shop that scored one copy's lines
on another would bend it wrongly, so the score lines of every copy, carried onto the template
by the copy's alignment, are compared with the template's.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import MultiLineString

#: Part of every score line between the points at which their distance is taken (the
#: distance of two straight segments is then exact within this fraction of their length).
DENSIFY = 0.02


def aligned(lines: list, R: np.ndarray, t: np.ndarray) -> list[np.ndarray]:
    """The polylines ``lines`` moved by ``x ↦ R x + t``."""
    return [np.asarray(x, float) @ np.asarray(R, float).T + np.asarray(t, float)
            for x in lines]


def score_distance(a: list, b: list) -> float:
    """The distance of two sets of score lines (polylines ``(k, 2)``): the largest distance of
    a point of either from the other (symmetric Hausdorff distance, each line densified by
    :data:`DENSIFY`); 0 for two empty sets, ``inf`` when only one is empty."""
    if len(a) == 0 or len(b) == 0:
        return 0.0 if len(a) == len(b) else float("inf")
    return float(shapely.hausdorff_distance(
        MultiLineString([np.asarray(x, float) for x in a]),
        MultiLineString([np.asarray(x, float) for x in b]), densify=DENSIFY))
