"""Geodesic gridshell laths (paper §6.2.1, Fig. 14; SPEC §1): the u-lines (geodesics) of two
transversal nets on one reference, their lengths and the arc-length positions of their
crossings with the other family (where the joints are drilled).

Two laths of different families cross where their polylines come closest: every pair of
segments near each other (a KD-tree of segment midpoints) gets its exact closest points,
vectorized; a pair counts when both closest points are inside their segments (not at a
lath's ends) and no farther apart than :data:`GAP` mean edge lengths. Nearby hits of one lath
pair (a crossing at a vertex is found on both adjacent segments) are merged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

#: Largest distance of two laths at a crossing, in mean edge lengths of the nets.
GAP = 0.25


@dataclass
class Lath:
    """One lath: ``points (k, 3)`` of a u-line, its id (``A01``…) and family (``A``/``B``)."""

    id: str
    family: str
    points: np.ndarray

    @property
    def cumulative(self) -> np.ndarray:
        """Arc length at each point ``(k,)``."""
        return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(self.points, axis=0),
                                                              axis=1))])

    @property
    def length(self) -> float:
        return float(self.cumulative[-1])


@dataclass
class Crossings:
    """Crossings of lath ``a[i]`` (family A) with ``b[i]`` (family B) at arc lengths ``s_a[i]``,
    ``s_b[i]``; ``gap[i]`` the distance between the two laths there, ``point[i]`` the midpoint."""

    a: np.ndarray
    b: np.ndarray
    s_a: np.ndarray
    s_b: np.ndarray
    gap: np.ndarray
    point: np.ndarray


def laths_of(f: np.ndarray, family: str) -> list[Lath]:
    """The u-lines ``f[:, v]`` of a net ``(m, n, 3)`` as laths ``<family><v+1>`` (zero-padded)."""
    n = f.shape[1]
    width = max(2, len(str(n)))
    return [Lath(f"{family}{v + 1:0{width}d}", family, np.ascontiguousarray(f[:, v]))
            for v in range(n)]


def _segments(laths: list[Lath]):
    p0 = np.concatenate([lt.points[:-1] for lt in laths])
    p1 = np.concatenate([lt.points[1:] for lt in laths])
    lath = np.concatenate([np.full(len(lt.points) - 1, i) for i, lt in enumerate(laths)])
    index = np.concatenate([np.arange(len(lt.points) - 1) for lt in laths])
    last = np.concatenate([np.arange(len(lt.points) - 1) == len(lt.points) - 2 for lt in laths])
    start = np.concatenate([lt.cumulative[:-1] for lt in laths])
    return p0, p1, lath, index, last, start


def _closest_params(p0, p1, q0, q1):
    """Parameters ``s, t ∈ [0, 1]`` of the closest points of the segments p0p1 and q0q1
    (row-wise; Ericson, Real-Time Collision Detection §5.1.9) and whether the unconstrained
    closest points of the two lines already lie inside both segments."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, b = np.sum(d1 * d1, 1), np.sum(d2 * d2, 1), np.sum(d1 * d2, 1)
    c, f = np.sum(d1 * r, 1), np.sum(d2 * r, 1)
    denom = a * e - b * b
    ok = denom > 1e-12 * a * e                       # not parallel
    safe = np.where(ok, denom, 1.0)
    s_line = np.where(ok, (b * f - c * e) / safe, 0.0)
    t_line = np.where(ok, (a * f - b * c) / safe, 0.0)
    inside = ok & (s_line >= 0) & (s_line <= 1) & (t_line >= 0) & (t_line <= 1)
    s = np.clip(s_line, 0.0, 1.0)
    t = (b * s + f) / e
    s = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0.0, 1.0)
    return s, t, inside


def find_crossings(family_a: list[Lath], family_b: list[Lath], *, gap: float) -> Crossings:
    """Crossings of every lath of ``family_a`` with every lath of ``family_b`` (see the module
    docstring); ``gap`` the largest distance between two laths that still counts."""
    pa0, pa1, la, ia, lasta, sa0 = _segments(family_a)
    pb0, pb1, lb, ib, lastb, sb0 = _segments(family_b)
    ma, mb = 0.5 * (pa0 + pa1), 0.5 * (pb0 + pb1)
    reach = 0.5 * max(np.linalg.norm(pa1 - pa0, axis=1).max(),
                      np.linalg.norm(pb1 - pb0, axis=1).max()) * 2 + gap
    pairs = cKDTree(ma).sparse_distance_matrix(cKDTree(mb), reach, output_type="ndarray")
    i, j = pairs["i"].astype(np.int64), pairs["j"].astype(np.int64)
    s, t, inside = _closest_params(pa0[i], pa1[i], pb0[j], pb1[j])
    # a lath's own end is no crossing
    inside &= ~((ia[i] == 0) & (s <= 0)) & ~(lasta[i] & (s >= 1))
    inside &= ~((ib[j] == 0) & (t <= 0)) & ~(lastb[j] & (t >= 1))
    xa = pa0[i] + s[:, None] * (pa1[i] - pa0[i])
    xb = pb0[j] + t[:, None] * (pb1[j] - pb0[j])
    dist = np.linalg.norm(xa - xb, axis=1)
    keep = inside & (dist <= gap)
    i, j, s, t, xa, xb, dist = i[keep], j[keep], s[keep], t[keep], xa[keep], xb[keep], dist[keep]
    s_a = sa0[i] + s * np.linalg.norm(pa1[i] - pa0[i], axis=1)
    s_b = sb0[j] + t * np.linalg.norm(pb1[j] - pb0[j], axis=1)
    a_id, b_id = la[i], lb[j]
    # merge duplicates of one crossing (found on adjacent segments): sort by pair, then s_a
    order = np.lexsort((dist, s_a, b_id, a_id))
    a_id, b_id, s_a, s_b, dist = a_id[order], b_id[order], s_a[order], s_b[order], dist[order]
    xa, xb = xa[order], xb[order]
    seg_len = np.median(np.linalg.norm(pa1 - pa0, axis=1))
    new = np.ones(len(a_id), dtype=bool)
    new[1:] = (a_id[1:] != a_id[:-1]) | (b_id[1:] != b_id[:-1]) | \
        (np.abs(s_a[1:] - s_a[:-1]) > 0.5 * seg_len)
    group = np.cumsum(new) - 1
    best = np.full(group.max() + 1 if len(group) else 0, -1, dtype=np.int64)
    by_gap = np.lexsort((dist, group))              # within each group, smallest gap first
    first = np.ones(len(by_gap), dtype=bool)
    first[1:] = group[by_gap][1:] != group[by_gap][:-1]
    best[group[by_gap][first]] = by_gap[first]
    return Crossings(a=a_id[best], b=b_id[best], s_a=s_a[best], s_b=s_b[best], gap=dist[best],
                     point=0.5 * (xa[best] + xb[best]))


def crossing_gap(f_a: np.ndarray, f_b: np.ndarray, gap: float | None = None) -> float:
    """The largest gap of a crossing: ``gap``, by default :data:`GAP` × the mean edge length
    of the two nets (in their unit)."""
    from dgpc_cli.core.problem import mean_edge_length

    if gap is not None:
        return float(gap)
    return float(GAP * 0.5 * (mean_edge_length(f_a) + mean_edge_length(f_b)))


def checked_gap(f_a: np.ndarray, f_b: np.ndarray, gap, units: str) -> float | None:
    """``--gap`` (a :class:`~dgpc_cli.io.length.Length` or None: the default) in the nets'
    unit ``units``, held to the rule of every length
    (:meth:`~dgpc_cli.io.length.Length.check`: a plain number is plausible up to the nets'
    mean edge, a gap wider than their quads)."""
    from dgpc_cli.core.problem import mean_edge_length
    from dgpc_cli.io.length import Span
    from dgpc_cli.io.units import mm_per_unit

    if gap is None:
        return None
    edge = 0.5 * (mean_edge_length(f_a) + mean_edge_length(f_b))
    mm = gap.check("--gap", units, Span(0.0, edge * mm_per_unit(units), "gap", low_open=True,
                                        high_text=f"the nets' mean edge ({edge:.4g} {units})"),
                   "the nets'")
    return mm / mm_per_unit(units)


def gridshell(f_a: np.ndarray, f_b: np.ndarray, *, gap: float | None = None):
    """Laths of the nets ``f_a``, ``f_b`` (families A and B) and their crossings.

    ``gap`` default: see :func:`crossing_gap`.
    """
    laths_a, laths_b = laths_of(f_a, "A"), laths_of(f_b, "B")
    return laths_a, laths_b, find_crossings(laths_a, laths_b, gap=crossing_gap(f_a, f_b, gap))
