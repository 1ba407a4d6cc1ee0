"""``dgpc optimize``: guided projection of a net in one of the modes of SPEC §4."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.core.problem import Problem, constraint_error, mean_edge_length
from dgpc_cli.core.solver import Schedule, SolverResult, guided_projection
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.metrics.degenerate import degeneracies
from dgpc_cli.metrics.residuals import gpc_angle_defect, pleat
from dgpc_cli.metrics.strain import strain
from dgpc_cli.mold.isometry import panel_errors
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)


@dataclass
class OptimizeOutcome:
    """The optimized vertices and a record of how the solver got there."""

    f: np.ndarray
    status: str
    message: str
    steps: list[SolverResult]
    residuals: dict[str, float]
    R: float
    max_iter: int = 0
    #: Hard terms the net was finally projected without (``RELEASE_R``); R leaves them out.
    released: tuple[str, ...] = ()

    @property
    def iterations(self) -> int:
        return sum(r.iterations for r in self.steps)

    @property
    def converged(self) -> bool:
        return self.status == "converged"

    def record(self) -> dict:
        """Deterministic summary for the artifact's ``status`` (no timings)."""
        return {
            "state": self.status,
            "message": self.message,
            "iterations": self.iterations,
            "steps": [{"status": r.status, "iterations": r.iterations, "hard_residual": r.R,
                       "history": [{"iteration": h["iteration"], "R": h["R"],
                                    "residuals": h["residuals"]} for h in r.history]}
                      for r in self.steps],
        }


#: A drag's intermediate handle step only has to bring the net close enough to carry on: at
#: most STEP_MAX_ITER iterations, done at a hard residual of STEP_TOL or when the objective falls
#: by less than 1 − STEP_RATIO over STEP_WINDOW iterations; its last step stops on that ratio
#: over LAST_WINDOW iterations (the solver's defaults, 0.999 over 20, hold without handles).
STEP_MAX_ITER, STEP_TOL, STEP_WINDOW, STEP_RATIO, LAST_WINDOW = 10, 1e-4, 5, 0.99, 10

#: Net boundary vertices closer than this fraction of the mean edge length to the reference's
#: boundary start on it; the ``boundary`` term keeps them there.
BOUNDARY_SNAP = 0.05


def boundary_vertices(f: np.ndarray, reference, snap: float = BOUNDARY_SNAP) -> np.ndarray:
    """Ids of the vertices on the rim of the net ``f (m, n, 3)`` that lie on the boundary of
    ``reference`` (within ``snap`` × mean edge length); empty for a closed reference."""
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    vid = np.arange(m * n).reshape(m, n)
    rim = np.unique(np.concatenate([vid[0], vid[-1], vid[:, 0], vid[:, -1]]))
    if len(reference.boundary_segments[0]) == 0:
        return rim[:0]
    q = f.reshape(-1, 3)[rim]
    b, _ = reference.closest_on_boundary(q)
    return rim[np.linalg.norm(q - b, axis=1) <= snap * mean_edge_length(f)]


def net_problem(f: np.ndarray, weights: dict[str, Schedule], *, reference=None,
                handle_ids: np.ndarray | None = None, handle_targets: np.ndarray | None = None,
                isometry_to: np.ndarray | None = None, soft: tuple[str, ...] = (),
                boundary_ids: np.ndarray | None = None,
                rim_slack: np.ndarray | None = None) -> Problem:
    """The problem :func:`optimize_net` solves for the input net ``f (m, n, 3)`` (its
    arguments of the same names): the drag terms bound to ``f``, the isometry term to
    ``isometry_to`` (default ``f``), scaled to the mean edge length of ``f``; the ``rim``
    term holds the rim of ``f`` (``rim_slack``: see :class:`~dgpc_cli.core.problem.Problem`)."""
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    problem = Problem(NetLayout(m, n), mean_edge_length(f), weights,
                      f0=(f if isometry_to is None else np.asarray(isometry_to, dtype=float))
                      if "isometry" in weights else None,
                      handle_ids=handle_ids, handle_targets=handle_targets,
                      reference=reference, soft=soft, boundary_ids=boundary_ids, f_start=f,
                      rim_slack=rim_slack)
    if not problem.active():
        raise DgpcError("no constraint term is active", source="--weight")
    return problem


def optimize_net(
    f: np.ndarray,
    weights: dict[str, Schedule],
    *,
    reference=None,
    handle_ids: np.ndarray | None = None,
    handle_targets: np.ndarray | None = None,
    isometry_to: np.ndarray | None = None,
    soft: tuple[str, ...] = (),
    boundary_ids: np.ndarray | None = None,
    rim_slack: np.ndarray | None = None,
    steps: int = 1,
    max_iter: int | None = None,
    tol: float = 1e-10,
    backend: str = "auto",
    progress: Callable[[int, dict], None] | None = None,
    relax: str | None = None,
    gpc_tol: float | None = None,
    max_strain: float | None = None,
) -> OptimizeOutcome:
    """Optimize the net ``f (m, n, 3)`` under ``weights`` (SPEC §4).

    Handles are reached in ``steps`` increments, as a dragged handle would be: step s pulls the
    handles to ``start + s/steps · (target − start)``, and every step is a guided-projection run
    (the last one must reach ``tol``). ``isometry_to`` is the net whose edge lengths w⁰ (and
    boundary angles) the isometry term keeps (default: the input). ``soft`` names the terms
    the tolerance does not apply to (see ``modes.SOFT``). ``boundary_ids`` are the vertices the
    ``boundary`` term keeps on the reference's boundary (see :func:`boundary_vertices`);
    ``rim_slack`` (per vertex of ``f``) how far the ``rim`` term lets each rim vertex come in. The
    drag terms (``displacement_fairness``, ``closeness``) are bound to the input ``f``. A last
    step that soft terms or regularizers held off ``tol`` is followed by a projection onto the
    hard terms alone (damped, so it moves the net as little as it must). ``relax`` names a
    regularizer that is then lowered tenfold per round while the strain against the input
    falls, no pleat appears and the gpc angle defect stays within ``gpc_tol`` (radians; when
    given), then (6) weighed more while the defect is above it and the strain within
    ``max_strain`` (see :func:`_relax`). The returned ``R`` is the paper's
    constraint error over the hard terms at the returned vertices, net rescaled to mean edge
    length 1 (§6.2.5).

    ``max_iter`` bounds the iterations of the whole run: each step gets at most an equal share
    of what is left for the steps still to come and the final projection (a drag's intermediate
    steps stop earlier, see ``STEP_MAX_ITER``), the relaxation rounds and the projection what
    is left. Without it every step, and the projection, may take ``tol.max_iter`` iterations
    (the outcome's ``max_iter`` is then the sum of those limits).
    """
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    layout = NetLayout(m, n)
    if steps < 1:
        raise DgpcError("--steps must be at least 1", source="--steps")
    problem = net_problem(f, weights, reference=reference, handle_ids=handle_ids,
                          handle_targets=handle_targets, isometry_to=isometry_to, soft=soft,
                          boundary_ids=boundary_ids, rim_slack=rim_slack)
    x = problem.x_from_vertices(f)
    start = f.reshape(-1, 3)[handle_ids] if handle_ids is not None else None
    results: list[SolverResult] = []
    workspace = None
    total = 0
    pulling = [t.name for t in problem.terms()
               if (not t.hard or t.regularizer) and t.weight.end > 0]
    faceted = _faceted(problem)
    phases = steps + bool(pulling)
    budget = max_iter is not None
    if not budget:
        max_iter = _default_budget(steps, start is not None, relax in problem.active(),
                                   bool(pulling))
    for s in range(1, steps + 1):
        allowance = (max_iter - total) // (phases - s + 1) if budget else TOL.max_iter
        targets = None
        if start is not None:
            targets = start + (handle_targets - start) * (s / steps)

        def step_progress(k, record, _base=total, _step=s):
            if progress is not None:
                progress(_base + k, {**record, "phase": "step", "step": _step, "steps": steps})

        result = guided_projection(x, problem.terms(targets), backend=backend,
                                   workspace=workspace, retract=layout.orient_edges,
                                   callback=step_progress,
                                   **_step_limits(s, steps, start is not None, allowance, tol,
                                                  bool(pulling) or faceted))
        log.info("step %d/%d: %s after %d iterations (%s)", s, steps, result.status,
                 result.iterations, result.message)
        workspace, x = result.workspace, result.x
        total += result.iterations
        results.append(result)
    if relax is not None and relax in problem.active() and total < max_iter:
        f_input = f if problem.f0 is None else problem.f0
        for result in _relax(problem, relax, x, f_input, targets, gpc_tol=gpc_tol,
                             max_strain=max_strain,
                             max_iter=(max_iter - total) if budget else TOL.max_iter, tol=tol,
                             backend=backend, workspace=workspace,
                             callback=lambda k, r, _base=total: progress and progress(
                                 _base + k, {**r, "phase": "relaxing"})):
            x = result.x
            results.append(result)
            total += result.iterations
    last = [r for r in results if r.status != "rejected"][-1]
    if not last.success and pulling and total < max_iter:
        # The soft terms hold the hard ones off their tolerance (a reference that is not
        # exactly developable, say): project onto the hard constraints from here, soft terms
        # off, so that the result is the nearby net that meets them (guided projection's
        # damping keeps it close).
        # where a schedule such as fairness 0.01->0 runs again (it regularizes the first steps)
        # the pulling terms fade out with it: alone it would drag the net, unopposed
        again = any(w.start != w.end for w in weights.values())
        hard_weights = {**weights, **{name: Schedule(weights[name].end, 0.0) if again
                                      else Schedule.constant(0.0) for name in pulling}}
        hard_only = replace(problem, weights=hard_weights)
        log.info("projecting onto the hard constraints without %s", ", ".join(pulling))
        result = guided_projection(x, hard_only.terms(),
                                   max_iter=(max_iter - total) if budget else TOL.max_iter,
                                   tol=tol,
                                   backend=backend, retract=layout.orient_edges,
                                   callback=lambda k, r: progress and progress(
                                       total + k, {**r, "phase": "projection"}))
        x = result.x
        results.append(result)
        total += result.iterations
    last = [r for r in results if r.status != "rejected"][-1]
    released: tuple[str, ...] = ()
    if not last.success and faceted and last.R <= RELEASE_R and total < max_iter:
        result = _release(problem, x, tol=tol, backend=backend,
                          max_iter=(max_iter - total) if budget else TOL.max_iter,
                          callback=lambda k, r: progress and progress(
                              total + k, {**r, "phase": "projection"}))
        if result is not None:
            x = result.x
            results.append(result)
            released = ("approximation",)   # R: the hard terms the net was projected onto
    f_out = problem.vertices(x)
    norms = problem.residual_norms(f_out)
    last = [r for r in results if r.status != "rejected"][-1]
    return OptimizeOutcome(f=f_out, status=last.status, message=last.message, steps=results,
                           residuals=norms,
                           R=constraint_error(norms, weights, (*problem.soft, *released)),
                           max_iter=max_iter, released=released)


#: A fit to a triangle mesh stalls where (6) and "on the mesh" cannot both hold closer: the
#: footpoints of the approximation term jump between facets, and on the 4,797-vertex bowling
#: pin (a 148,680-vertex mesh) the hard residual stops at 2e-8 (6e-7 at 161×81). Below
#: RELEASE_R the net is projected onto the other hard terms alone; the result is kept when no
#: vertex moved more than RELEASE_MOVE mean edge lengths — far below the chord error of the
#: mesh's facets themselves — and the status message says so (4,797 vertices: 2 iterations to
#: R 1.9e-11, vertices moved ≤ 2.3e-7 mean edges, 1.7e-9 of the mesh's diagonal).
RELEASE_R, RELEASE_MOVE = 1e-6, 1e-4


def _faceted(problem: Problem) -> bool:
    """Whether the approximation term (a triangle mesh) is a hard term of ``problem``."""
    return ("approximation" in problem.active() and "approximation" not in problem.soft
            and problem.weights["approximation"].end > 0)


def _release(problem: Problem, x: np.ndarray, *, tol: float, backend: str, max_iter: int,
             callback=None) -> SolverResult | None:
    """The projection of a stalled fit onto its hard terms without the approximation term
    (see ``RELEASE_R``); None when it does not reach ``tol`` or moves a vertex further than
    ``RELEASE_MOVE`` mean edge lengths."""
    # every schedule at its end (a schedule such as fairness 0.01->0 must not run again)
    released = _reweighted(problem, {**{name: w.end for name, w in problem.weights.items()},
                                     "approximation": 0.0})
    log.info("the fit stalled at the facets of the reference: projecting onto the other hard "
             "constraints")
    result = guided_projection(x, released.terms(), max_iter=max_iter, tol=tol,
                               backend=backend, retract=problem.layout.orient_edges,
                               callback=callback)
    before, after = problem.vertices(x), problem.vertices(result.x)
    moved = float(np.linalg.norm(after - before, axis=-1).max()) / problem.scale
    if not result.success or moved > RELEASE_MOVE:
        log.info("projection not kept (%s; largest move %.3g mean edges)", result.status, moved)
        return None
    result.message += (f"; the approximation term released at the mesh's facets (vertices "
                       f"moved at most {moved:.2g} mean edges)")
    return result


#: Relaxation of a drag's regularizer: its weight falls to these fractions of the mode's, one
#: round of at most RELAX_ITER iterations each, while the largest strain against the input falls
#: by at least RELAX_GAIN per round and the pleat measure stays below half its tolerance (the
#: last round, without it, reaches an exact isometric deformation where there is one). Measured
#: on the Gehry facades, the demo wall and five gallery shapes (21×13): starting at 1e-2 rather
#: than 1e-1 of the mode's weight ends at the same nets (largest strain within 4e-5 of 3e-4)
#: with 10–60 iterations fewer; a round needs its 30 iterations (the solver's non-monotone
#: steps near the solution: rounds of 20 left the Minding-bent half sphere at strain 1.7e-5
#: instead of 4e-8).
RELAX_FRACTIONS, RELAX_ITER, RELAX_GAIN = (1e-2, 1e-3, 0.0), 30, 0.9
#: ... and while the pleat measure stays below this fraction of its tolerance (a round that
#: passes it ends there and is refused).
RELAX_PLEAT_MARGIN = 0.5
#: ... and while the gpc angle defect stays within this fraction of --gpc-tol: the projection
#: onto the hard terms that follows moves it (a cylinder twisted at 21×13: 9.8e-5 → 1.17e-4).
RELAX_GPC_MARGIN = 0.5
#: Factors of the gpc weight tried, one round each, where the net is still above that margin.
RELAX_GPC_FACTORS = (4.0, 16.0, 64.0)
#: A kept round whose largest strain fell by less than this factor ends the descent: the strain
#: is near what the design allows, and a smaller weight gains less still (Gehry facades 1–2:
#: 0.73 and 0.75, then 0.97 and 0.96, rejected; the Minding-bent half sphere: 0.21, 0.012).
RELAX_SLOW = 0.5


def _default_budget(steps: int, drag: bool, relax: bool, pulling: bool) -> int:
    """The iterations a run without ``--max-iter`` may take at most: ``tol.max_iter`` for each
    step (a drag's intermediate steps ``STEP_MAX_ITER``), the relaxation rounds, and
    ``tol.max_iter`` for the final projection."""
    limits = [_step_limits(s, steps, drag, TOL.max_iter, 0.0)["max_iter"]
              for s in range(1, steps + 1)]
    return (sum(limits) + (RELAX_ITER * len(RELAX_FRACTIONS) if relax else 0)
            + (TOL.max_iter if pulling else 0))


def _step_limits(s: int, steps: int, drag: bool, max_iter: int, tol: float,
                 projected: bool = False) -> dict:
    """Stopping rules of handle step ``s`` of ``steps`` (see ``STEP_MAX_ITER``). A run
    without handles that a projection follows when it stalls (its soft terms or regularizers
    pull, or it fits a triangle mesh, see ``RELEASE_R``) stops once its objective falls by less
    than 1 − STEP_RATIO over LAST_WINDOW iterations: what it still gains there the projection
    would undo."""
    if not drag:
        if projected:
            return {"max_iter": max_iter, "tol": tol, "stagnation_window": LAST_WINDOW,
                    "stagnation_ratio": STEP_RATIO}
        return {"max_iter": max_iter, "tol": tol}
    if s < steps:
        return {"max_iter": min(max_iter, STEP_MAX_ITER), "tol": max(tol, STEP_TOL),
                "stagnation_window": STEP_WINDOW, "stagnation_ratio": STEP_RATIO}
    return {"max_iter": max_iter, "tol": tol, "stagnation_window": LAST_WINDOW,
            "stagnation_ratio": STEP_RATIO}


def _relax(problem: Problem, name: str, x: np.ndarray, f_input: np.ndarray, targets, *,
           max_iter: int, tol: float, backend: str, workspace, gpc_tol: float | None = None,
           max_strain: float | None = None, callback=None) -> list[SolverResult]:
    """Lower the weight of the regularizer ``name`` (the drag's smoothness) as the net settles,
    but never to a pleat: an isometric drag is a weighing of (6) against the edge lengths, and
    the less the smoothness weighs, the smaller the strain — until the net starts to pleat
    (their exact solutions). A round is kept only if it keeps the gpc angle defect (6) within
    ``gpc_tol`` (or, where the net started above it, no larger): the smallest strain *of a
    gpc net within its tolerance* is sought, not the smallest strain; a round that gained
    little (``RELAX_SLOW``) is the last of the descent, and a round that begins to pleat ends
    at its first point of descent beyond the pleat limit (it would be refused at its end: on
    Gehry facades 3–4 the pleat grew from iteration 8 on, monotonically; the round ends after
    11 iterations instead of 21). Returns the rounds' solver results; a
    round that did not help has status ``rejected`` and the net it started from as its ``x``.
    The rounds take at most ``max_iter`` iterations together."""
    def largest_pleat(g) -> float:
        corrugation = pleat(g)
        return float(corrugation.max()) if corrugation.size else 0.0

    def measure(xv):
        g = problem.vertices(xv)
        return (float(np.nanmax(strain(g, f_input)[0])), largest_pleat(g),
                float(np.nanmax(gpc_angle_defect(g))))

    pleat_limit = RELAX_PLEAT_MARGIN * TOL.pleat
    best, _, current = measure(x)
    defect_limit = np.inf if gpc_tol is None else max(RELAX_GPC_MARGIN * gpc_tol, current)
    accepted = []
    done = 0                                        # iterations of the rounds so far
    level = problem.weights[name].end               # the regularizer's weight of the net x

    def pleating(xv) -> str | None:
        """Why a round is ended early: it pleats, and would be rejected at its end anyway."""
        corrugation = largest_pleat(problem.vertices(xv))
        if corrugation > pleat_limit:
            return f"the net began to pleat ({corrugation:.3g} mean edges)"
        return None

    def round_at(weights: dict, label: str):
        nonlocal done
        result = guided_projection(x, _reweighted(problem, weights).terms(targets),
                                   max_iter=min(max_iter - done, RELAX_ITER), tol=tol,
                                   backend=backend, workspace=workspace,
                                   retract=problem.layout.orient_edges, halt=pleating,
                                   callback=callback and (lambda k, r, _done=done: callback(
                                       _done + k, r)))
        done += result.iterations
        worst, corrugation, defect = measure(result.x)
        log.info("%s: strain %.3g, pleat %.3g, gpc defect %.3g (%d iterations%s)", label, worst,
                 corrugation, defect, result.iterations,
                 f"; ended early: {result.message}" if result.status == "halted" else "")
        return result, worst, corrugation, defect

    fractions = list(RELAX_FRACTIONS)
    while fractions and done < max_iter:
        fraction = fractions.pop(0)
        weight = fraction * problem.weights[name].end
        result, worst, corrugation, defect = round_at({name: weight},
                                                      f"{name} weight {weight:.0e}")
        if not (np.isfinite(worst) and worst <= RELAX_GAIN * best
                and corrugation <= pleat_limit and defect <= defect_limit):
            result.status, result.x = "rejected", x      # its work counts, its net does not
            accepted.append(result)
            # no gain at this weight: one last try without it (an exact isometric deformation
            # is reached there when one exists; a pleat is refused) — unless the gpc defect
            # ended above its limit (less smoothness does not bring it back) or the net pleated
            # (Gehry facades 3–4: that try cost 21 iterations and ended at a larger strain)
            fractions = ([0.0] if fraction > 0 and defect <= defect_limit
                         and corrugation <= pleat_limit else [])
            continue
        slow = worst > RELAX_SLOW * best
        best, x, current, level = worst, result.x, defect, weight
        accepted.append(result)
        if slow:
            break
    # the drag left the gpc defect above its margin: weigh (6) more, round by round, while the
    # defect falls, no pleat appears and the strain stays within max_strain (or no larger)
    strain_limit = np.inf if max_strain is None else max(max_strain, best)
    for factor in RELAX_GPC_FACTORS:
        if gpc_tol is None or current <= RELAX_GPC_MARGIN * gpc_tol or done >= max_iter:
            break
        gpc_weight = factor * problem.weights["gpc"].end
        result, worst, corrugation, defect = round_at({name: level, "gpc": gpc_weight},
                                                      f"gpc weight {gpc_weight:.0e}")
        if not (np.isfinite(worst) and worst <= strain_limit and defect < current
                and corrugation <= pleat_limit):
            result.status, result.x = "rejected", x
            accepted.append(result)
            break
        best, x, current = worst, result.x, defect
        accepted.append(result)
    return accepted


def _reweighted(problem: Problem, weights: dict[str, float]) -> Problem:
    """``problem`` with the terms of ``weights`` at those constant weights."""
    return replace(problem, weights={**problem.weights,
                                     **{k: Schedule.constant(w) for k, w in weights.items()}})


#: Rows named in a status message.
WORST_ROWS = 3


def _worst_rows(per_vertex: np.ndarray, limit: float) -> str:
    """``"rows 3 (4.1e-4), 2 (3.9e-4)"``: the rows whose largest value exceeds ``limit``."""
    per_row = np.nanmax(np.where(np.isfinite(per_vertex), per_vertex, -np.inf), axis=1)
    bad = np.flatnonzero(per_row > limit)
    worst = bad[np.argsort(-per_row[bad], kind="stable")][:WORST_ROWS]
    return "rows " + ", ".join(f"{u} ({per_row[u]:.2e})" for u in worst)


#: A handle nearer its target than this (mm) is reached.
HANDLE_REACHED_MM = 1e-3


def missed_handle(f: np.ndarray, f_input: np.ndarray, handles, units: str) -> str | None:
    """What a run that stopped short says of its handles (``f``, ``f_input`` and the
    ``handles`` ``(ids, targets)`` in mm): the handle farthest from its target, by how much,
    and how far it was dragged, in ``units``; None where every handle is reached."""
    if handles is None or handles[0] is None:
        return None
    ids, targets = np.asarray(handles[0], np.int64), np.asarray(handles[1], float)
    miss = np.linalg.norm(f.reshape(-1, 3)[ids] - targets, axis=1)
    k = int(np.argmax(miss))
    if not miss[k] > HANDLE_REACHED_MM:
        return None
    drag = float(np.linalg.norm(targets[k] - f_input.reshape(-1, 3)[ids[k]]))
    u, v = divmod(int(ids[k]), f.shape[1])
    mm = mm_per_unit(units)
    return (f"handle [{u}, {v}] stopped {miss[k] / mm:.3g} {units} short of its target "
            f"(dragged {drag / mm:.3g} {units}): the net cannot follow this drag; drag it "
            "less or in more --steps, pin fewer vertices (each pin takes a freedom the "
            "bending needs), or move its target")


def judge(outcome: OptimizeOutcome, f_input: np.ndarray, *, mode: str,
          max_strain: float = TOL.max_strain, gpc_tol: float = TOL.gpc_tol,
          handles=None, units: str = "mm") -> tuple[str, str]:
    """The state and message of an optimized net (SPEC §4): never ``converged`` on a folded,
    collapsed or pleated net (state ``degenerate``, naming the rows and columns, see
    :func:`~dgpc_cli.metrics.degenerate.degeneracies`, with an edge shorter than
    ``TOL.min_edge_ratio`` of the mean, the bound of ``inspect``'s ``edges.folded``; or
    ``pleated``). In revolution mode
    ``converged`` only when every quad is within ``max_strain`` of the surface of revolution
    extract-mold builds from the net (edges and diagonals); in isometric mode only when the
    largest strain against the input (§6.1) is at most ``max_strain`` and the gpc angle defect
    at most ``gpc_tol`` (radians). A run that stopped short (``stagnated``, ``max_iter``)
    with ``handles`` (``(ids, targets)`` in mm) names the handle it missed, by how much in
    ``units``, and what to try (:func:`missed_handle`).
    """
    f = outcome.f
    # The edge floor is the one of `inspect`'s edges.folded (10 % of the mean edge): a net that
    # inspect calls folded is never converged.
    found = degeneracies(f, edge_ratio=TOL.min_edge_ratio)
    if found:
        return "degenerate", f"folded or collapsed net: {found.message()}"
    corrugation = pleat(f)
    if corrugation.size and float(corrugation.max()) > TOL.pleat:
        return "pleated", (f"period-2 pleat across the geodesics of "
                           f"{float(corrugation.max()):.3g} × the mean edge at "
                           f"{_worst_rows(corrugation, TOL.pleat)}")
    if not outcome.converged:
        missed = missed_handle(f, f_input, handles, units)
        return outcome.status, outcome.message + (f"; {missed}" if missed else "")
    if mode not in ("revolution", "isometric"):
        return outcome.status, outcome.message
    misses = []
    if mode == "revolution":
        error = panel_errors(f)
        if error is None:
            return "missed_tolerance", "no surface of revolution fits the net's strip widths"
        if np.nanmax(error) > max_strain:
            misses.append(f"quads {np.nanmax(error):.3g} off the surface of revolution "
                          f"(> --max-strain {max_strain:g}) at {_worst_rows(error, max_strain)}")
        done = f"quads within {np.nanmax(error):.3g} of the surface of revolution"
    else:
        amount, _ = strain(f, f_input)
        defect = gpc_angle_defect(f)
        if np.nanmax(amount) > max_strain:
            misses.append(f"strain {np.nanmax(amount):.3g} > --max-strain {max_strain:g} at "
                          f"{_worst_rows(amount, max_strain)}")
        if np.nanmax(defect) > gpc_tol:
            misses.append(f"gpc angle defect {np.nanmax(defect):.3g} rad > --gpc-tol "
                          f"{gpc_tol:g} at {_worst_rows(defect, gpc_tol)}")
        done = (f"strain {np.nanmax(amount):.3g} ≤ {max_strain:g}, gpc angle defect "
                f"{np.nanmax(defect):.3g} ≤ {gpc_tol:g} rad")
    if misses:
        return "missed_tolerance", "; ".join(misses)
    return "converged", done
