"""``dgpc edit --replay``: recorded drags go through the page's solver thread without a page;
the saved artifact is the one ``optimize`` writes for the saved handles file, byte for byte,
and the log has each event's latency."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import dgpc, wall_net

from dgpc_cli.io.net import read_net

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-replay")
    wall_net(d, 21, 13)
    return d


def drags(d: Path) -> Path:
    """The demo wall's handles: three placed at once, the fourth dragged there in 8 moves
    (the last one ends the drag)."""
    handles = json.loads((ROOT / "samples/handles/wall-21x13.json").read_text())["handles"]
    f = read_net(d / "wall").f
    events = [{"handle": h["index"], "target": h["target"], "time": 0.0} for h in handles[:3]]
    last = handles[3]
    start = f[tuple(last["index"])]
    for k in range(1, 9):
        target = start + (np.array(last["target"]) - start) * k / 8
        events.append({"handle": last["index"], "target": target.tolist(), "time": 0.05 * k,
                       **({"end": True} if k == 8 else {})})
    path = d / "drags.json"
    path.write_text(json.dumps({"events": events}))
    return path


def test_replay_gives_the_bytes_of_optimize_with_the_final_handles(wall):
    (wall / "a").mkdir()
    (wall / "b").mkdir()
    result = dgpc("edit", wall / "wall", "--mode", "isometric", "--replay", drags(wall),
                  "--steps", 5, "-o", wall / "a" / "out")
    assert result.stdout.strip() == str(wall / "a" / "out.json")
    shutil.copy(wall / "a" / "out-handles.json", wall / "b" / "out-handles.json")
    dgpc("optimize", wall / "wall", "--mode", "isometric", "--handles",
         wall / "b" / "out-handles.json", "--steps", 5, "-o", wall / "b" / "out")
    for name in ("out.json", "out.obj"):
        assert (wall / "a" / name).read_bytes() == (wall / "b" / name).read_bytes(), name
    art = json.loads((wall / "a" / "out.json").read_text())
    assert art["status"]["state"] == "converged"
    # the dragged handle reached its last target; the log has a latency per shown event
    saved = json.loads((wall / "a" / "out-handles.json").read_text())["handles"]
    assert len(saved) == 4
    log = json.loads((wall / "a" / "out-replay.json").read_text())
    shown = [e for e in log["events"] if "latency" in e]
    assert shown and all(e["latency"] > 0 and e["iterations"] >= 0 for e in shown)
    assert len(log["events"]) == 11                  # every event: shown or superseded
    assert log["settles"] and log["settles"][-1]["state"] == "converged"


def test_replay_of_a_bad_drags_file_is_one_line(wall):
    bad = wall / "bad.json"
    bad.write_text(json.dumps({"events": [{"handle": [99, 0], "target": [0, 0, 0],
                                           "time": 0}]}))
    result = dgpc("edit", wall / "wall", "--replay", bad, "-o", wall / "bad-out", expect=1)
    assert "events[0].handle" in result.stderr and "outside" in result.stderr
    assert not (wall / "bad-out.json").exists()


@pytest.mark.parametrize("mode", ["revolution", "isometric"])
def test_replay_exit_code_and_bytes_are_optimizes_on_a_coarse_wall(tmp_path, mode):
    """9×7: the middle of row 0 pushed 10 % towards the axis: converged in revolution mode; in
    isometric mode above a --max-strain of 1e-9 (exit 3 from both, the same bytes written
    anyway)."""
    wall_net(tmp_path, 9, 7)
    f = read_net(tmp_path / "wall").f
    p = f[0, 3]
    push = (p - 0.1 * np.array([p[0], p[1], 0.0])).tolist()
    strict = ["--max-strain", "1e-9"] if mode == "isometric" else []
    events = [{"handle": [8, 0], "action": "pin", "time": 0.0},
              {"handle": [8, 6], "action": "pin", "time": 0.0},
              {"handle": [0, 3], "target": push, "time": 0.1, "end": True}]
    (tmp_path / "drags.json").write_text(json.dumps({"events": events}))
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first = dgpc("edit", tmp_path / "wall", "--mode", mode, "--replay", tmp_path / "drags.json",
                 *strict, "-o", tmp_path / "a" / "out", expect=None)
    shutil.copy(tmp_path / "a" / "out-handles.json", tmp_path / "b" / "out-handles.json")
    second = dgpc("optimize", tmp_path / "wall", "--mode", mode, "--handles",
                  tmp_path / "b" / "out-handles.json", *strict, "-o", tmp_path / "b" / "out",
                  expect=None)
    assert first.exit_code == second.exit_code
    assert first.exit_code == (0 if mode == "revolution" else 3)
    for name in ("out.json", "out.obj"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
