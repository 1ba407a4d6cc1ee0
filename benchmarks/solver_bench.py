"""``make bench``: seconds per iteration at the paper's problem sizes (SPEC §8, §10).

Each problem is solved with our solver (fixed-pattern assembly, symbolic factorization once,
the fastest available sparse Cholesky) to tolerance, and a few iterations of the same problem
are run with a plain reference solve — a fresh ``scipy.sparse.linalg.spsolve`` every
iteration, as the authors' code does — in the same run. Speed is reported as a ratio, so the
noisy machine cancels out.

Problems (paper §5.2 table):
* 21×21 net, 8,043 paper variables (Fig. 1, 10): isometric deformation of a half-sphere
  meridian net by three boundary handles (gpc 1, isometry 1, handles 1, fairness 0.01→0),
  targets from an exact isometric (Minding) bending.
* 123×39 = 4,797 vertices (Fig. 11-2): a twisted bowling-pin net fitted to its surface
  (gpc 1, approximation 1, fairness 0.01→0), closest points recomputed every iteration.
"""

from __future__ import annotations

import platform
import statistics
import sys
import time

import numpy as np

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.core.solver.linear import available_backends
from dgpc_cli.fitting.modes import RELAX, SOFT, mode_weights
from dgpc_cli.fitting.optimize import optimize_net
from dgpc_cli.stages.init import REFERENCE_MARGIN
from dgpc_cli.surfaces.minding import minding_bend
from dgpc_cli.surfaces.profiles import builtin_profile
from dgpc_cli.surfaces.revolution import extended, revolution_mesh, revolution_net
from dgpc_cli.tolerances import tol as TOL

REFERENCE_ITERATIONS = 3


def isometric_problem():
    f = revolution_net(builtin_profile("sphere"), 21, 21, span_deg=90.0)
    g = minding_bend(f, 0.85)
    layout = NetLayout(21, 21)
    ids = np.array([layout.vid[0, 0], layout.vid[0, -1], layout.vid[-1, 10]])
    kwargs = dict(handle_ids=ids, handle_targets=g.reshape(-1, 3)[ids], steps=5,
                  soft=SOFT["isometric"], relax=RELAX["isometric"], gpc_tol=TOL.gpc_tol,
                  max_strain=TOL.max_strain)            # as `dgpc optimize --mode isometric`
    return "21×21 isometric (Fig. 1, 10)", f, mode_weights("isometric"), kwargs


def fit_problem():
    profile = builtin_profile("bowling-pin")
    f = revolution_net(profile, 123, 39, span_deg=180.0, twist=0.5)
    vertices, faces = revolution_mesh(extended(profile, REFERENCE_MARGIN))
    kwargs = dict(reference=ReferenceSurface(vertices, faces))
    return "123×39 fit (Fig. 11-2)", f, mode_weights("fit"), kwargs


def per_iteration(outcome) -> float:
    times = [h["seconds"] for r in outcome.steps for h in r.history if "seconds" in h]
    return statistics.median(times)


def factor_solve_floor(f, weights, kwargs, outcome, repeats: int = 5) -> float:
    """Median seconds of one numeric factorization and solve of the normal matrix of the
    run's first step at its final net, with the run's own solver (the cost an iteration
    cannot go below); NaN where the pattern differs."""
    from dgpc_cli.core.problem import Problem, mean_edge_length
    from dgpc_cli.core.solver.guided_projection import _evaluate, _stack

    workspace = outcome.steps[0].workspace
    problem = Problem(NetLayout(*f.shape[:2]), mean_edge_length(f), weights,
                      f0=f if "isometry" in weights else None,
                      handle_ids=kwargs.get("handle_ids"),
                      handle_targets=kwargs.get("handle_targets"),
                      reference=kwargs.get("reference"), f_start=f)
    terms = problem.terms(kwargs.get("handle_targets"))
    x = problem.x_from_vertices(outcome.f)
    phis, jacs = _evaluate(terms, x)
    rows, cols, vals = _stack(jacs, phis)
    if workspace is None or not workspace.pattern.same_pattern(rows, cols):
        return float("nan")
    row_w = np.repeat([t.weight(10**6) for t in terms], [p.size for p in phis])
    matrix = workspace.pattern.values(vals, row_w, 1e-8)
    rhs = -workspace.pattern.gradient(vals, row_w, np.concatenate(phis))
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        workspace.solver.factorize(matrix)
        workspace.solver.solve(rhs)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def run(problem):
    name, f, weights, kwargs = problem
    layout = NetLayout(*f.shape[:2])
    t0 = time.perf_counter()
    ours = optimize_net(f, weights, max_iter=200, tol=1e-10, **kwargs)
    wall = time.perf_counter() - t0
    ref_kwargs = {**kwargs, "steps": 1, "relax": None}
    ref = optimize_net(f, weights, max_iter=REFERENCE_ITERATIONS, tol=0.0, backend="spsolve",
                       **ref_kwargs)
    return {
        "problem": name, "vertices": layout.n_vertices, "paper_vars": layout.paper_size,
        "our_vars": layout.size, "backend": ours.steps[-1].backend,
        "s_per_iter": per_iteration(ours), "iterations": ours.iterations,
        "status": ours.status, "R": ours.R, "wall": wall,
        "ref_s_per_iter": per_iteration(ref),
        "floor": factor_solve_floor(f, weights, kwargs, ours),
    }


def main() -> int:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next(line.split(":", 1)[1].strip() for line in fh if "model name" in line)
    except (OSError, StopIteration):
        pass
    print(f"machine: {cpu}, Python {platform.python_version()}, "
          f"solvers available: {', '.join(available_backends())}")
    rows = [run(isometric_problem()), run(fit_problem())]
    header = (f"{'problem':30} {'|V|':>5} {'paper vars':>10} {'our vars':>8} "
              f"{'s/iter':>8} {'iters':>5} {'status':>9} {'R':>9} "
              f"{'spsolve s/iter':>14} {'ratio':>6} {'target s/iter':>13} "
              f"{'factor+solve s':>14} {'iter/floor':>10}")
    print(header)
    print("-" * len(header))
    targets = {441: 0.0125, 4797: 0.33}
    ok = True
    for r in rows:
        target = targets.get(r["vertices"])
        ratio = r["ref_s_per_iter"] / r["s_per_iter"]
        print(f"{r['problem']:30} {r['vertices']:5d} {r['paper_vars']:10d} {r['our_vars']:8d} "
              f"{r['s_per_iter']:8.4f} {r['iterations']:5d} {r['status']:>9} {r['R']:9.1e} "
              f"{r['ref_s_per_iter']:14.3f} {ratio:5.0f}× {target:13.4f} "
              f"{r['floor']:14.4f} {r['s_per_iter'] / r['floor']:9.2f}×")
        ok &= target is None or r["s_per_iter"] <= target
    print("all per-iteration targets met" if ok else "per-iteration target NOT met")
    return 0


if __name__ == "__main__":
    sys.exit(main())
