"""Boards of stock length: developable strips split at rulings, joints staggered (SPEC §6 unfold).

A strip longer than the stock is cut into boards at its rulings (the planar-quad edges
``A_u B_u``): a joint at row u ends one board and starts the next. A board covering the rows
a … b needs stock as long as its outline's extent along its own chord (the direction from the
mid-point of its first ruling to that of its last one), which is how ``unfold`` lays it out.

Joints of neighbouring strips lie on their shared geodesic (strip v has the geodesics v and
v+1 as its sides A and B). No joint of a strip may come within the stagger of a joint of its
neighbour on that geodesic, measured by arc length from the first row. Strips are cut in
order of their column: each strip's joints avoid those of the strip before it (whose joints
are fixed), and every board is made as long as the stock and the stagger allow (greedy from
the first row, which gives the fewest boards for the strip). A strip takes the joints of the
strip two columns before it instead, where they fit its stock, keep the stagger and need no
more boards. (Strips that ``planarize-strips`` bent from one template are cut at the template's
lines instead, two patterns alternating: :mod:`dgpc_cli.strips.template_boards`.)

Where no ruling lies within the stock (a planar quad longer than the stock is left), the joint
is cut inside the quad: the straight segment ``t = u + f`` of the strip's ``(t, s)``
(:mod:`dgpc_cli.strips.trim`) from the point at fraction ``f`` of its side A to the point at
the same fraction of its side B. The map ``(t, s)`` is bilinear on each quad, so at fixed ``t``
it is straight on the 3-D quad and on its development alike, and the quad being planar, both
pieces stay planar and their developments exact; its direction lies between those of the two
rulings bounding the quad (the joint leans no more than they do), and the board's rows are
then fractional (:func:`knots`). ``f`` is as large as the stock allows, moved back where that
keeps the stagger from the neighbour's joints. A joint goes inside a quad too where no ruling
within the stock keeps the stagger but a point inside a quad does, and where the farthest
ruling within the stock would leave a board shorter than half the stock (a sliver before a
long quad).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError

from .develop import Development
from .trim import strip_points

log = logging.getLogger(__name__)

#: A board shorter than this fraction of the stock, cut at a ruling, is cut inside the quad
#: beyond that ruling instead (where that keeps the stagger): no sliver before a long quad.
SLIVER = 0.5
#: A board shorter than this fraction of the stock along its side A, cut at a ruling, is cut
#: inside the quad beyond it even where that breaks the default stagger (with a warning).
TINY = 0.1


@dataclass(frozen=True)
class Board:
    """Board ``number`` (1-based) of the strip at position ``strip`` of the strip list,
    covering the vertex rows ``start … stop`` (fractional where a joint cuts inside a quad)."""

    strip: int
    number: int
    start: float
    stop: float


def fractional(t: float) -> bool:
    """Whether the row ``t`` lies inside a quad (not on a ruling, to round-off)."""
    return abs(float(t) - float(np.round(t))) > 1e-9


def snapped(t: float) -> float:
    """The row ``t``, on its ruling where it lies there to round-off (:func:`fractional`)."""
    return float(t) if fractional(t) else float(np.round(t))


def knots(a: float, b: float) -> np.ndarray:
    """The rows of a board from ``t = a`` to ``t = b``: ``a``, the rows strictly between,
    ``b`` (fractional ends where a joint cuts inside a quad)."""
    return np.concatenate([[float(a)], np.arange(np.floor(a) + 1.0, np.ceil(b)), [float(b)]])


def strip_between(A: np.ndarray, B: np.ndarray, a: float, b: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The strip ``A, B (m, d)`` (3-D, or its development) from ``t = a`` to ``t = b``: its
    vertices at the rows :func:`knots` (the strip's own vertices at whole rows, the ends of the
    joint at a fractional one). A planar-quad strip again: an end quad is a part of a planar
    quad cut along the straight line ``t = const``."""
    T = knots(a, b)
    return tuple(strip_points(A, B, np.column_stack([T, np.full_like(T, s)]))
                 for s in (0.0, 1.0))


def edge_path(edge: np.ndarray, a: float, b: float) -> np.ndarray:
    """The cut edge ``edge (k, 2)`` (a shared-outline template's curve in the strip's ``(t, s)``,
    from the vertex at row 0 to the vertex at the last row, :mod:`dgpc_cli.strips.cut_edges`)
    from row ``a`` to row ``b``: its samples between and its ends, where it crosses a
    fractional row (a joint inside a quad), else the strip's vertex (as at the strip's ends)."""
    inside = edge[(edge[:, 0] > a) & (edge[:, 0] < b)]
    side = float(edge[0, 1])
    ends = [[r, float(np.interp(r, edge[:, 0], edge[:, 1])) if fractional(r) else side]
            for r in (a, b)]
    return np.concatenate([ends[:1], inside, ends[1:]])


def at_rows(positions: np.ndarray, t) -> np.ndarray:
    """Values ``positions (m,)`` given at the rows, at the (fractional) rows ``t``: linear
    within a quad, as the arc length along its straight sides is."""
    return np.interp(t, np.arange(len(positions), dtype=float), positions)


def last_within(extent, a: float, hi: float, stock: float, steps: int = 60) -> float:
    """The largest ``t`` in ``(a, hi)`` with ``extent(a, t) <= stock`` (bisection; the extent
    grows with the board)."""
    lo = a
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        if hi - lo <= 1e-12 * max(1.0, abs(hi)):
            break
        if extent(a, mid) <= stock:
            lo = mid
        else:
            hi = mid
    return lo


def cut_inside(extent, a: float, nxt: float, stock: float, sides: list, stagger: float,
               cuttable=None, after: float | None = None) -> tuple[float | None, float | None]:
    """Joints inside the quad(s) between the row ``a`` and the next ruling ``nxt`` the board
    can be cut at (:func:`split_run`): ``t_max``, the farthest ``t`` within the stock, and the
    farthest ``t`` up to it that keeps ``stagger`` from the neighbours' joints (``t_max``
    itself, or moved back to the edge of a joint's stagger), beyond the row ``after`` (default
    ``a``); each None where there is none, or ``cuttable(t)`` refuses it. ``sides`` lists
    ``(positions, forbidden)``: the arc lengths ``(m,)`` of a side at the rows and the
    neighbour's joints on it."""
    t_max = last_within(extent, a, nxt, stock)
    if not t_max > a:
        return None, None
    after = a if after is None else after
    rows = np.arange(len(sides[0][0]) if sides else 0, dtype=float)
    edges = np.concatenate([np.interp(np.concatenate([f - stagger, f + stagger]), x, rows)
                            for x, f in sides] + [np.zeros(0)])
    tries = np.concatenate([[t_max], np.sort(edges[(edges > after) & (edges < t_max)])[::-1]])
    if cuttable is not None:
        tries = np.array([t for t in tries if cuttable(t)])
    if tries.size == 0:
        return None, None
    t_max = float(tries[0]) if tries[0] == t_max else None
    keep = np.ones(len(tries), bool)
    for x, f in sides:
        if f.size:
            far = at_rows(x, tries)
            keep &= ((np.min(np.abs(far[:, None] - f[None, :]), axis=1)
                      >= stagger * (1 - 1e-9)) & (far > at_rows(x, a) + 1e-9 * stock))
    tries = tries[keep]
    return t_max, (float(tries[0]) if tries.size else None)


def cumulative(X: np.ndarray) -> np.ndarray:
    """Arc length ``(m,)`` along the polyline ``X (m, d)`` from its first point."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=-1))])


def board_extent(dev: Development, a: float, b: float, cut: list | None = None) -> float:
    """Stock length the rows ``a … b`` (fractional at a joint inside a quad) of the developed
    strip ``dev`` need: the extent of their outline along their own mid-curve chord; with
    ``cut`` (the strip's two cut edges in its ``(t, s)``, :func:`edge_path`) of the outline
    along those too."""
    A, B = strip_between(dev.A, dev.B, a, b)
    chord = 0.5 * (A[-1] + B[-1]) - 0.5 * (A[0] + B[0])
    d = chord / np.linalg.norm(chord)
    along = [] if cut is None else [strip_points(dev.A, dev.B, edge_path(e, a, b)) for e in cut]
    x = np.concatenate([A, B, *along]) @ d
    return float(x.max() - x.min())


def split_run(extent, start: float, stop: float, candidates: list[int], stock: float,
              forbidden: np.ndarray, stagger: float, positions: np.ndarray, name: str,
              relax: bool = False, cuttable=None) -> list[float]:
    """Joint rows of a run of a strip from ``start`` to ``stop`` (rows, or ``t`` where an
    outline ends it): boards no longer than ``stock`` by ``extent(a, b)``, joints among the
    rows ``candidates`` (ascending, inside the run), each as far as the stock allows; a joint
    at row u is allowed when ``positions[u]`` (its arc length along the shared geodesic) is
    at least ``stagger`` from every value of ``forbidden`` (the neighbour's joints there).
    Where no ruling within the stock keeps the stagger: DgpcError, or with ``relax`` (the
    default stagger, not one asked for) the ruling farthest from the neighbour's joints,
    with a warning (rulings farther apart than the stagger leave no choice). Where no ruling
    lies within the stock, or none that keeps the stagger, or the farthest one that does
    leaves a board shorter than :data:`SLIVER` of the stock, the joint is cut inside a quad
    (:func:`cut_inside`; a fractional row), where ``cuttable(t)`` (default: everywhere)
    allows it; with ``relax`` a board shorter than :data:`TINY` of the stock is not left
    for the stagger's sake."""
    joints: list[float] = []
    close: list[tuple[float, float]] = []        # joints nearer the neighbour's than stagger
    a = start
    while True:
        if extent(a, stop) <= stock:
            if close:
                log.warning("%s: %d joint(s) (rows %s) nearer than the stagger (%.4g mm) to the "
                            "joints of the strip beside it (the nearest %.4g): no ruling "
                            "within the stock keeps it there", name, len(close),
                            ", ".join(f"{r:.6g}" for r, _ in close), stagger,
                            min(g for _, g in close))
            return joints
        ahead = [b for b in candidates if b > a]
        ends = [b for b in ahead if extent(a, b) <= stock][::-1]      # farthest first
        if not ends:                 # no ruling within the stock: a joint inside the quad
            nxt = ahead[0] if ahead else stop
            t_max, t_ok = cut_inside(extent, a, nxt, stock, [(positions, forbidden)], stagger,
                                     cuttable)
            if t_max is None and t_ok is None:
                raise DgpcError(f"{name}: from row {a:g} to row {nxt:g} (the next ruling it "
                                f"can be cut at) is {extent(a, nxt):.6g} mm long, more than the "
                                f"stock length ({stock:.6g} mm), and no straight joint inside the "
                                "quad fits the outline there", source="--stock-length")
            if t_ok is None and not relax:
                raise DgpcError(f"{name}: no joint inside the quad after row {a:.6g} keeps "
                                f"the stagger ({stagger:.6g} mm) from the joints of the strip "
                                "beside it; use a smaller --stagger or a longer --stock-length",
                                source="--stagger")
            if t_ok is None:
                close.append((t_max, float(np.min(np.abs(at_rows(positions, t_max)
                                                         - forbidden)))))
            joints.append(t_max if t_ok is None else t_ok)
            a = joints[-1]
            continue
        ok = [b for b in ends if forbidden.size == 0
              or np.min(np.abs(positions[b] - forbidden)) >= stagger]
        later = [b for b in ahead if b > ends[0]]
        nxt = later[0] if later else stop
        t_max = t_ok = None
        if not ok:                   # no ruling keeps the stagger: inside a quad, if one does
            half = last_within(extent, a, nxt, 0.5 * stock)      # boards of half the stock on
            t_max, t_ok = cut_inside(extent, a, nxt, stock, [(positions, forbidden)], stagger,
                                     cuttable, after=min(ends[-1], half))
        elif extent(a, ok[0]) < SLIVER * stock:     # a short board: a longer one inside a quad
            t_max, t_ok = cut_inside(extent, a, nxt, stock, [(positions, forbidden)], stagger,
                                     cuttable, after=ok[0])
        if t_ok is not None:
            ok = [t_ok]
        elif relax and (ok or ends):
            if not ok:               # the ruling farthest from the neighbour's joints
                gap = np.min(np.abs(positions[ends][:, None] - forbidden[None, :]), axis=1)
                ok = [ends[int(np.argmax(gap))]]
            if (t_max is not None and t_max > ok[0]
                    and at_rows(positions, ok[0]) - at_rows(positions, a) < TINY * stock):
                ok = [t_max]         # rather than a sliver of a board
            far = float(np.min(np.abs(at_rows(positions, ok[0]) - forbidden),
                               initial=np.inf))
            if far < stagger:
                close.append((ok[0], far))
        if not ok:
            raise DgpcError(f"{name}: no ruling between rows {ends[-1]} and {ends[0]} keeps "
                            f"the stagger ({stagger:.6g} mm) from the joints of the strip "
                            "beside it; use a smaller --stagger or a longer --stock-length",
                            source="--stagger")
        joints.append(ok[0])
        a = ok[0]


def split_strip(dev: Development, stock: float, forbidden: np.ndarray, stagger: float,
                positions: np.ndarray, name: str, relax: bool = False,
                cut: list | None = None) -> list[float]:
    """Joint rows of one developed strip (:func:`split_run` over all its rows; ``cut`` as in
    :func:`board_extent`)."""
    m = dev.A.shape[0]
    return split_run(lambda a, b: board_extent(dev, a, b, cut), 0, m - 1,
                     list(range(1, m - 1)), stock, forbidden, stagger, positions, name, relax)


def keeps(dev: Development, joints: list[float], stock: float, forbidden: np.ndarray,
          stagger: float, positions: np.ndarray, cut: list | None = None) -> bool:
    """Whether the joint rows ``joints`` of the developed strip ``dev`` give boards within
    ``stock`` whose joints keep ``stagger`` from ``forbidden`` (as in :func:`split_strip`)."""
    cuts = [0, *joints, dev.A.shape[0] - 1]
    if any(b <= a for a, b in zip(cuts[:-1], cuts[1:], strict=True)):
        return False
    if any(board_extent(dev, a, b, cut) > stock
           for a, b in zip(cuts[:-1], cuts[1:], strict=True)):
        return False
    return forbidden.size == 0 or not joints or bool(
        np.min(np.abs(at_rows(positions, joints)[:, None] - forbidden[None, :])) >= stagger)


def split_boards(devs: list[Development], geometry: list, columns: list[int], names: list[str],
                 stock: float, stagger: float, relax: bool = False,
                 cuts: list | None = None) -> list[list[Board]]:
    """Boards of every strip: ``devs[i]`` the development of the strip ``geometry[i] = (A, B)``
    (3-D, for the arc lengths along its geodesics) of net column ``columns[i]``; ``relax`` as
    in :func:`split_run`; ``cuts[i]`` the strip's cut edges in its ``(t, s)`` (None: its sides,
    as :func:`board_extent` takes them)."""
    cuts = cuts or [None] * len(devs)
    if not stock > 0:
        raise DgpcError(f"{stock:g}: must be > 0", source="--stock-length")
    if not stagger >= 0:
        raise DgpcError(f"{stagger:g}: must be >= 0", source="--stagger")
    along_a = [cumulative(np.asarray(A, float)) for A, _ in geometry]
    along_b = [cumulative(np.asarray(B, float)) for _, B in geometry]
    joints: dict[int, list[float]] = {}
    by_column = {int(v): i for i, v in enumerate(columns)}
    out = []
    for i in sorted(range(len(devs)), key=lambda i: columns[i]):
        left = by_column.get(int(columns[i]) - 1)      # shares this strip's side A
        forbidden = (at_rows(along_b[left], joints[left]) if left is not None and left in joints
                     else np.zeros(0))
        joints[i] = split_strip(devs[i], stock, forbidden, stagger, along_a[i], names[i],
                                relax, cuts[i])
        before = by_column.get(int(columns[i]) - 2)
        if (before is not None and before in joints and len(joints[before]) <= len(joints[i])
                and keeps(devs[i], joints[before], stock, forbidden, stagger, along_a[i],
                          cuts[i])):
            joints[i] = list(joints[before])
    for i in range(len(devs)):
        cuts = [0, *joints[i], devs[i].A.shape[0] - 1]
        out.append([Board(i, k + 1, a, b)
                    for k, (a, b) in enumerate(zip(cuts[:-1], cuts[1:], strict=True))])
    return out
