"""Boards of stock length cut from the strips of one template (``planarize-strips`` fitted one
flat template, ``unfold --stock-length``; issue "Strips that build the design", item 4).

The strips of a template are isometric bendings of one flat part: their developments agree to
round-off (cut along the template's outline curves, :mod:`dgpc_cli.strips.cut_edges`, or along
shared vertices). So every strip is cut at the SAME lines of the template: a cut is the straight
segment of the flat template between the points at arc length ``α`` along its outline edge A and
``β`` along its edge B (from the end at row 0). With a shared outline each strip has its own
rulings, so a cut need not lie on a ruling: on the 3-D strip it is the template's straight line
carried through the strip's planar quads (a polyline bent at the rulings it crosses); the strip's
own rulings stay the score lines, clipped to each board. Where every strip has the template's
own vertices (no cut edges) the cuts are the template's rulings, so joints stay on score lines;
where no ruling lies within the stock (or none keeps the stagger) a cut goes inside a planar quad
of the template, straight across it at the same fraction of both its sides
(:func:`dgpc_cli.strips.boards.cut_inside`), still one template line for every strip.

Two joint patterns, P for the strips of even column and Q for those of odd column, alternate
strip by strip: P greedy (each board as long as the stock allows), Q greedy too with its joints
at least the stagger from P's on both shared geodesics (Q's side A against P's side B, Q's side
B against P's side A). Arc lengths along a strip's edge equal those along its geodesic in space
(an isometry), and every strip starts on the net's first row, so the stagger is measured in
template positions. The boards of all strips are then the boards of two patterns: copies.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from dgpc_cli.errors import DgpcError

from .boards import SLIVER, cumulative, cut_inside, last_within
from .cut_edges import inverse_bilinear
from .develop import Development, signed_area, straightness
from .trim import strip_points

log = logging.getLogger(__name__)

#: Step of the cut positions tried along a shared outline (mm), at most this many positions.
STEP_MM = 1.0
MAX_POSITIONS = 20000


@dataclass(frozen=True)
class Cuts:
    """The template's cut lines of one joint pattern: ``along (k + 2, 2)`` the arc lengths
    ``(α, β)`` on edges A and B, the strip's ends first and last."""

    along: np.ndarray

    @property
    def joints(self) -> np.ndarray:
        """The interior cuts ``(k, 2)``."""
        return self.along[1:-1]


def at_arc(X: np.ndarray, s: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Points ``(k, d)`` at arc lengths ``x`` along the polyline ``X (m, d)`` of cumulative arc
    lengths ``s``."""
    return np.stack([np.interp(x, s, X[:, j]) for j in range(X.shape[1])], axis=-1)


def piece(X: np.ndarray, s: np.ndarray, x0: float, x1: float) -> np.ndarray:
    """The polyline ``X`` from arc length ``x0`` to ``x1``: both end points and the vertices
    strictly between."""
    inner = X[(s > x0) & (s < x1)]
    return np.concatenate([at_arc(X, s, np.array([x0])), inner, at_arc(X, s, np.array([x1]))])


def board_extent(ea, sa, eb, sb, a: np.ndarray, b: np.ndarray) -> float:
    """Stock length the board between the cuts ``a = (α, β)`` and ``b`` of the developed edges
    ``ea, eb`` (cumulative arcs ``sa, sb``) needs: its outline's extent along the chord from
    the mid-point of its first cut to that of its last."""
    pa, pb = piece(ea, sa, a[0], b[0]), piece(eb, sb, a[1], b[1])
    chord = 0.5 * (pa[-1] + pb[-1]) - 0.5 * (pa[0] + pb[0])
    x = np.concatenate([pa, pb]) @ (chord / np.linalg.norm(chord))
    return float(x.max() - x.min())


def candidate_cuts(dev: Development, on_rulings: bool) -> np.ndarray:
    """The cuts ``(n, 2)`` a pattern may use on the template whose development is ``dev``: its
    interior rulings (``on_rulings``), else positions every :data:`STEP_MM` at equal arc
    length on both edges."""
    ea, eb = dev.cut_edges
    la, lb = cumulative(ea)[-1], cumulative(eb)[-1]
    if on_rulings:
        return np.stack([cumulative(dev.A)[1:-1], cumulative(dev.B)[1:-1]], axis=-1)
    end = min(la, lb)
    count = int(min(MAX_POSITIONS, np.ceil(end / STEP_MM)))
    x = np.linspace(0.0, end, count + 1)[1:-1]
    return np.stack([x, x], axis=-1)


def greedy_pattern(dev: Development, candidates: np.ndarray, allowed: np.ndarray, stock: float,
                   name: str, quads: list | None = None, stagger: float = 0.0) -> Cuts:
    """A pattern of cuts among ``candidates`` where ``allowed``: from the first row, each
    board as long as the stock allows (:func:`board_extent`); DgpcError when no allowed cut
    keeps a board within the stock. ``quads`` (candidates on the rulings): where no ruling
    within the stock is allowed, or the farthest one leaves a board shorter than
    :data:`~dgpc_cli.strips.boards.SLIVER` of the stock, a cut inside a quad
    (:func:`quad_cut`) that keeps
    ``stagger`` from the joints ``quads`` lists (``(side, joints)``: side 0 or 1, A or B, and
    arc lengths of the other pattern's joints on it)."""
    ea, eb = dev.cut_edges
    sa, sb = cumulative(ea), cumulative(eb)
    end = np.array([sa[-1], sb[-1]])
    cuts = [np.zeros(2)]
    while board_extent(ea, sa, eb, sb, cuts[-1], end) > stock:
        a = cuts[-1]
        ahead = np.flatnonzero((candidates[:, 0] > a[0] + 1e-9) & (candidates[:, 1] > a[1] + 1e-9))
        lo, hi = 0, len(ahead)            # the first candidate beyond the stock: bisection
        while lo < hi:
            mid = (lo + hi) // 2
            if board_extent(ea, sa, eb, sb, a, candidates[ahead[mid]]) <= stock:
                lo = mid + 1
            else:
                hi = mid
        fit = [c for c in ahead[:lo][allowed[ahead[:lo]]][::-1]    # farthest first
               if board_extent(ea, sa, eb, sb, a, candidates[c]) <= stock][:1]
        if not fit and quads is not None:
            inside = quad_cut(dev, a, ahead, lo, stock, quads, stagger)
            if inside is not None:
                cuts.append(inside)
                continue
        if (fit and quads is not None          # a sliver at a ruling: inside the next quad
                and board_extent(ea, sa, eb, sb, a, candidates[fit[0]]) < SLIVER * stock):
            inside = quad_cut(dev, a, ahead, lo, stock, quads, stagger, after=fit[0] + 1.0)
            if inside is not None:
                cuts.append(inside)
                continue
        if not fit:
            raise DgpcError(f"{name}: no cut of the template from {a.mean():.6g} on keeps a "
                            f"board within the stock length ({stock:.6g} mm) and the stagger from "
                            "the joints of the strips beside it; use a smaller --stagger or a "
                            "longer --stock-length", source="--stock-length")
        cuts.append(candidates[fit[0]])
    cuts.append(end)
    return Cuts(np.asarray(cuts))


def quad_cut(dev: Development, a: np.ndarray, ahead: np.ndarray, lo: int, stock: float,
             quads: list, stagger: float, after: float | None = None) -> np.ndarray | None:
    """A cut ``(α, β)`` inside a planar quad of the template developed as ``dev`` (cut at its
    rulings) after the cut ``a``, where the rulings ``ahead`` (indices of the interior rulings
    beyond ``a``) offer none: the first ``lo`` of them lie within the stock. The cut is the
    straight line at the fraction ``f`` of both sides of quad ``u`` (row ``t = u + f``), as
    far as the stock allows, and, where ``quads`` names the other pattern's joints, at least
    ``stagger`` from them (:func:`~dgpc_cli.strips.boards.cut_inside`); beyond the row
    ``after``, by default the first ruling within the stock where there is one (or where the
    board reaches half the stock, if that comes first). None where no such cut is."""
    ea, eb = dev.cut_edges
    sa, sb = cumulative(ea), cumulative(eb)
    m = dev.A.shape[0]
    rows = np.arange(m, dtype=float)

    def cut(t):
        return np.array([np.interp(t, rows, sa), np.interp(t, rows, sb)])

    def extent(x, y):
        return board_extent(ea, sa, eb, sb, cut(x), cut(y))

    t0 = float(np.interp(a[0], sa, rows))
    nxt = float(ahead[lo] + 1) if lo < len(ahead) else m - 1.0
    if after is None and lo > 0:           # boards of half the stock on
        after = min(float(ahead[0] + 1), last_within(extent, t0, nxt, 0.5 * stock))
    sides = [((sa, sb)[side], np.asarray(joints, float)) for side, joints in quads]
    t_max, t_ok = cut_inside(extent, t0, nxt, stock, sides, stagger, after=after)
    if t_ok is None and lo == 0 and t_max is not None and after is None:
        log.warning("a template cut inside quad %d keeps less than the stagger %.4g from the "
                    "joints of the strips beside it: no cut within the stock keeps it there",
                    int(t_max), stagger)
        t_ok = t_max
    return None if t_ok is None else cut(t_ok)


def template_patterns(dev: Development, on_rulings: bool, stock: float, stagger: float,
                      both_sides: bool, name: str) -> tuple[Cuts, Cuts]:
    """The two joint patterns (P, Q) of the strips of the template developed as ``dev`` (see
    the module); ``both_sides``: Q's joints keep the stagger from P's on both geodesics (three
    strips or more), else on the one Q's side A shares with P's side B."""
    if not stock > 0:
        raise DgpcError(f"{stock:g}: must be > 0", source="--stock-length")
    if not stagger >= 0:
        raise DgpcError(f"{stagger:g}: must be >= 0", source="--stagger")
    cand = candidate_cuts(dev, on_rulings)
    p = greedy_pattern(dev, cand, np.ones(len(cand), bool), stock, name,
                       [] if on_rulings else None, stagger)
    allowed = np.ones(len(cand), bool)
    quads = []
    if len(p.joints):
        allowed &= np.abs(cand[:, 0, None] - p.joints[None, :, 1]).min(axis=1) >= stagger
        quads.append((0, p.joints[:, 1]))
        if both_sides:
            allowed &= np.abs(cand[:, 1, None] - p.joints[None, :, 0]).min(axis=1) >= stagger
            quads.append((1, p.joints[:, 0]))
    return p, greedy_pattern(dev, cand, allowed, stock, name, quads if on_rulings else None,
                             stagger)


def cut_params(dev: Development, along: np.ndarray) -> np.ndarray:
    """The strip's ``(t, s)`` ``(k, 2, 2)`` of the ends (on edge A, on edge B) of the cuts
    ``along (k, 2)`` on the strip developed as ``dev``: each end in the quad between the two
    ruling ends that enclose it along its edge (the edge between them lies in that quad's
    region, :mod:`dgpc_cli.strips.cut_edges`)."""
    m = dev.A.shape[0]
    out = []
    for j, (edge, X) in enumerate(zip(dev.cut_edges, (dev.A, dev.B), strict=True)):
        s = cumulative(edge)
        p = at_arc(edge, s, along[:, j])
        x = shapely.line_locate_point(LineString(edge), shapely.points(X))
        u = np.clip(np.searchsorted(x, along[:, j], side="right") - 1, 0, m - 2)
        frac = (along[:, j] - x[u]) / (x[u + 1] - x[u])
        out.append(inverse_bilinear(dev.A, dev.B, u, p,
                                    np.stack([frac, np.full_like(frac, float(j))], axis=-1)))
    return np.stack(out, axis=1)


def _place(points: np.ndarray, start: np.ndarray, stop: np.ndarray):
    """The rigid motion putting ``start`` at the origin and ``stop - start`` along +x, applied
    to ``points (..., 2)``."""
    d = stop - start
    c, s = d / np.linalg.norm(d)
    rel = points - start
    return np.stack([c * rel[..., 0] + s * rel[..., 1], -s * rel[..., 0] + c * rel[..., 1]], -1)


def board_geometry(dev: Development, a: np.ndarray, b: np.ndarray, ta: np.ndarray,
                   tb: np.ndarray) -> dict:
    """The developed board between the cuts ``a = (α, β)`` and ``b`` of the strip developed as
    ``dev`` (``ta``, ``tb`` ``(2, 2)``: the ``(t, s)`` of the cuts' ends on edges A and B),
    placed with its first cut's mid-point at the origin and its chord along +x: ``edges`` (its
    cut-edge pieces A, B), ``outline`` (counter-clockwise), ``geodesics`` (the cuts' ends and
    between them the strip's vertices of the rows strictly between the cuts on both edges, as
    many on A as on B), ``score`` (the strip's interior rulings clipped to the board),
    ``label``, ``length`` (mean of the edges' arc lengths), ``straightness``."""
    ea, eb = dev.cut_edges
    sa, sb = cumulative(ea), cumulative(eb)
    pa, pb = piece(ea, sa, a[0], b[0]), piece(eb, sb, a[1], b[1])
    start, stop = 0.5 * (pa[0] + pb[0]), 0.5 * (pa[-1] + pb[-1])
    rows = np.arange(int(np.floor(ta[:, 0].max())) + 1, int(np.ceil(tb[:, 0].min())))
    ga = np.concatenate([pa[:1], dev.A[rows], pa[-1:]])
    gb = np.concatenate([pb[:1], dev.B[rows], pb[-1:]])
    ring = np.concatenate([pa, pb[::-1]])
    ring = ring if signed_area(ring) > 0 else ring[::-1]
    poly = Polygon(ring)
    score = []
    size = float(np.ptp(ring, axis=0).max())
    for u in range(1, dev.A.shape[0] - 1):
        seg = poly.intersection(LineString([dev.A[u], dev.B[u]]))
        for line in getattr(seg, "geoms", [seg]):
            if (line.geom_type == "LineString" and line.length > 1e-9 * size and
                    poly.exterior.distance(line.interpolate(0.5, normalized=True))
                    > 1e-9 * size):
                score.append(np.asarray(line.coords))
    label = np.asarray(poly.representative_point().coords[0])

    def put(x):
        return _place(np.asarray(x, float), start, stop)

    return {"edges": (put(pa), put(pb)), "outline": put(ring),
            "geodesics": (put(ga), put(gb)), "score": [put(s) for s in score],
            "label": put(label), "length": 0.5 * float(b[0] - a[0] + b[1] - a[1]),
            "straightness": np.array([straightness(ga), straightness(gb)])}


def cut_path(dev: Development, ends: np.ndarray) -> np.ndarray:
    """The strip's ``(t, s)`` ``(k, 2)`` of the template cut whose ends (on edge A, on edge B)
    are ``ends (2, 2)``: its ends and where it crosses the strip's rulings, from A to B. Between
    two of them the cut is straight within one planar quad, so
    :func:`~dgpc_cli.strips.trim.strip_points` of the path on the 3-D strip is the cut in space
    (the template's straight line carried through the strip's quads, bent at the rulings)."""
    ends = np.asarray(ends, float)
    p, q = strip_points(dev.A, dev.B, ends)
    lo, hi = np.sort(ends[:, 0])
    rows = np.arange(int(np.floor(lo)) + 1, int(np.ceil(hi)))
    a, r = dev.A[rows], dev.B[rows] - dev.A[rows]
    d = q - p
    det = d[0] * r[:, 1] - d[1] * r[:, 0]            # p + λ d = a + s r
    w = a - p
    lam = (w[:, 0] * r[:, 1] - w[:, 1] * r[:, 0]) / det
    s = (w[:, 0] * d[1] - w[:, 1] * d[0]) / det
    order = np.argsort(lam)
    return np.concatenate([ends[:1], np.stack([rows, s], axis=-1)[order], ends[1:]])
