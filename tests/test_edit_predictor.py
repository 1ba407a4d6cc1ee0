"""Predictor steps of a live drag: a drag event between factorizations re-solves the last
factorized iteration for the handle's new target (one back-substitution). It is that iteration
redone with the new target, exactly; it refuses a workspace factorized for other terms; in a
session the handle follows every event while only every REFACTOR-th event factorizes."""

import numpy as np
import pytest
from cli_helpers import wall_net

from dgpc_cli.core.solver import guided_projection, predictor_step
from dgpc_cli.edit.session import REFACTOR, EditSession
from dgpc_cli.fitting.modes import SOFT, mode_weights
from dgpc_cli.fitting.optimize import net_problem
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize

M, N = 9, 7


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-predictor")
    wall_net(d, M, N)
    return d


def _problem(wall):
    prepared = prepare_optimize(wall / "wall", OptimizeSettings(
        "isometric", mode_weights("isometric")))
    f = prepared.net.f_mm
    ids = np.array([(M - 1) * N, M * N - 1, N // 2])       # row M−1's corners, row 0's middle
    problem = net_problem(f, prepared.settings.schedules, handle_ids=ids, soft=SOFT["isometric"])
    start = f.reshape(-1, 3)[ids]
    push = np.zeros_like(start)
    push[2] = -0.04 * np.array([start[2, 0], start[2, 1], 0.0])   # towards the axis
    return problem, start, push, f


def test_the_predictor_is_the_factorized_iteration_redone_for_the_new_target(wall):
    problem, start, push, f = _problem(wall)
    x0 = problem.x_from_vertices(f)
    first = guided_projection(x0, problem.terms(start + push), max_iter=1,
                              retract=problem.layout.orient_edges)
    assert first.workspace.linearization is not None
    moved = start + 2 * push                                # the handle dragged on
    terms = [problem.term("handles", moved) if t.name == "handles" else t
             for t in first.workspace.linearization.terms]
    step = predictor_step(terms, first.workspace, retract=problem.layout.orient_edges)
    assert step is not None and step.accepted
    # the same iteration from the same point with a factorization of its own
    again = guided_projection(x0, problem.terms(moved), max_iter=1,
                              retract=problem.layout.orient_edges)
    scale = np.abs(again.x - x0).max()
    assert scale > 1e-2                                     # the net moved
    assert np.abs(step.x - again.x).max() < 1e-8 * max(1.0, scale)
    # the dragged vertex is at its new target (the handles are constraints, 1e6)
    fv = problem.vertices(step.x).reshape(-1, 3)
    assert np.abs(fv[N // 2] - moved[2]).max() < 1e-3 * np.abs(push[2]).max()


def test_the_predictor_refuses_a_factorization_of_other_terms(wall):
    problem, start, push, f = _problem(wall)
    x0 = problem.x_from_vertices(f)
    first = guided_projection(x0, problem.terms(start + push), max_iter=1)
    other = problem.terms(start + 2 * push)          # every term bound anew: not these terms'
    step = predictor_step(other, first.workspace)
    assert step is not None                          # re-evaluated at x_k, the same pattern ...
    fewer = [t for t in other if t.name != "displacement_fairness"]
    assert predictor_step(fewer, first.workspace) is None       # ... but other terms: none
    assert predictor_step(other, None) is None


def test_a_session_drag_factorizes_every_refactor_events_and_the_handle_follows(wall):
    settings = OptimizeSettings("isometric", mode_weights("isometric"), max_strain=1e-3,
                                gpc_tol=1e-3)
    s = EditSession(prepare_optimize(wall / "wall", settings))
    s.pin(M - 1, 0)
    s.pin(M - 1, N - 1)
    p = np.array(s.position(0, N // 2))
    target = p - 0.05 * np.array([p[0], p[1], 0.0])
    counts, gaps = [], []
    for k in range(1, 2 * REFACTOR + 1):
        goal = p + (target - p) * k / (2 * REFACTOR)
        s.drag(0, N // 2, goal)
        counts.append(s.quick_frame().factorizations)
        gaps.append(np.linalg.norm(np.array(s.position(0, N // 2)) - goal))
    assert counts == ([1] + [0] * (REFACTOR - 1)) * 2
    step = np.linalg.norm(target - p) / (2 * REFACTOR)
    assert max(gaps) < 1e-3 * step, gaps             # every event brings the handle there
