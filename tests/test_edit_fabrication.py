"""The editor's fabrication figures tell the pipeline's truth: settled, they are what
``planarize-strips`` and ``unfold`` (their defaults) write for the saved net; while a handle
moves, the last strips are bent onto the moved net, only those whose net strip moved, and
unmoved they give the pipeline's figures back. The page's texts and camera: no emoji, the
figures' source said, column 0 on the left; undo leaves no stale run figures."""

import json
import unicodedata

import numpy as np
import pytest
from cli_helpers import dgpc, wall_net

from dgpc_cli.edit.fabrication import live_figures, pipeline_figures
from dgpc_cli.edit.page import (
    _fabrication_markdown,
    _field_markdown,
    _status_markdown,
    initial_camera,
)
from dgpc_cli.edit.session import EditSession
from dgpc_cli.fitting.modes import mode_weights
from dgpc_cli.io.net import read_net
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize

M, N = 9, 7


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-fabrication")
    wall_net(d, M, N)
    return d


def _session(d):
    settings = OptimizeSettings("isometric", mode_weights("isometric"), max_strain=1e-3,
                                gpc_tol=1e-3)
    return EditSession(prepare_optimize(d / "wall", settings))


def _pushed_session(d):
    """Row M−1's corners held, the middle of row 0 pushed 5 % towards the axis, settled."""
    s = _session(d)
    s.pin(M - 1, 0)
    s.pin(M - 1, N - 1)
    p = np.array(s.position(0, N // 2))
    s.drag(0, N // 2, p - 0.05 * np.array([p[0], p[1], 0.0]))
    s.settle()
    return s


def test_settled_figures_are_those_planarize_strips_and_unfold_write(wall, tmp_path):
    s = _pushed_session(wall)
    s.save(tmp_path / "net")
    shown = s.fabrication()["strips"]
    assert shown["source"] == "pipeline"
    dgpc("planarize-strips", tmp_path / "net", "-o", tmp_path / "strips", expect=None)
    dgpc("unfold", tmp_path / "strips", "-o", tmp_path / "flat")
    strips = json.loads((tmp_path / "strips.json").read_text())
    flat = json.loads((tmp_path / "flat.json").read_text())
    fab = strips["metrics"]["fabrication"]
    assert shown["method"] == strips["parameters"]["method"]
    assert shown["refine"] == strips["parameters"].get("refine", 1)
    assert shown["templates"] == len(flat["data"]["classes"])
    assert shown["quantities"] == [c["quantity"] for c in flat["data"]["classes"]]
    # the artifacts hold the net's coordinates to their printed digits: equal to 1e-6
    assert shown["deviation"] == pytest.approx(fab["max_deviation_relative"], rel=1e-6)
    assert shown["seam_step"] == pytest.approx(fab["max_seam_step_relative"], rel=1e-6)


def test_unmoved_live_figures_are_the_pipelines_and_only_moved_strips_are_bent(wall):
    f = read_net(wall / "wall").f_mm
    figures, state = pipeline_figures(f, "m")
    assert figures["method"] == "template" and figures["templates"] == 1
    live, bent = live_figures(state, f)
    assert bent == 0 and live["source"] == "live"
    same = ("strips", "method", "refine", "templates", "quantities", "missed")
    assert {k: live[k] for k in same} == {k: figures[k] for k in same}
    for key in ("deviation", "seam_step"):                 # the same measures, in mm
        assert live[key] == pytest.approx(figures[key], rel=1e-9)
    # move the net beyond column 3 only: strips 3.. are touched, 0..2 are not
    g = f.copy()
    g[:, 4:] += np.linspace(0.0, 1.0, M)[:, None, None] * np.array([0.0, 0.0, 20.0])
    before, before_b = state.A.copy(), state.B.copy()
    live, bent = live_figures(state, g)
    assert bent == N - 1 - 3
    assert np.array_equal(state.A[:3], before[:3]) and not np.allclose(state.A[3:], before[3:])
    assert live["templates"] == 1 and live["deviation"] > figures["deviation"]
    # bent, the strips keep their flat shapes (the template): edges and rulings unchanged
    for A0, A1, B0, B1 in zip(before, state.A, before_b, state.B, strict=True):
        assert np.allclose(np.linalg.norm(np.diff(A1, axis=0), axis=-1),
                           np.linalg.norm(np.diff(A0, axis=0), axis=-1), atol=1e-6)
        assert np.allclose(np.linalg.norm(B1 - A1, axis=-1), np.linalg.norm(B0 - A0, axis=-1),
                           atol=1e-6)


def test_the_page_says_where_the_figures_come_from_without_emoji(wall):
    s = _pushed_session(wall)
    frame = s.frame(fabrication=True)
    texts = [_status_markdown(frame), _field_markdown(frame, 1e-3),
             _fabrication_markdown(frame.fabrication)]
    assert "planarize-strips and unfold make them" in texts[2]
    for text in texts:
        symbols = [c for c in text if unicodedata.category(c) == "So"]
        assert symbols == [], (symbols, text)
    # a drag: the live estimate, said so
    p = np.array(s.position(0, N // 2))
    s.drag(0, N // 2, p + 0.01 * np.array([p[0], p[1], 0.0]))
    live = _fabrication_markdown(s.frame(fabrication=True).fabrication)
    assert "live estimate" in live and "when it settles" in live


def test_undo_leaves_no_figures_of_another_run(wall):
    s = _pushed_session(wall)
    assert s.frame().iterations > 0 and "iterations" in _status_markdown(s.frame())
    s.undo()
    assert s.frame().iterations == 0 and "iterations" not in _status_markdown(s.frame())
    s.redo()
    s.pin(2, 2)
    assert "iterations" not in _status_markdown(s.frame())


def test_the_camera_puts_column_0_on_the_left_and_row_0_at_the_bottom(wall):
    f = read_net(wall / "wall").f
    centre, position = initial_camera(f)
    toward = (position - centre) / np.linalg.norm(position - centre)
    right = np.cross([0.0, 0.0, 1.0], toward)
    up = np.cross(toward, right)
    assert f[M // 2, 0] @ right < f[M // 2, N - 1] @ right
    assert f[0, N // 2] @ up < f[M - 1, N // 2] @ up
    # seen from the outside of the wall (away from its axis), as the report's views
    assert toward @ np.r_[f[M // 2, N // 2, :2], 0.0] > 0


class _NoGestures:
    def __getattr__(self, name):
        return lambda *args: None


def test_the_saved_line_changes_once_the_handles_change_after_a_save(wall):
    from dgpc_cli.edit.page import EditPage

    s = _pushed_session(wall)
    page = EditPage(s.frame(), _NoGestures(), host="127.0.0.1", port=0, title="t",
                    max_strain=1e-3)
    try:
        page.saved_to("Saved **out.json** (converged)", saved=True)
        page.show(s.frame())                           # the same handles: still saved
        assert page.saved.content.startswith("Saved")
        p = np.array(s.position(0, N // 2))
        s.drag(0, N // 2, p + 0.01 * np.array([p[0], p[1], 0.0]))
        page.show(s.quick_frame())
        assert "not saved" in page.saved.content
    finally:
        page.stop()


def test_the_pipelines_figures_come_from_a_worker_while_the_solver_goes_on(wall):
    """As the page runs it: the settled net's figures are asked of the fabrication worker;
    the solver answers at once with the figures pending, then with the pipeline's."""
    import threading

    from dgpc_cli.edit.fabrication import fabrication_figures
    from dgpc_cli.edit.fabrication_worker import FabricationWorker
    from dgpc_cli.edit.live import LiveSolver, Request

    s = _pushed_session(wall)
    answers, done = [], threading.Event()

    def on_frame(answer):
        answers.append(answer)
        fab = answer.frame.fabrication if answer.frame is not None else None
        if fab and (fab.get("strips") or {}).get("source") == "pipeline":
            done.set()

    solver = LiveSolver(s, on_frame, fabrication=lambda: True)
    worker = FabricationWorker(lambda f: fabrication_figures(f, "m"), lambda f, r: solver.submit(
        Request("call", (lambda x: x.fabricated(f, r),))))
    s.fabricate = worker.ask
    try:
        solver.submit(Request("call", (lambda x: None,)))
        assert done.wait(600)
    finally:
        worker.close()
        solver.close()
    first = answers[0].frame.fabrication
    assert first["pending"] and first["strips"] is None
    assert "at work on the settled net" in _fabrication_markdown(first)
    last = answers[-1].frame.fabrication
    assert "pending" not in last and last["strips"]["source"] == "pipeline"
    assert last["strips"] == pipeline_figures(s.f_mm, "m")[0]
