"""Pinched trimmed parts (``planarize-strips --trim``; issue "a real roof clad by the default
command": no part narrower than a quarter of the mean strip width).

Where the geodesics of a net converge (round a pole of a dome, at a fan) a strip narrows to a
point; where the outline crosses a strip at a grazing angle it leaves a sliver along one of its
geodesics. Neither can be cut and fixed as a board. A trimmed part (a polygon in the strip's
``(t, s)``, :mod:`dgpc_cli.strips.trim`) therefore loses the rows where its strip is narrower
than :data:`PINCH` of the strips' mean width (the end is cut straight across the strip where
the width, linear between rows, reaches it), and a part whose widest cross-section stays
below that is a sliver: it is dropped. The reference area they leave bare is what the trim
reports.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon, box
from shapely.geometry.polygon import orient
from shapely.ops import unary_union

#: Least part width, as a share of the strips' mean width.
PINCH = 0.25
#: The pinched rows are cut where the width is this much above the least one, so that the cut
#: end, measured again on the developed part, stays above it.
MARGIN = 1.02


def _distance_to_polyline(P: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Distances ``(k,)`` of the points ``P (k, d)`` from the polyline ``X (m, d)``."""
    a, e = X[:-1], np.diff(X, axis=0)
    ee = np.einsum("si,si->s", e, e)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.einsum("ksi,si->ks", P[:, None] - a[None], e) / np.where(ee > 0, ee, 1.0)
    foot = a[None] + np.clip(s, 0.0, 1.0)[..., None] * e[None]
    return np.linalg.norm(foot - P[:, None], axis=-1).min(axis=1)


def row_widths(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Width ``(m,)`` of the strip ``A, B (m, d)`` at each row: the smaller of the distances
    of ``A_u`` from the polyline B and of ``B_u`` from the polyline A."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    return np.minimum(_distance_to_polyline(A, B), _distance_to_polyline(B, A))


def wide_region(widths: np.ndarray, least: float):
    """The region of ``(t, s)`` (a shapely geometry, s in [−1, 2]) where the width, linear
    between the rows' ``widths (m,)``, is at least ``least``."""
    w0, w1 = widths[:-1], widths[1:]
    u = np.arange(len(w0), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = u + (least - w0) / (w1 - w0)
    lo = np.where(w0 >= least, u, np.where(w1 >= least, cross, np.nan))
    hi = np.where(w1 >= least, u + 1.0, np.where(w0 >= least, cross, np.nan))
    keep = ~np.isnan(lo) & (hi > lo)
    return unary_union([box(a, -1.0, b, 2.0) for a, b in zip(lo[keep], hi[keep], strict=True)])


def _rings(geometry) -> list[np.ndarray]:
    """The polygons of a shapely geometry as rings ``(k, 2)``, counter-clockwise, not closed."""
    polys = (geometry.geoms if isinstance(geometry, MultiPolygon) else
             [geometry] if isinstance(geometry, Polygon) else
             [g for g in getattr(geometry, "geoms", []) if isinstance(g, Polygon)])
    out = []
    for p in polys:
        if p.is_empty or p.area <= 0:
            continue
        ring = np.asarray(orient(p, 1.0).exterior.coords)[:-1]
        out.append(ring)
    return out


def unpinched(ring: np.ndarray, widths: np.ndarray, least: float) -> list[np.ndarray]:
    """The pieces of the part ``ring (k, 2)`` (in ``(t, s)``) where its strip, of the rows'
    ``widths``, is at least ``least`` wide (cut :data:`MARGIN` above it), in order along the
    strip; the part itself when it is nowhere narrower."""
    ring = np.asarray(ring, float)
    t0, t1 = ring[:, 0].min(), ring[:, 0].max()
    r0, r1 = int(np.floor(t0)), int(np.ceil(t1))
    if widths[r0:r1 + 1].min() >= MARGIN * least:
        return [ring]
    pieces = _rings(Polygon(ring).intersection(wide_region(widths, MARGIN * least)))
    return sorted(pieces, key=lambda r: r[:, 0].min())


def widest_section(ring: np.ndarray, widths: np.ndarray, samples: int = 8) -> float:
    """The widest cross-section of the part ``ring (k, 2)`` (in ``(t, s)``) of a strip whose
    rows are ``widths`` wide: the length of the part's cut by the lines ``t = const`` (at
    ``samples`` per quad and at the ring's points), in s, times the width there."""
    ring = np.asarray(ring, float)
    t0, t1 = ring[:, 0].min(), ring[:, 0].max()
    ts = np.unique(np.concatenate([np.linspace(t0, t1, max(2, int(samples * (t1 - t0)) + 1)),
                                   ring[:, 0]]))
    lines = shapely.linestrings(np.stack([np.stack([ts, np.full_like(ts, -1.0)], -1),
                                          np.stack([ts, np.full_like(ts, 2.0)], -1)], 1))
    across = shapely.length(shapely.intersection(Polygon(ring), lines))
    width = np.interp(ts, np.arange(len(widths), dtype=float), widths)
    return float((across * width).max())
