"""``dgpc init MESH --strip-width``: the largest strip width of a net made on a mesh (issue: on
an arched roof of 40 × 39 m the default net's strips were 2.75 m wide on average and up to
4 m, so that no part of it could fit a 2500 mm sheet).

A strip's width at a row is its v-edge there (``metrics.width_ratio.widest_strip``), counted
where the edge lies on the reference (its middle or an end within the coverage tolerance of
it: an overhang's edges beyond the outline are trimmed away). Where ``init`` chooses the
columns itself (neither ``--cols`` nor ``--edge-length``), a net whose widest strip exceeds the
limit is made again with ``ceil((n − 1) · widest / limit) + 1`` columns (the base curve's band
split finer: the widths shrink in proportion), at most :data:`WIDEN_STEPS` times and to at most
:data:`MAX_COLS` columns. Given columns or edge length win: ``init`` then only warns where a
given ``--strip-width`` is exceeded.

Default limit: :data:`DEFAULT_STRIP_WIDTH_MM` for a mesh whose unit is given (``--units``);
none for a mesh without a unit, whose size ``init`` does not know.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import TypeVar

import numpy as np

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.layout.grids import DEFAULT_COLS
from dgpc_cli.metrics.coverage import default_tolerance
from dgpc_cli.metrics.width_ratio import widest_strip

log = logging.getLogger(__name__)

#: The default largest strip width, mm: a 2500 mm sheet (``nest --sheet 6100x2500``, the
#: usual board) less its margins (10–25 mm each side, ``nest --tool``) and some room for a
#: board that curves in the plane (its bounding box is wider than its widest cross-section).
DEFAULT_STRIP_WIDTH_MM = 2400.0
#: A net too wide is made again at most this many times.
WIDEN_STEPS = 3
#: ... and with at most this many columns (the fit of a finer net takes long and may pleat).
MAX_COLS = 101

T = TypeVar("T")


def plausible_spans(diagonal: float, units: str) -> dict:
    """Where a plain ``--edge-length`` and ``--strip-width`` are plausible on a mesh whose
    bounding-box diagonal is ``diagonal`` (in ``units``): an edge up to half the diagonal (a
    net of three columns at least), a strip width from a thousandth of the diagonal to the
    diagonal (:class:`~dgpc_cli.io.length.Span`, mm; the rule of every length,
    :mod:`dgpc_cli.io.length`)."""
    from dgpc_cli.io.length import Span

    k = mm_per_unit(units)
    return {"--edge-length": Span(0.0, 0.5 * diagonal * k, "edge", low_open=True,
                                  high_text=f"half the mesh's diagonal ({0.5 * diagonal:.4g} "
                                            f"{units})"),
            "--strip-width": Span(1e-3 * diagonal * k, diagonal * k, "strip width",
                                  low_text=f"a thousandth of the mesh's diagonal "
                                           f"({1e-3 * diagonal:.4g} {units})",
                                  high_text=f"the mesh's diagonal ({diagonal:.4g} {units})")}


def default_limit(units: str, units_given: bool) -> float | None:
    """The largest strip width without ``--strip-width``, in ``units``: the default for a mesh
    whose unit is given, None for a mesh without one."""
    return DEFAULT_STRIP_WIDTH_MM / mm_per_unit(units) if units_given else None


def reference_edges(f: np.ndarray, surface, tolerance: float) -> np.ndarray:
    """``(m, n−1)``: whether each v-edge of the net ``f (m, n, 3)`` lies on the reference
    ``surface`` (a ``core.reference.ReferenceSurface``): its middle or one of its ends within
    ``tolerance`` of it."""
    f = np.asarray(f, float)
    m, n = f.shape[:2]
    ends = f.reshape(-1, 3)
    mids = (0.5 * (f[:, 1:] + f[:, :-1])).reshape(-1, 3)
    points = np.concatenate([ends, mids])
    foot, _ = surface.closest(points)
    near = np.linalg.norm(points - foot, axis=1) <= tolerance
    on_end = near[:m * n].reshape(m, n)
    return near[m * n:].reshape(m, n - 1) | on_end[:, 1:] | on_end[:, :-1]


def widest_on(f: np.ndarray, surface, tolerance: float) -> dict | None:
    """``{"widest": width, "strip": "S-v07"}`` of the net ``f`` over its v-edges on the
    reference (:func:`reference_edges`); None when no edge lies on it."""
    found = widest_strip(f, reference_edges(f, surface, tolerance))
    if found is None:
        return None
    return {"widest": found[0], "strip": f"S-v{found[1]:02d}"}


def next_cols(cols: int, widest: float, limit: float) -> int | None:
    """The columns that bring a net of ``cols`` columns whose widest strip is ``widest`` within
    ``limit``: ``ceil((cols − 1) · widest / limit) + 1``, at least one more, at most
    :data:`MAX_COLS`; None when ``cols`` is there already."""
    if cols >= MAX_COLS:
        return None
    return min(MAX_COLS, max(cols + 1, math.ceil((cols - 1) * widest / limit - 1e-9) + 1))


def widen(first: T, make: Callable[[int], T | None], widest: Callable[[T], float | None],
          cols: Callable[[T], int], limit: float) -> list[T]:
    """The nets made one after the other from ``first`` while the last one's ``widest`` strip
    exceeds ``limit``: ``make(n)`` makes the net again with ``n`` columns (:func:`next_cols`;
    None when it cannot), ``cols`` tells the columns a net was asked for. At most
    :data:`WIDEN_STEPS` nets more; the last is the one to keep."""
    steps = [first]
    while len(steps) <= WIDEN_STEPS:
        w = widest(steps[-1])
        if w is None or w <= limit:
            break
        n = next_cols(cols(steps[-1]), w, limit)
        made = make(n) if n is not None else None
        if made is None:
            break
        steps.append(made)
    return steps


def width_record(limit: float, given: bool, widen_allowed: bool, steps: list[dict],
                 chosen: dict) -> dict:
    """What a net records of its largest strip width (``data.init.choice.strip_width``):
    ``limit`` (model unit), whether it was ``given`` (``--strip-width``) or the default,
    whether ``init`` chose the columns (``chooses_columns``), the nets made for it
    (``steps``: each one's ``cols`` and ``widest`` strip, the first the one the choice made
    without the limit), the net kept (its ``cols``, ``widest`` strip and ``strip``), and
    whether it is ``within`` the limit."""
    w = chosen.get("widest")
    return {"limit": limit, "given": given, "chooses_columns": widen_allowed, "steps": steps,
            "cols": chosen.get("cols"), "widest": w, "strip": chosen.get("strip"),
            "within": w is None or w <= limit * (1 + 1e-9)}


def width_line(record: dict | None, units: str, what: str = "",
               options: str | None = None) -> str | None:
    """The stderr line of a net's largest strip width when there is something to say (the
    net made again, or wider than the limit), else None; ``what``: the net's name
    (``n0.p1: ``); ``options``: the options that make the net kept again. :func:`tell` says
    it."""
    if not record:
        return None
    steps, limit = record["steps"], record["limit"]
    first = steps[0]

    def length(x):
        return "?" if x is None else f"{x:.3g} {units}"

    if len(steps) > 1:
        tail = ("" if record["within"] else
                f"; still wider than {length(limit)} (at most {MAX_COLS} columns or "
                f"{WIDEN_STEPS} tries): give --edge-length or --patches")
        return (f"{what}strips up to {length(first['widest'])} wide at {first['cols']} "
                f"columns, more than the largest strip width {length(limit)}"
                f"{'' if record['given'] else ' (default)'}: made again with "
                f"{', '.join(str(x['cols']) for x in steps[1:])} columns; kept "
                f"{record['cols']} columns, widest {length(record['widest'])}"
                + (f" (options: {options})" if options else "") + tail)
    if not record["within"] and (record["given"] or record["chooses_columns"]):
        how = ("given columns or --edge-length win" if not record["chooses_columns"] else
               "no net with more columns could be made")
        name = "--strip-width" if record["given"] else "the largest strip width (default)"
        return (f"{what}the widest strip ({record['strip']}) is "
                f"{length(record['widest'])}, more than {name} {length(limit)} ({how})")
    return None


def widened_choice(mesh, first: tuple, make: Callable[[int], tuple], cols: int | None,
                   limit: float, given: bool, widen_cols: bool) -> tuple[tuple, dict]:
    """The choice of ``layout.choice.choose`` (``first``: its ``(grid, outcome, tried)``
    with ``cols`` columns, None: the default) within the largest strip width ``limit`` on
    ``mesh``: when ``widen_cols``, made again by ``make(n)`` (``choose`` with ``n`` columns)
    while too wide (:func:`widen`); the choice kept and its :func:`width_record`."""
    surface = ReferenceSurface(mesh.vertices, mesh.faces)
    tolerance = default_tolerance(mesh.vertices)

    def step(choice: tuple, n: int | None) -> dict:
        grid = choice[0]
        return {"candidate": grid.label, "cols": n, "shape": list(grid.net.shape),
                **(widest_on(grid.net.f, surface, tolerance) or {}), "choice": choice}

    def again(n: int) -> dict | None:
        try:
            return step(make(n), n)
        except DgpcError as err:
            log.info("%d columns: %s", n, err.reason)
            return None

    start = step(first, cols if cols is not None or not widen_cols else DEFAULT_COLS)
    steps = (widen(start, again, lambda s: s.get("widest"), lambda s: s["cols"], limit)
             if widen_cols else [start])
    kept = steps[-1]
    plain = [{k: v for k, v in s.items() if k != "choice"} for s in steps]
    return kept["choice"], width_record(limit, given, widen_cols, plain, plain[-1])


def require_met(record: dict | None, units: str, what: str = "") -> None:
    """Refuse (DgpcError naming ``--strip-width``, exit 1, before anything is written) a net
    wider than a *given* ``--strip-width`` where ``init`` chose the columns: no net it may
    make meets the request (``--strip-width 1e-9m``). The default limit, and a given one that
    given ``--cols`` or ``--edge-length`` win over, only warn (:func:`tell`)."""
    if not record or record["within"] or not (record["given"] and record["chooses_columns"]):
        return
    raise DgpcError(f"{what}{record['limit']:.4g} {units} cannot be met: the strips are up to "
                    f"{record['widest']:.4g} {units} wide with {record['cols']} columns, and "
                    f"init makes at most {MAX_COLS} columns in {WIDEN_STEPS} tries; give a "
                    "larger --strip-width, or --patches to split the mesh",
                    source="--strip-width")


def tell(record: dict | None, units: str, say: Callable[[str], None] | None,
         what: str = "", options: str | None = None) -> None:
    """Say the :func:`width_line` of ``record``: a net made within the limit as ``init``'s
    progress (``say``, when given), a net wider than the limit as a warning; a given limit
    that cannot be met is an error (:func:`require_met`)."""
    require_met(record, units, what)
    line = width_line(record, units, what, options)
    if line is None:
        return
    if not record["within"]:
        log.warning("%s", line)
    elif say is not None:
        say(f"init: {line}")
