"""The session behind ``dgpc edit`` (no page): handles, live drags warm-started from the net on
screen, settling as ``optimize`` does, undo/redo, the solver thread's supersession, the drags
file and the crease measure the page flags."""

import json
import threading

import numpy as np
import pytest
from cli_helpers import wall_net

from dgpc_cli.edit.live import LiveSolver, Request
from dgpc_cli.edit.session import EditSession
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.modes import mode_weights
from dgpc_cli.io.drags import read_drags
from dgpc_cli.metrics.crease import CREASE_LIMIT, crease, creased_vertices
from dgpc_cli.stages.optimize_artifact import (
    OptimizeSettings,
    optimize_prepared,
    prepare_optimize,
)

M, N = 9, 7


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-session")
    wall_net(d, M, N)
    return d


def session(d, mode="isometric"):
    settings = OptimizeSettings(mode, mode_weights(mode), max_strain=1e-3, gpc_tol=1e-3)
    return EditSession(prepare_optimize(d / "wall", settings))


def pushed(s, fraction=0.05):
    """Hold the corners of row M−1, push the middle of row 0 towards the axis."""
    s.pin(M - 1, 0)
    s.pin(M - 1, N - 1)
    p = np.array(s.position(0, N // 2))
    return p - fraction * np.array([p[0], p[1], 0.0])


def test_a_drag_moves_the_net_towards_the_handle_and_settles_as_optimize(wall):
    s = session(wall)
    f_in = s.f_mm.copy()
    target = pushed(s)
    assert len(s.handles) == 2 and not s.settled
    start = np.array(s.position(0, N // 2))
    for k in range(1, 4):
        s.drag(0, N // 2, start + (target - start) * k / 3)
    live = np.array(s.position(0, N // 2))
    # warm-started iterations bring the handle most of the way at once
    assert np.linalg.norm(live - target) < 0.5 * np.linalg.norm(start - target)
    frame = s.frame()
    assert frame.state.startswith("dragging") and frame.field.shape == (M, N)
    assert frame.field_name == "strain" and not frame.settled
    outcome = s.settle()
    ids, targets = s.handle_arrays()
    again = optimize_prepared(s.prepared, ids, targets)
    assert np.array_equal(outcome.f, again.f)          # settling is optimize's own run
    assert s.frame().state == outcome.status
    assert np.abs(s.f_mm - f_in).max() > 1.0            # mm: the design moved


def test_undo_and_redo_restore_handles_and_net(wall):
    s = session(wall)
    target = pushed(s)
    two = dict(s.handles)
    s.drag(0, N // 2, target)
    s.drag(0, N // 2, target)                           # the same drag: one undo step
    s.settle()
    settled = s.f_mm.copy()
    assert s.undo()
    assert s.handles == two and not s.settled
    assert s.redo()
    assert s.settled and np.array_equal(s.f_mm, settled)
    s.release(0, N // 2)
    assert (0 * N + N // 2) not in s.handles
    assert s.undo() and (0 * N + N // 2) in s.handles


def test_revolution_frame_is_coloured_by_panel_error(wall):
    s = session(wall, "revolution")
    frame = s.frame()
    assert frame.field_name == "panel error" and frame.state == "input"
    assert np.nanmax(frame.field) < 1e-9                # the input is a surface of revolution


def test_a_newer_drag_supersedes_a_waiting_one(wall):
    s = session(wall)
    target = pushed(s)
    answers, done = [], threading.Event()

    def on_frame(answer):
        answers.append(answer)
        if answer.request.action == "settle":
            done.set()

    solver = LiveSolver(s, on_frame)
    try:
        start = np.array(s.position(0, N // 2))
        for k in range(1, 21):
            solver.submit(Request("drag", (0, N // 2, start + (target - start) * k / 20),
                                  end=k == 20, tag=k))
        assert done.wait(300)
        assert solver.wait_idle(60)
    finally:
        solver.close()
    drags = [a for a in answers if a.request.action == "drag" and not a.refresh]
    assert len(drags) == 20
    assert any(a.frame is None for a in drags)           # superseded before they ran
    assert drags[-1].frame is not None                   # the last one always runs
    assert s.handles[0 * N + N // 2] == pytest.approx(tuple(target))
    assert s.settled and s.outcome is not None


def test_drags_file_errors_name_the_entry(tmp_path):
    path = tmp_path / "d.json"
    cases = [
        ({"events": [{"handle": [0, 0], "time": 0}]}, "events[0].target"),
        ({"events": [{"handle": [0, 0], "target": [0, 0, 0], "time": 1},
                     {"handle": [0, 0], "target": [0, 0, 0], "time": 0.5}]}, "events[1].time"),
        ({"events": [{"handle": [0, 9], "target": [0, 0, 0], "time": 0}]}, "events[0].handle"),
        ({"events": []}, "events"),
    ]
    for doc, where in cases:
        path.write_text(json.dumps(doc))
        with pytest.raises(DgpcError, match=where.replace("[", r"\[").replace("]", r"\]")):
            read_drags(path, (M, N))
    path.write_text(json.dumps({"events": [{"handle": [1, 2], "action": "pin", "time": 0}]}))
    (event,) = read_drags(path, (M, N))
    assert event.action == "pin" and event.index == (1, 2) and event.target is None


def test_crease_is_small_on_a_circle_and_flags_a_kink():
    t = np.linspace(0, np.pi / 2, 13)
    row = np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], -1)
    f = np.stack([row + [0, 0, z] for z in np.linspace(0, 1, 5)])
    assert crease(f).max() < 0.5 * CREASE_LIMIT
    assert not creased_vertices(f).any()
    kinked = f.copy()
    kinked[:, 6:, 0] += 0.5 * np.arange(7) * (t[1] - t[0])   # a bend at column 6
    c = crease(kinked)
    assert c.max() > CREASE_LIMIT
    assert creased_vertices(kinked)[:, 5:8].any() and not creased_vertices(kinked)[:, :3].any()
