"""``dgpc optimize``: guided projection of a net in one of the modes of SPEC §4."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.core.problem import Problem, constraint_error, mean_edge_length
from dgpc_cli.core.solver import Schedule, SolverResult, guided_projection
from dgpc_cli.errors import DgpcError
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


def optimize_net(
    f: np.ndarray,
    weights: dict[str, Schedule],
    *,
    reference=None,
    handle_ids: np.ndarray | None = None,
    handle_targets: np.ndarray | None = None,
    isometry_to: np.ndarray | None = None,
    soft: tuple[str, ...] = ("fairness",),
    boundary_ids: np.ndarray | None = None,
    steps: int = 1,
    max_iter: int | None = None,
    tol: float = 1e-10,
    backend: str = "auto",
    progress: Callable[[int, dict], None] | None = None,
) -> OptimizeOutcome:
    """Optimize the net ``f (m, n, 3)`` under ``weights`` (SPEC §4).

    Handles are reached in ``steps`` increments, as a dragged handle would be: step s pulls the
    handles to ``start + s/steps · (target − start)``, and every step is a guided-projection run
    (the last one must reach ``tol``). ``isometry_to`` is the net whose edge lengths w⁰ (and
    boundary angles) the isometry term keeps (default: the input). ``soft`` names the terms
    the tolerance does not apply to (see ``modes.SOFT``). ``boundary_ids`` are the vertices the
    ``boundary`` term keeps on the reference's boundary (see :func:`boundary_vertices`). The
    returned ``R`` is the paper's constraint error at the returned vertices, net rescaled to
    mean edge length 1 (§6.2.5).

    ``max_iter`` bounds the iterations of the whole run: each step, and the final projection
    onto the hard constraints when soft terms pull, gets an equal share of what is left
    (default: ``tol.max_iter`` for each of them).
    """
    f = np.asarray(f, dtype=float)
    m, n = f.shape[:2]
    layout = NetLayout(m, n)
    if steps < 1:
        raise DgpcError("--steps must be at least 1", source="--steps")
    problem = Problem(layout, mean_edge_length(f), weights,
                      f0=(f if isometry_to is None else np.asarray(isometry_to, dtype=float))
                      if "isometry" in weights else None,
                      handle_ids=handle_ids, handle_targets=handle_targets,
                      reference=reference, soft=soft, boundary_ids=boundary_ids)
    if not problem.active():
        raise DgpcError("no constraint term is active", source="--weight")
    x = problem.x_from_vertices(f)
    start = f.reshape(-1, 3)[handle_ids] if handle_ids is not None else None
    results: list[SolverResult] = []
    workspace = None
    total = 0
    pulling = [name for name in problem.active()
               if name in problem.soft and weights[name].end > 0]
    phases = steps + bool(pulling)
    max_iter = TOL.max_iter * phases if max_iter is None else max_iter
    for s in range(1, steps + 1):
        allowance = (max_iter - total) // (phases - s + 1)
        targets = None
        if start is not None:
            targets = start + (handle_targets - start) * (s / steps)

        def step_progress(k, record, _base=total):
            if progress is not None:
                progress(_base + k, record)

        result = guided_projection(x, problem.terms(targets), max_iter=allowance, tol=tol,
                                   backend=backend, workspace=workspace,
                                   retract=layout.orient_edges, callback=step_progress)
        log.info("step %d/%d: %s after %d iterations (%s)", s, steps, result.status,
                 result.iterations, result.message)
        workspace, x = result.workspace, result.x
        total += result.iterations
        results.append(result)
    last = results[-1]
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
        hard_only = Problem(layout, problem.scale, hard_weights,
                            problem.f0, handle_ids, handle_targets, reference, problem.soft,
                            boundary_ids)
        log.info("projecting onto the hard constraints without %s", ", ".join(pulling))
        result = guided_projection(x, hard_only.terms(), max_iter=max_iter - total, tol=tol,
                                   backend=backend, retract=layout.orient_edges,
                                   callback=lambda k, r: progress and progress(total + k, r))
        x = result.x
        results.append(result)
    f_out = problem.vertices(x)
    norms = problem.residual_norms(f_out)
    last = results[-1]
    return OptimizeOutcome(f=f_out, status=last.status, message=last.message, steps=results,
                           residuals=norms, R=constraint_error(norms, weights),
                           max_iter=max_iter)
