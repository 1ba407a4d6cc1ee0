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
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError

from .develop import Development

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Board:
    """Board ``number`` (1-based) of the strip at position ``strip`` of the strip list,
    covering the vertex rows ``start … stop``."""

    strip: int
    number: int
    start: int
    stop: int


def cumulative(X: np.ndarray) -> np.ndarray:
    """Arc length ``(m,)`` along the polyline ``X (m, d)`` from its first point."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=-1))])


def board_extent(dev: Development, a: int, b: int) -> float:
    """Stock length the rows ``a … b`` of the developed strip ``dev`` need: the extent of
    their outline along their own mid-curve chord."""
    mid = 0.5 * (dev.A + dev.B)
    chord = mid[b] - mid[a]
    d = chord / np.linalg.norm(chord)
    x = np.concatenate([dev.A[a:b + 1], dev.B[a:b + 1]]) @ d
    return float(x.max() - x.min())


def split_run(extent, start: float, stop: float, candidates: list[int], stock: float,
              forbidden: np.ndarray, stagger: float, positions: np.ndarray, name: str,
              relax: bool = False) -> list[int]:
    """Joint rows of a run of a strip from ``start`` to ``stop`` (rows, or ``t`` where an
    outline ends it): boards no longer than ``stock`` by ``extent(a, b)``, joints among the
    rows ``candidates`` (ascending, inside the run), each as far as the stock allows; a joint
    at row u is allowed when ``positions[u]`` (its arc length along the shared geodesic) is
    at least ``stagger`` from every value of ``forbidden`` (the neighbour's joints there).
    Where no ruling within the stock keeps the stagger: DgpcError, or with ``relax`` (the
    default stagger, not one asked for) the ruling farthest from the neighbour's joints,
    with a warning (rulings farther apart than the stagger leave no choice)."""
    joints: list[int] = []
    close: list[tuple[int, float]] = []          # joints nearer the neighbour's than stagger
    a = start
    while True:
        if extent(a, stop) <= stock:
            if close:
                log.warning("%s: %d joint(s) (rows %s) nearer than the stagger %.4g to the "
                            "joints of the strip beside it (the nearest %.4g): no ruling "
                            "within the stock keeps it there", name, len(close),
                            ", ".join(str(r) for r, _ in close), stagger,
                            min(g for _, g in close))
            return joints
        ahead = [b for b in candidates if b > a]
        ends = [b for b in ahead if extent(a, b) <= stock][::-1]      # farthest first
        if not ends:
            nxt = ahead[0] if ahead else stop
            raise DgpcError(f"{name}: from row {a:g} to row {nxt:g} (the next ruling it can be "
                            f"cut at) is {extent(a, nxt):.6g} long, more than the stock "
                            f"length {stock:.6g}", source="--stock-length")
        ok = [b for b in ends if forbidden.size == 0
              or np.min(np.abs(positions[b] - forbidden)) >= stagger]
        if not ok and relax:
            gap = np.min(np.abs(positions[ends][:, None] - forbidden[None, :]), axis=1)
            ok = [ends[int(np.argmax(gap))]]
            close.append((ok[0], float(gap.max())))
        if not ok:
            raise DgpcError(f"{name}: no ruling between rows {ends[-1]} and {ends[0]} keeps "
                            f"{stagger:.6g} from the joints of the strip beside it; use a "
                            "smaller --stagger or a longer --stock-length", source="--stagger")
        joints.append(ok[0])
        a = ok[0]


def split_strip(dev: Development, stock: float, forbidden: np.ndarray, stagger: float,
                positions: np.ndarray, name: str, relax: bool = False) -> list[int]:
    """Joint rows of one developed strip (:func:`split_run` over all its rows)."""
    m = dev.A.shape[0]
    return split_run(lambda a, b: board_extent(dev, a, b), 0, m - 1, list(range(1, m - 1)),
                     stock, forbidden, stagger, positions, name, relax)


def keeps(dev: Development, joints: list[int], stock: float, forbidden: np.ndarray,
          stagger: float, positions: np.ndarray) -> bool:
    """Whether the joint rows ``joints`` of the developed strip ``dev`` give boards within
    ``stock`` whose joints keep ``stagger`` from ``forbidden`` (as in :func:`split_strip`)."""
    cuts = [0, *joints, dev.A.shape[0] - 1]
    if any(b <= a for a, b in zip(cuts[:-1], cuts[1:], strict=True)):
        return False
    if any(board_extent(dev, a, b) > stock for a, b in zip(cuts[:-1], cuts[1:], strict=True)):
        return False
    return forbidden.size == 0 or not joints or bool(
        np.min(np.abs(positions[joints][:, None] - forbidden[None, :])) >= stagger)


def split_boards(devs: list[Development], geometry: list, columns: list[int], names: list[str],
                 stock: float, stagger: float, relax: bool = False) -> list[list[Board]]:
    """Boards of every strip: ``devs[i]`` the development of the strip ``geometry[i] = (A, B)``
    (3-D, for the arc lengths along its geodesics) of net column ``columns[i]``; ``relax`` as
    in :func:`split_run`."""
    if not stock > 0:
        raise DgpcError(f"{stock:g}: must be > 0", source="--stock-length")
    if not stagger >= 0:
        raise DgpcError(f"{stagger:g}: must be >= 0", source="--stagger")
    along_a = [cumulative(np.asarray(A, float)) for A, _ in geometry]
    along_b = [cumulative(np.asarray(B, float)) for _, B in geometry]
    joints: dict[int, list[int]] = {}
    by_column = {int(v): i for i, v in enumerate(columns)}
    out = []
    for i in sorted(range(len(devs)), key=lambda i: columns[i]):
        left = by_column.get(int(columns[i]) - 1)      # shares this strip's side A
        forbidden = (along_b[left][joints[left]] if left is not None and left in joints
                     else np.zeros(0))
        joints[i] = split_strip(devs[i], stock, forbidden, stagger, along_a[i], names[i],
                                relax)
        before = by_column.get(int(columns[i]) - 2)
        if (before is not None and before in joints and len(joints[before]) <= len(joints[i])
                and keeps(devs[i], joints[before], stock, forbidden, stagger, along_a[i])):
            joints[i] = list(joints[before])
    for i in range(len(devs)):
        cuts = [0, *joints[i], devs[i].A.shape[0] - 1]
        out.append([Board(i, k + 1, a, b)
                    for k, (a, b) in enumerate(zip(cuts[:-1], cuts[1:], strict=True))])
    return out
