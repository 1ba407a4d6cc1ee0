"""Guided projection (Tang, Sun, Gomes, Wallner, Pottmann 2014), as used in paper §5.

Every constraint φ_t(x) = 0 is linearized at x_k; the step solves the regularized normal equations

    (JᵀWJ + ε²I) Δx = −JᵀWφ,        x_(k+1) = x_k + Δx,

i.e. the paper's ``(HᵀWH + KᵀK + ε²I) x = HᵀWr + Kᵀs + ε² x_k`` written for the increment (the
linear fairness rows K are among the terms). The normal matrix is assembled into a fixed pattern
and its symbolic factorization is done once (SPEC §10).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from dgpc_cli.core.solver.linear import blas_on_one_thread, make_solver
from dgpc_cli.core.solver.normal_matrix import NormalMatrix
from dgpc_cli.core.solver.schedule import Schedule

log = logging.getLogger(__name__)

#: Default regularization ε of the normal equations, for a net scaled to mean edge length 1.
EPSILON = 1e-3
#: Bounds and factors of the Levenberg–Marquardt control of ε².
MU_MIN, MU_MAX, MU_DOWN, MU_UP = 1e-16, 1e4, 0.1, 4.0
#: Once every weight has settled, ε² is not lowered below ``clip(MU_FLOOR_C · R², MU_MIN,
#: MU_FAR)``: damped far from the solution, (nearly) undamped Gauss–Newton close to it, which
#: singular roots need (see :func:`guided_projection`). While a schedule still runs, ε² stays
#: at least ε²₀: the guided phase of Tang et al.
MU_FLOOR_C, MU_FAR = 1e-4, 1e-10
#: "Near the solution": every weight settled and the hard residual below NEAR. Only there is
#: ε² lowered below ε²₀ and acceptance relaxed; farther away it is guided projection.
NEAR = 1e-3
#: Non-monotone (watchdog) acceptance: a step is taken while the objective stays below KAPPA²
#: times its current value; after WATCHDOG settled iterations without a new best objective the
#: iterate returns to the best point and the next WATCHDOG iterations are monotone.
KAPPA, WATCHDOG = 1e3, 30


@dataclass(frozen=True)
class Term:
    """A constraint term bound to its data: ``func(x) -> (phi, J)`` and its weight schedule.

    ``hard`` terms model the geometry asked for and must reach the tolerance; soft terms
    (closeness to a reference) pull and may keep a residual. A ``regularizer`` (fairness, the
    smoothness of a drag) only shapes the path and the solution among many: its residual is
    in no residual norm.
    """

    name: str
    func: Callable
    weight: Schedule
    hard: bool = True
    regularizer: bool = False


@dataclass
class SolverResult:
    """Outcome of :func:`guided_projection` (cf. ``scipy.optimize.OptimizeResult``).

    ``status`` is ``converged`` (hard residual ≤ tol, soft terms ≤ tol or no longer falling, every
    schedule settled), ``stagnated`` (hard residual above tol and no progress), ``max_iter``,
    ``halted`` (the caller's ``halt`` gave a reason, in ``message``; x is the point it judged) or
    ``failed`` (non-finite residuals). ``R`` is the norm of the hard residuals at the returned x.
    ``history`` has one record per iteration: the unweighted residual norm of every term at x_k,
    the hard residual, the objective, the step norm and the seconds the iteration took.
    """

    x: np.ndarray
    status: str
    message: str
    iterations: int
    R: float
    residuals: dict
    history: list = field(default_factory=list)
    workspace: object = None
    backend: str = ""

    @property
    def success(self) -> bool:
        return self.status == "converged"

    @property
    def seconds_per_iteration(self) -> float:
        times = [h["seconds"] for h in self.history if h.get("seconds") is not None]
        return float(np.median(times)) if times else 0.0


@dataclass
class Linearization:
    """The point ``x`` whose normal matrix the workspace's solver holds factorized, with the
    terms, weights, residuals and Jacobians there (what :func:`predictor_step` re-solves)."""

    x: np.ndarray
    terms: list
    weights: list
    phis: list
    jacs: list


class _Workspace:
    """Pattern and linear solver kept across runs on the same net (handle steps)."""

    def __init__(self, rows, cols, n_rows, size, backend):
        self.pattern = NormalMatrix(rows, cols, n_rows, size)
        self.solver = make_solver(self.pattern, backend)
        #: What the solver's numeric factorization was made at (None: no valid one).
        self.linearization: Linearization | None = None


def _evaluate(terms, x):
    out = [t.func(x) for t in terms]
    phis = [p for p, _ in out]
    jacs = [J for _, J in out]
    return phis, jacs


def _norms(terms, phis):
    return {t.name: float(np.linalg.norm(p)) for t, p in zip(terms, phis, strict=True)}


def _norm(terms, phis, hard):
    sq = sum(float(p @ p) for t, p in zip(terms, phis, strict=True)
             if t.hard == hard and t.weight.end > 0 and not t.regularizer)
    return float(np.sqrt(sq))


def _objective(weights, phis):
    return sum(w * float(p @ p) for w, p in zip(weights, phis, strict=True))


def _stack(jacs, phis):
    offsets = np.cumsum([0] + [p.size for p in phis[:-1]])
    rows = np.concatenate([J.row + off for J, off in zip(jacs, offsets, strict=True)])
    cols = np.concatenate([J.col for J in jacs])
    vals = np.concatenate([J.data for J in jacs])
    return rows, cols, vals


@blas_on_one_thread
def guided_projection(
    x0: np.ndarray,
    terms: list[Term],
    *,
    max_iter: int = 100,
    tol: float = 1e-10,
    epsilon: float = EPSILON,
    stagnation_window: int = 20,
    stagnation_ratio: float = 0.999,
    backend: str = "auto",
    workspace: _Workspace | None = None,
    retract: Callable | None = None,
    callback: Callable | None = None,
    halt: Callable[[np.ndarray], str | None] | None = None,
) -> SolverResult:
    """Run guided projection from ``x0`` until R ≤ ``tol``, stagnation, or ``max_iter``.

    While a weight schedule runs (e.g. fairness 0.01→0) this is Tang et al.'s guided projection
    with ε fixed at ``epsilon``: the regularization keeps the net near its previous position.
    Once every weight has settled, ε² is controlled as in Levenberg–Marquardt and allowed down
    to ~1e-4·R²: near-flexible constraint sets (isometry with the angle condition (6) has far
    more infinitesimal than finite flexes) have singular roots, where damped steps crawl (the
    residual sits on singular values ~1e-8) while nearly undamped Gauss–Newton converges
    linearly (distance halves per step). Undamped steps may overshoot first, so acceptance is
    non-monotone (objective may grow by KAPPA²), with a watchdog that returns to the best point.

    Parameters
    ----------
    x0 : (size,) array
        Start point (vertices, unit edge vectors, edge lengths; see ``NetLayout``).
    terms : list of Term
        The bound constraint terms; their Jacobian patterns must not depend on x.
    tol : float
        Tolerance on the norm of the hard residuals (unweighted, at x_k, terms with a positive
        final weight), and on the soft residuals unless they stop falling.
    epsilon : float
        Initial ε (the net is scaled to mean edge length 1).
    stagnation_window, stagnation_ratio : int, float
        Stop as ``stagnated`` when the last ``window`` iterations (once every schedule has
        settled) did not bring the weighted objective below ``ratio`` times its best value.
    retract : callable, optional
        ``retract(x) -> x`` applied to every trial point, e.g. to restore sign conventions of
        auxiliary variables that leave every residual unchanged but the geometry's meaning.
    callback : callable, optional
        ``callback(k, record)`` after every iteration (progress bars).
    halt : callable, optional
        ``halt(x) -> reason or None`` at every point a step of descent (the objective fell)
        reached, unless it converged there; a reason ends the run there as ``halted`` (a caller
        that would reject where the run is heading saves the rest of its iterations). Points
        of the watchdog's non-monotone steps are not judged: the run may still come back.
    """
    x = np.array(x0, dtype=float)
    if workspace is not None:
        workspace.linearization = None            # only this run's factorizations count
    history: list[dict] = []
    objective: list[float] = []
    status, message = "max_iter", f"iteration limit {max_iter} reached"
    mu0 = mu = epsilon * epsilon
    soft_active = any(not t.hard and t.weight.end > 0 for t in terms)
    phis, jacs = _evaluate(terms, x)
    best = None                                   # (objective, x, phis, jacs, iteration)
    monotone_until = -1
    k = 0
    moved = False                   # x came by a step of descent since halt last saw it
    while True:
        t0 = time.perf_counter()
        residuals = _norms(terms, phis)
        R, soft = _norm(terms, phis, True), _norm(terms, phis, False)
        weights = [t.weight(k) for t in terms]
        obj = _objective(weights, phis)
        settled = all(t.weight.settled(k) for t in terms)
        record = {"iteration": k, "R": R, "residuals": residuals, "objective": obj}
        stalled = (settled and len(objective) > stagnation_window
                   and min(objective[-stagnation_window:])
                   > stagnation_ratio * min(objective[:-stagnation_window]))
        if not np.isfinite(obj):
            status, message = "failed", "residuals are not finite"
            break
        if settled and R <= tol and (not soft_active or soft <= tol or stalled):
            status = "converged"
            message = f"hard residual {R:.3g} ≤ tol {tol:g}"
            if soft_active:
                message += f", soft residual {soft:.3g}"
            break
        if k >= max_iter:
            break
        if halt is not None and moved:
            moved = False
            if reason := halt(x):
                status, message = "halted", reason
                break
        if stalled or mu > MU_MAX:
            status = "stagnated"
            message = f"hard residual {R:.3g} stopped falling above tol {tol:g}"
            break
        if settled:
            if best is None or obj < best[0]:
                best = (obj, x, phis, jacs, k)
            elif k - best[4] >= WATCHDOG:         # watchdog: back to the best point
                obj, x, phis, jacs, _ = best
                best = (obj, x, phis, jacs, k)
                R = _norm(terms, phis, True)
                mu = max(mu * 100.0, MU_FAR)
                monotone_until = k + WATCHDOG
            objective.append(best[0])

        rows, cols, vals = _stack(jacs, phis)
        phi = np.concatenate(phis)
        row_w = np.repeat(np.asarray(weights, dtype=float), [p.size for p in phis])
        if workspace is None or not workspace.pattern.same_pattern(rows, cols):
            workspace = _Workspace(rows, cols, phi.size, x.size, backend)
        pattern = workspace.pattern
        solver = workspace.solver
        try:
            solver.factorize(pattern.values(vals, row_w, mu))
        except Exception:  # noqa: BLE001 - numerically singular at a tiny ε²: damp more
            workspace.linearization = None
            mu *= 100.0
            k += 1
            continue
        workspace.linearization = Linearization(x, list(terms), weights, phis, jacs)
        dx = solver.solve(-pattern.gradient(vals, row_w, phi))
        if retract is not None:
            dx = retract(x + dx) - x
        trial = _evaluate(terms, x + dx)
        trial_obj = _objective(weights, trial[0])
        near = settled and R < NEAR
        relaxed = near and k >= monotone_until
        if np.isfinite(trial_obj) and trial_obj < (KAPPA * KAPPA * obj if relaxed else obj):
            x = x + dx
            phis, jacs = trial
            moved = trial_obj < obj                # halt judges points of descent only
            floor = min(MU_FAR, max(MU_MIN, MU_FLOOR_C * R * R)) if near else mu0
            mu = max(mu * MU_DOWN, floor)
            record["step"] = float(np.linalg.norm(dx))
        else:
            mu *= MU_UP
            record["step"] = 0.0
        record["mu"] = mu
        record["seconds"] = time.perf_counter() - t0
        history.append(record)
        log.debug("iter %3d  R %.3e  objective %.3e  |dx| %.3e  mu %.1e  %.3fs", k, R, obj,
                  record["step"], mu, record["seconds"])
        if callback is not None:
            callback(k, record)
        k += 1
    if (status != "halted" and best is not None
            and best[0] < _objective([t.weight(k) for t in terms], phis)):
        _, x, phis, _, _ = best                   # a relaxed step may have left the best
        residuals = _norms(terms, phis)
        R = _norm(terms, phis, True)
        record = {**record, "R": R, "residuals": residuals}
    history.append(record)
    return SolverResult(x=x, status=status, message=message, iterations=k, R=R,
                        residuals=residuals, history=history, workspace=workspace,
                        backend=type(workspace.solver).name if workspace else "")


@dataclass
class PredictorStep:
    """Outcome of :func:`predictor_step`: the point reached, and whether it is taken (the
    objective fell below its value at the linearization with the new terms)."""

    x: np.ndarray
    accepted: bool
    objective: float
    R: float


@blas_on_one_thread
def predictor_step(terms: list[Term], workspace: _Workspace,
                   retract: Callable | None = None) -> PredictorStep | None:
    """The step of the last factorized iteration re-solved for changed terms, with no new
    factorization: one back-substitution (Euler predictor of a continuation in the terms'
    data, e.g. a dragged handle's target; Allgower and Georg 1990, §2.2).

    The normal equations at the workspace's linearization point x_k stay as they were (the
    terms that changed, found by their functions, must keep their Jacobian there: e.g. the
    handles, linear in x); only the gradient ``JᵀWφ`` is made anew with the changed terms'
    residuals at x_k, so the result is the Gauss–Newton step from x_k that the new data asks
    for. Stiff nonlinear terms forbid the cheaper chord step from the current point with the
    old matrix: their rotated Jacobian makes the old matrix no model of the new one. The step
    is taken where the objective falls, as :func:`guided_projection` takes a step. None when
    the workspace holds no factorization of these terms (other terms changed too, or their
    pattern).
    """
    lin = workspace.linearization if workspace is not None else None
    if lin is None or len(lin.terms) != len(terms) or any(
            a.name != b.name for a, b in zip(lin.terms, terms, strict=True)):
        return None
    phis, jacs = list(lin.phis), list(lin.jacs)
    for i, (old, new) in enumerate(zip(lin.terms, terms, strict=True)):
        if new.func is not old.func:
            phis[i], jacs[i] = new.func(lin.x)
    rows, cols, vals = _stack(jacs, phis)
    if not workspace.pattern.same_pattern(rows, cols):
        return None
    row_w = np.repeat(np.asarray(lin.weights, dtype=float), [p.size for p in phis])
    base = _objective(lin.weights, phis)
    dx = workspace.solver.solve(-workspace.pattern.gradient(vals, row_w, np.concatenate(phis)))
    x = lin.x + dx
    if retract is not None:
        x = retract(x)
    trial, _ = _evaluate(terms, x)
    obj = _objective(lin.weights, trial)
    accepted = bool(np.isfinite(obj) and obj < base)
    return PredictorStep(x=x, accepted=accepted, objective=obj, R=_norm(terms, trial, True))
