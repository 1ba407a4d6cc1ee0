"""``dgpc init --method geodesic`` chooses its net by the result, not the start (SPEC §5; issue:
a roof whose best start, fitted, covered 54 % of it, where other options reached 98 %).

It searches three things the user did not give:

* the base curve (``layout.choice.candidates``: a sweep of sections, the boundary curves,
  the sections across the longest extents), unless ``--base``, ``--direction`` or ``--angle``
  names one;
* the overhang, unless ``--extend`` is given or the mesh is closed: when the best candidate
  kept on the mesh covers less than :data:`EXTEND_BELOW` of it, the :data:`EXTEND_CANDIDATES`
  best base curves are traced again on the mesh continued by each of :data:`EXTEND_STEPS` (of
  its diagonal) in turn, up to the largest continuation that does not fold, until one covers
  :data:`EXTEND_ENOUGH` or more overhang covers no more;
* the size, unless ``--cols`` or ``--edge-length`` is given: the best net so far made again
  with each of :data:`SIZES` columns, and, where a largest strip width is set
  (``layout.width``), the best net made again with as many more columns as bring its
  widest strip within it.

Candidates are ranked after a quick fit: the :data:`FINALISTS` best of each round (by the
coverage of the net as traced) get :data:`QUICK_FIT_ITERATIONS` iterations of ``optimize
--mode fit`` (its weights, its polish of a nearly gpc net), and are measured again: the
coverage of the reference (``metrics.coverage``, on the mesh itself: what trimmed strips can
clad), whether the fitted net folds (``metrics.degenerate``), and how much its strips vary in
width along themselves over the reference (``metrics.width_ratio``). The choice: of the nets
that do not fold, those within :data:`COVERAGE_SLACK` of the best coverage; of those the one
whose widths vary least, within :data:`WIDTH_SLACK`; ties go to the earlier candidate (an
old default, less overhang, fewer columns). With a largest strip width and the columns
``init``'s to choose, the nets within it are ranked first (any net there is). Every candidate
tried is recorded with its figures.

The quick fit itself is the caller's (:data:`NetFit`: ``stages.init`` runs ``optimize --mode
fit``'s solver), so that laying nets on meshes stays below the stages.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.extension import continued, largest_unfolded, surrounded
from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.layout.choice import (
    COVERAGE_SAMPLES,
    Candidate,
    Outcome,
    candidates,
    evaluate_all,
    no_sound_net,
    option,
)
from dgpc_cli.layout.grids import DEFAULT_COLS, MeshGrid, MeshTracing
from dgpc_cli.layout.width import widen, widest_on, width_record
from dgpc_cli.metrics.coverage import coverage, default_tolerance
from dgpc_cli.metrics.degenerate import degeneracies
from dgpc_cli.metrics.width_ratio import width_figures

log = logging.getLogger(__name__)

#: Iterations of the quick fit that ranks the finalists (the fit itself takes 20–40; after 5 a
#: fit has not yet pulled in what it will, after 10 mostly has: an apse roof at 98.5 % as traced
#: read 97.7 % after 5, 93.9 % after 10, 92.1 % after 20 and at the end).
QUICK_FIT_ITERATIONS = 10
#: Candidates of each round (by the coverage of the traced net) that get a quick fit.
FINALISTS = 3
#: An overhang is searched when the best net kept on the mesh covers less than this.
EXTEND_BELOW = 0.97
#: The overhangs tried, fractions of the reference's bounding-box diagonal (``--extend``).
EXTEND_STEPS = (0.1, 0.2, 0.3)
#: ... no further once the best net covers this much.
EXTEND_ENOUGH = 0.99
#: The base curves carried on to each overhang: the best of the nets kept on the mesh.
EXTEND_CANDIDATES = 3
#: The overhang at the fold limit is tried only when it is at least this much beyond the last
#: step tried.
EXTEND_MIN_STEP = 0.02
#: Columns tried for the best net, besides :data:`~dgpc_cli.layout.grids.DEFAULT_COLS`.
SIZES = (31, 41)
#: Nets covering within this of the best count as covering as much.
COVERAGE_SLACK = 0.005
#: ... and of those, nets whose strip widths vary within this fraction of the least variation
#: count as varying as little (the earlier candidate wins).
WIDTH_SLACK = 0.1


#: A few iterations of ``optimize --mode fit``: ``fit(f, surface, on_mesh, iterations)`` fits
#: the net ``f (m, n, 3)`` to ``surface`` (a ``core.reference.ReferenceSurface``; ``on_mesh``:
#: the net is traced on the mesh itself, no overhang, so its rim is held to the mesh's
#: boundary) and returns the fitted net and the iterations run; DgpcError when it cannot run.
NetFit = Callable[[np.ndarray, ReferenceSurface, bool, int], tuple[np.ndarray, int]]


@dataclass
class Trial:
    """One candidate made over one overhang at one size: its record, its sound net (None when
    it failed) and the figures of its quick fit (None until it had one)."""

    cand: Candidate
    extend: float
    cols: int | None
    record: dict
    outcome: Outcome | None
    quick: dict | None = None

    @property
    def scored(self) -> bool:
        return self.quick is not None and "coverage" in self.quick

    def describe(self) -> str:
        """``"section 90° (--extend 0.2, 31 columns)"``."""
        extra = ([f"--extend {self.extend:g}"] if self.extend else []) + \
            ([f"{self.cols} columns"] if self.cols is not None else [])
        return self.cand.label + (f" ({', '.join(extra)})" if extra else "")


@dataclass
class SearchResult:
    """The chosen net, its outcome and overhang, every trial, the search's record and the
    record of its largest strip width (``layout.width.width_record``, None without a
    limit); ``narrowed``."""

    grid: MeshGrid
    outcome: Outcome
    extend: float
    chosen: Trial
    why: str
    trials: list[Trial] = field(default_factory=list)
    record: dict = field(default_factory=dict)
    width: dict | None = None
    #: With ``defer_width``: the result within the largest strip width (the search goes on,
    #: its progress to the callback given), None when there is nothing to do.
    narrowed: Callable[..., SearchResult] | None = None


def _on_reference(f: np.ndarray, reference: ReferenceSurface, tolerance: float) -> np.ndarray:
    """``(m, n−1)``: whether the middle of each v-edge of ``f`` lies within ``tolerance`` of
    the reference (an overhang's edges beyond the outline do not)."""
    mid = 0.5 * (f[:, 1:] + f[:, :-1])
    foot, _ = reference.closest(mid.reshape(-1, 3))
    return (np.linalg.norm(mid.reshape(-1, 3) - foot, axis=1) <= tolerance).reshape(
        mid.shape[:2])


def quick_fit(mesh: ReferenceMesh, surface: ReferenceSurface, grid: MeshGrid,
              extend: float, fit: NetFit, iterations: int = QUICK_FIT_ITERATIONS,
              reference: ReferenceSurface | None = None) -> dict:
    """The figures of the net of ``grid`` after ``iterations`` of ``optimize --mode fit``
    (``fit``) to ``surface`` (the mesh, or its continuation for an overhang): ``coverage`` of
    ``mesh``, ``iterations`` run, ``folded``, ``width_ratio`` and ``narrowest`` (over the
    reference, see :func:`~dgpc_cli.metrics.width_ratio.width_figures`); ``{"failed":
    reason}`` when the fit cannot run. ``reference``: ``surface`` of the mesh itself, when
    made already."""
    reference = ReferenceSurface(mesh.vertices, mesh.faces) if reference is None else reference
    try:
        fitted, done = fit(grid.net.f, surface, not extend, iterations)
    except DgpcError as err:
        return {"failed": err.reason}
    cov = coverage(fitted, mesh.vertices, mesh.faces, samples=COVERAGE_SAMPLES,
                   surface=reference)["area_fraction"]
    widths = width_figures(fitted, _on_reference(fitted, reference,
                                                 default_tolerance(mesh.vertices)))
    return {"coverage": cov, "iterations": done, "folded": bool(degeneracies(fitted)),
            **(widths or {})}


def _cover(t: Trial) -> float:
    return t.quick["coverage"] if t.scored else (t.outcome.coverage if t.outcome else -1.0)


def _fits(t: Trial, limit: float | None) -> bool:
    """Whether the trial's widest strip is within ``limit`` (None: no limit)."""
    w = t.record.get("widest")
    return limit is None or w is None or w <= limit * (1 + 1e-9)


def _rank(trials: list[Trial], limit: float | None = None) -> tuple[Trial, str]:
    """The trial chosen (see the module) and why, in a few words; ``limit``: the largest
    strip width, the nets within it ranked first."""
    if len(trials) == 1:
        return trials[0], "is the one the options name"
    scored = [t for t in trials if t.scored]
    if not scored:
        sound = [t for t in trials if t.outcome is not None]
        sound = [t for t in sound if _fits(t, limit)] or sound
        best = max(t.outcome.coverage for t in sound)
        chosen = next(t for t in sound if t.outcome.coverage >= best - COVERAGE_SLACK)
        return chosen, "covers most as traced"
    unfolded = [t for t in scored if not t.quick["folded"]]
    folded = len(scored) - len(unfolded)
    pool = unfolded or scored
    fitting = [t for t in pool if _fits(t, limit)]
    narrow = (f"; {len(pool) - len(fitting)} with strips wider than {limit:.3g} left out"
              if fitting and len(fitting) < len(pool) else "")
    pool = fitting or pool
    best = max(t.quick["coverage"] for t in pool)
    close = [t for t in pool if t.quick["coverage"] >= best - COVERAGE_SLACK]
    least = min(t.quick.get("width_ratio", math.inf) for t in close)
    chosen = next(t for t in close
                  if t.quick.get("width_ratio", math.inf) <= least * (1 + WIDTH_SLACK))
    note = (f"; {folded} folded in the quick fit" if folded and unfolded else "") + narrow
    if len(close) == 1:
        rest = sorted((t for t in pool if t is not chosen), key=_cover, reverse=True)
        runner = (f", next {rest[0].describe()} {100 * _cover(rest[0]):.1f} %" if rest else "")
        return chosen, f"covers most after a quick fit{runner}{note}"
    return chosen, (f"covers as much as {len(close) - 1} other(s) (within "
                    f"{100 * COVERAGE_SLACK:g} %) with strip widths varying least "
                    f"({chosen.quick.get('width_ratio', math.nan):.2f}× along a strip){note}")


def search(mesh: ReferenceMesh, *, fit: NetFit, base: str | None = None, direction=None,
           angle: float | None = None, rows: int | None = None, cols: int | None = None,
           spacing: float | None = None, extend: float | None = None,
           surroundings: ReferenceMesh | None = None,
           progress: Callable[[str], None] | None = None,
           strip_width: float | None = None, strip_width_given: bool = False,
           widen_cols: bool | None = None, defer_width: bool = False) -> SearchResult:
    """The net ``init --method geodesic`` writes for ``mesh`` (see the module), its candidates
    ranked after a quick ``fit``; ``extend`` None: searched, else that overhang
    (``--extend``). ``surroundings``: the whole mesh ``mesh`` is a patch of, which an overhang
    runs onto (:func:`~dgpc_cli.geodesics.extension.surrounded`) instead of the patch's
    continuation.
    ``strip_width``: the largest strip width (model unit; None: none), ``strip_width_given``
    whether the user gave it; ``widen_cols``: whether the columns are ``init``'s to choose
    (default: neither ``cols`` nor ``spacing`` given), starting from ``cols``;
    ``defer_width``: the net too wide is made again only when the caller asks for it
    (``SearchResult.narrowed``: ``init`` first decides on patches by the net as chosen)."""
    say = progress or (lambda text: None)
    given_extend = extend is not None
    if widen_cols is None:
        widen_cols = cols is None and spacing is None
    size = {"rows": rows, "cols": cols, "spacing": spacing}
    e0 = float(extend) if given_extend else 0.0
    diagonal = mesh.bbox_diagonal
    trials: list[Trial] = []
    reference = ReferenceSurface(mesh.vertices, mesh.faces)
    tolerance = default_tolerance(mesh.vertices)
    domains: dict[float, tuple[ReferenceMesh, MeshTracing, ReferenceSurface]] = {}

    def domain_of(e: float) -> ReferenceMesh:
        """The mesh continued by ``e`` (made once), its tracing and its surface (what the
        quick fit fits to)."""
        if e not in domains:
            dom = (continued(mesh, e) if surroundings is None
                   else surrounded(mesh, surroundings, e))
            domains[e] = (dom, MeshTracing.of(dom),
                          reference if not e else ReferenceSurface(dom.vertices, dom.faces))
        return domains[e][0]

    def finalize(round_trials: list[Trial], count: int = FINALISTS) -> None:
        ready = sorted((t for t in round_trials if t.outcome is not None),
                       key=lambda t: -t.outcome.coverage)[:count]
        for t in ready:
            say(f"quick fit of {t.describe()}")
            t.quick = quick_fit(mesh, domains[t.extend][2], t.outcome.grid, t.extend, fit,
                                reference=reference)
            t.record["quick_fit"] = t.quick
            if t.scored:
                log.info("%s: after a quick fit covers %.1f %%%s, widths vary %.2f×",
                         t.describe(), 100 * t.quick["coverage"],
                         " (folded)" if t.quick["folded"] else "",
                         t.quick.get("width_ratio", math.nan))

    def run(cand_list: list[Candidate], e: float, dom: ReferenceMesh, sz: dict,
            explicit: bool = False) -> list[Trial]:
        out = []
        for i, cand in enumerate(cand_list):
            say(f"{cand.label}" + (f", --extend {e:g}" if e else "")
                + (f", {sz['cols']} columns" if sz["cols"] != size["cols"] else "")
                + f" ({i + 1}/{len(cand_list)})")
            [(record, outcome)] = evaluate_all(mesh, dom, "geodesic", [cand], sz,
                                               e * diagonal, explicit=explicit,
                                               tracing=domains[e][1], surface=reference,
                                               relocate=surroundings is not None and e > 0)
            record.update(cand.record())
            record.update({"extend": e, "cols": sz["cols"]})
            if strip_width is not None and outcome is not None:
                record.update(widest_on(outcome.grid.net.f, reference, tolerance) or {})
            t = Trial(cand, e, sz["cols"], record, outcome)
            out.append(t)
        trials.extend(out)
        return out

    # the base curves, on the mesh (or over the overhang given)
    dom = domain_of(e0)
    cands = candidates(mesh, "geodesic", base=base, direction=direction, angle=angle,
                       frame=dom)
    explicit = len(cands) == 1
    first = run(cands, e0, dom, size, explicit=explicit)
    if not any(t.outcome for t in first):
        raise no_sound_net(mesh, [t.record for t in first])
    finalize(first)
    fold_limit = None
    tried_extends = [e0]
    # the overhang
    best, _ = _rank(trials)
    if not given_extend and _cover(best) < EXTEND_BELOW and domains[e0][1].bounded:
        carried = [t.cand for t in sorted((t for t in first if t.outcome is not None),
                                          key=lambda t: -_cover(t))[:EXTEND_CANDIDATES]]
        previous = _cover(best)
        for step in EXTEND_STEPS:
            e = step
            try:
                dom = domain_of(e)
            except DgpcError as err:
                log.info("--extend %g: %s", e, err.reason)
                fold_limit = math.floor(1000 * largest_unfolded(mesh, e, steps=6)) / 1000
                e = fold_limit
                if e < tried_extends[-1] + EXTEND_MIN_STEP:
                    break
                try:
                    dom = domain_of(e)
                except DgpcError:
                    break
            tried_extends.append(e)
            level = run(carried, e, dom, size)
            finalize(level)
            scored = [_cover(t) for t in level if t.scored and not t.quick["folded"]]
            level_best = max(scored, default=-1.0)
            if level_best >= EXTEND_ENOUGH or level_best < previous - COVERAGE_SLACK \
                    or e != step:
                break
            previous = max(previous, level_best)
    # the size
    sizes = []
    if cols is None and spacing is None:
        best, _ = _rank(trials)
        sizes = [n for n in SIZES if n != DEFAULT_COLS]
        for n in sizes:
            sz = {**size, "cols": n}
            finalize(run([best.cand], best.extend, domain_of(best.extend), sz), count=1)

    def result(narrow: bool) -> SearchResult:
        """The search's result; ``narrow``: the largest strip width kept (the net made again
        with more columns where it is too wide), else only measured."""
        steps = []
        if strip_width is not None:
            steps = (_widened(trials, run, finalize, domain_of, size, strip_width,
                              widen_cols and narrow))
        chosen, why = _rank(trials, strip_width if widen_cols and narrow else None)
        width = (width_record(strip_width, strip_width_given, widen_cols, steps,
                              _width_step(chosen, spacing)) if strip_width is not None
                 else None)
        record = {"quick_fit_iterations": QUICK_FIT_ITERATIONS, "extends": tried_extends,
                  "fold_limit": fold_limit, "sizes": [DEFAULT_COLS if cols is None else cols,
                                                      *sizes] if spacing is None else [],
                  "candidates": len(trials),
                  "quick_fits": sum(t.quick is not None for t in trials),
                  "options": _options(chosen), "why": why}
        later = _later if not narrow else None
        return SearchResult(chosen.outcome.grid, chosen.outcome, chosen.extend, chosen, why,
                            trials, record, width, later)

    def _later(progress_later: Callable[[str], None] | None = None) -> SearchResult:
        nonlocal say
        say = progress_later or say
        return result(True)

    return result(not defer_width or strip_width is None or not widen_cols)


def _cols_of(t: Trial, spacing: float | None = None) -> int | None:
    """The columns a trial was asked for (a degenerate net may be cut to fewer); None for
    ``--edge-length``."""
    return t.cols if t.cols is not None else (DEFAULT_COLS if spacing is None else None)


def _width_step(t: Trial, spacing: float | None = None) -> dict:
    return {"candidate": t.describe(), "cols": _cols_of(t, spacing),
            "shape": list(t.outcome.grid.net.shape) if t.outcome else None,
            "widest": t.record.get("widest"), "strip": t.record.get("strip")}


def _widened(trials, run, finalize, domain_of, size, limit, widen_cols) -> list[dict]:
    """The steps of the largest strip width (``layout.width.widen``): the best trial
    (ranked without the limit) and, when ``widen_cols``, the same candidate made again with
    more columns while its widest strip exceeds ``limit``, each with its quick fit."""
    best, _ = _rank(trials)
    if not widen_cols:
        return [_width_step(best, size["spacing"])]

    def make(n: int) -> Trial | None:
        [t] = run([best.cand], best.extend, domain_of(best.extend), {**size, "cols": n})
        if t.outcome is None:
            return None
        finalize([t], count=1)
        return t

    steps = widen(best, make, lambda t: t.record.get("widest"), _cols_of, limit)
    return [_width_step(t) for t in steps]


def _options(t: Trial) -> str:
    """The ``init`` options that make the chosen net again."""
    parts = [option(t.cand, by_direction=bool(t.extend))]
    if t.extend:
        parts.append(f"--extend {t.extend:g}")
    if t.cols is not None:
        parts.append(f"--cols {t.cols}")
    return " ".join(parts)
