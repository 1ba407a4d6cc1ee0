"""A failed drag does not look like success downstream (stages.input_status): optimize's exit 3
names the handle it missed, by how much and what to try; every later stage refuses the net,
and what is built from it with --accept-status, in one line naming its status; the report's
strain figure keeps round-off pale."""

import json
import shutil

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.io.net import read_net
from dgpc_cli.report.net import strain_scale_top
from dgpc_cli.stages.input_status import shortfall

WALL = "samples/profiles/wall.csv"


@pytest.fixture(scope="module")
def failed(tmp_path_factory):
    """A 9 × 7 wall in metres (``base``) and a drag it cannot follow (``wall``): one bottom
    corner pinned, the other pulled 3 m up; optimize stops (stagnated) with the handle short
    of its target, exit 3, the net written anyway."""
    d = tmp_path_factory.mktemp("failed")
    dgpc("init", "--surface", "revolution", "--profile", WALL, "--rows", 9, "--cols", 7,
         "--span", 60, "--units", "m", "-o", d / "base")
    (d / "h.json").write_text(json.dumps({"handles": [
        {"index": [0, 0], "offset": [0, 0, 0]}, {"index": [0, 6], "offset": [0, 0, 3]}]}))
    r = dgpc("optimize", d / "base", "--mode", "isometric", "--handles", d / "h.json",
             "--steps", 5, "-o", d / "wall", expect=3)
    return d, r


def _one_error(r) -> str:
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("Error: "), r.stderr
    return lines[0]


def _stems(folder) -> set[str]:
    return {p.name for p in folder.iterdir()}


def test_the_stagnation_names_the_handle_the_distance_and_what_to_try(failed):
    d, r = failed
    line = _one_error(r)
    net = read_net(d / "wall")
    assert net.status["state"] == "stagnated" and line.startswith("Error: ")
    assert "stagnated" in line and "written anyway" in line
    # the handle, the distance it missed in the net's unit, and the remedies
    assert "handle [0, 6] stopped " in line and " m short of its target (dragged 3 m)" in line
    assert "drag it less or in more --steps" in line and "pin fewer vertices" in line
    miss = float(line.split("handle [0, 6] stopped ")[1].split(" m short")[0])
    target = read_net(d / "base").f[0, 6] + [0, 0, 3]
    assert miss == pytest.approx(float(np.linalg.norm(net.f[0, 6] - target)), rel=1e-2)
    assert miss > 0.1


@pytest.mark.parametrize("args", [
    ["planarize-strips", "{d}/wall", "-o", "{o}/strips"],
    ["extract-mold", "{d}/wall", "-o", "{o}/mold"],
    ["laths", "{d}/wall", "{d}/base", "-o", "{o}/laths"],
])
def test_every_next_stage_refuses_the_failed_drag(failed, tmp_path, args):
    d, _ = failed
    before = _stems(d)
    r = dgpc(*[a.format(d=d, o=tmp_path) for a in args], expect=1)
    line = _one_error(r)
    assert "wall.json: its status is stagnated (" in line and "--accept-status" in line
    assert _stems(d) == before and list(tmp_path.iterdir()) == []


def test_the_status_travels_to_the_cut_sheets(failed, tmp_path):
    """With --accept-status each stage goes on, says so, and records what it built on; the
    next stage asks again: strips, flat parts and sheets each refuse the accepted state."""
    d, _ = failed
    shutil.copy(d / "wall.json", tmp_path)
    shutil.copy(d / "wall.obj", tmp_path)
    r = dgpc("planarize-strips", tmp_path / "wall", "--accept-status", "-o", tmp_path / "s")
    assert "status stagnated" in r.stderr and "going on with it (--accept-status)" in r.stderr
    strips = json.loads((tmp_path / "s.json").read_text())
    assert strips["status"]["accepted"] == [{"input": "net", "state": "stagnated"}]
    line = _one_error(dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f", expect=1))
    assert "s.json: its status is stagnated (built from its input net with --accept-status)" \
        in line
    assert not list(tmp_path.glob("f.*"))
    dgpc("unfold", tmp_path / "s", "--accept-status", "-o", tmp_path / "f")
    flat = json.loads((tmp_path / "f.json").read_text())
    assert flat["status"]["accepted"] == [{"input": "strips", "state": "stagnated"}]
    line = _one_error(dgpc("nest", tmp_path / "f", "--sheet", "6100x2500", "-o",
                           tmp_path / "sh", expect=1))
    assert "f.json: its status is stagnated" in line
    assert not list(tmp_path.glob("sh.*"))
    dgpc("nest", tmp_path / "f", "--sheet", "6100x2500", "--no-preview", "--accept-status",
         "-o", tmp_path / "sh")
    sheets = json.loads((tmp_path / "sh.json").read_text())
    assert sheets["status"]["accepted"] == [{"input": "flat", "state": "stagnated"}]


def test_a_converged_net_goes_on_without_a_word(failed, tmp_path):
    d, _ = failed
    r = dgpc("planarize-strips", d / "base", "-o", tmp_path / "s")
    assert "status" not in r.stderr
    assert "accepted" not in json.loads((tmp_path / "s.json").read_text())["status"]


@pytest.mark.parametrize("status, state", [
    ({}, None), ({"state": "converged"}, None), ({"state": "ok"}, None),
    ({"state": "max_iter", "message": "iteration limit 3 reached"}, "max_iter"),
    ({"state": "missed_tolerance"}, "missed_tolerance"), ({"state": "pleated"}, "pleated"),
    ({"polished": 2, "polish_not_converged": ["S-v01"], "rulings_cross": []},
     "polish_not_converged"),
    ({"polished": 0, "polish_not_converged": [], "rulings_cross": ["S-v03"]}, "rulings_cross"),
    ({"n_classes": 1, "accepted": [{"input": "strips", "state": "max_iter"}]}, "max_iter"),
])
def test_what_falls_short(status, state):
    found = shortfall(status)
    assert (found and found[0]) == state


def test_strips_short_of_their_polish_are_refused_by_unfold(failed, tmp_path):
    d, _ = failed
    dgpc("planarize-strips", d / "base", "-o", tmp_path / "s")
    doc = json.loads((tmp_path / "s.json").read_text())
    doc["status"]["polish_not_converged"] = ["S-v02"]
    (tmp_path / "s.json").write_text(json.dumps(doc))
    line = _one_error(dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f", expect=1))
    assert "its status is polish_not_converged (S-v02)" in line


def test_round_off_is_never_red_in_the_strain_figure():
    """An unmoved net's strain is round-off (1e-15): the scale runs to the tolerance, so it
    sits at the scale's pale bottom; a strain above the tolerance sets the scale itself."""
    roundoff = np.array([1.9e-15, 0.0, 1e-16])
    top = strain_scale_top(roundoff, 3e-4)
    assert top == 3e-4 and roundoff.max() / top < 1e-10
    assert strain_scale_top(np.array([1e-3, 2e-4]), 3e-4) == 1e-3
    assert strain_scale_top(np.array([np.nan, 0.0]), None) == 1.0
