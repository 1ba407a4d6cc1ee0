"""A patch set with a failed member (an arched roof unfolded with a stock length one patch's
strips cannot be cut into): the set records the member, its stage, exit code and reason, its
exit code is the worst member's, and every later stage refuses it in one line before computing
and without writing, so that no cut sheet is made of half a roof. ``inspect`` still shows it.

Two walls of revolution stand in for two patches: ``p1`` 9×7 over 60° (strips up to 740 mm
wide, wider than 0.7 m of stock), ``p2`` 25×7 over 20° (narrow strips, short quads: boards of
0.7 m fit)."""

import json
from pathlib import Path

import pytest
from cli_helpers import dgpc

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.patch_set import member_files, member_stems, read_patch_set
from dgpc_cli.stages.patch_set_run import write_patch_set

PROFILE = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"
NETS = {"p1": (9, 60), "p2": (25, 20)}            # rows, span (degrees); 7 columns each


def net_set(d: Path, name: str, members: dict, stage: str = "init", failed=()) -> Path:
    """A patch set ``d/name`` of the artifacts ``members`` (name -> stem) made by ``stage``,
    with the ``failed`` records."""
    write_patch_set(d / name, stage, [
        {"name": k, "kind": json.loads(artifact_paths(s)[0].read_text())["kind"],
         "json": artifact_paths(s)[0], "exit_code": 0,
         "files": member_files(artifact_paths(s)[0])} for k, s in members.items()],
        force=False, failed=list(failed))
    return d / name


@pytest.fixture(scope="module")
def failed_unfold(tmp_path_factory):
    """``(folder, result)``: the folder with the net set ``n`` (two walls), its strips set
    ``s`` and the flat set ``f`` of ``unfold s --stock-length 0.7m``, which fails on ``p1``;
    the result of that ``unfold``."""
    d = tmp_path_factory.mktemp("roof")
    for name, (rows, span) in NETS.items():
        dgpc("init", "--surface", "revolution", "--profile", PROFILE, "--rows", rows,
             "--cols", 7, "--span", span, "--units", "m", "-o", d / f"w{name}")
    net_set(d, "n", {k: d / f"w{k}" for k in NETS})
    dgpc("planarize-strips", d / "n", "-o", d / "s")
    return d, dgpc("unfold", d / "s", "--stock-length", "0.7m", "-o", d / "f", expect=1)


@pytest.fixture
def roof(failed_unfold):
    return failed_unfold[0]


def files_of(d: Path) -> set[str]:
    return {p.name for p in d.iterdir()}


def test_the_set_records_the_failed_member(failed_unfold):
    roof, r = failed_unfold
    assert r.stdout.split() == [str(roof / "f.p2.json")]    # the output of p2 only
    last = r.stderr.strip().splitlines()[-1]
    assert "f.json" in last and "1 of the patch set's 2 members failed (p1)" in last
    assert any(line.startswith("unfold: p1: exit 1:") and "shorter than the strips are wide"
               in line for line in r.stderr.splitlines())
    doc = read_patch_set(roof / "f")                        # valid by its schema
    assert doc["status"]["exit_code"] == 1
    assert [m["name"] for m in doc["data"]["members"]] == ["p2"]
    (failed,) = doc["data"]["failed"]
    assert failed["name"] == "p1" and failed["stage"] == "unfold" and failed["exit_code"] == 1
    assert "shorter than the strips are wide" in failed["reason"]
    assert "\n" not in failed["reason"] and "/" not in failed["reason"].split(":")[0]
    assert not list(roof.glob("f.p1.*"))                    # no output of the failed member
    assert (roof / "f.p2.json").is_file()


def test_inspect_shows_the_failed_member(roof):
    shown = json.loads(dgpc("inspect", roof / "f").stdout)
    assert set(shown["members"]) == {"p2"} and shown["members"]["p2"]["kind"] == "flat"
    assert shown["failed"]["p1"]["stage"] == "unfold"
    assert shown["failed"]["p1"]["exit_code"] == 1
    assert "shorter than the strips are wide" in shown["failed"]["p1"]["reason"]


@pytest.mark.parametrize("command", [
    ("nest", "f", "--sheet", "8000x3000", "-o", "out"),
    ("unfold", "f", "-o", "out"),
    ("report", "f", "-o", "out"),
])
def test_later_stages_refuse_a_set_with_a_failed_member(roof, command):
    before = files_of(roof)
    r = dgpc(*(roof / a if a in ("f", "out") else a for a in command), expect=1)
    (line,) = r.stderr.strip().splitlines()                 # one line
    assert line.startswith(f"Error: {roof / 'f.json'}: data.failed: member p1 (exit 1) "
                           "failed in `dgpc unfold`"), line
    assert r.stdout == "" and files_of(roof) == before       # nothing written


@pytest.mark.parametrize("command", [
    ("planarize-strips", "bad", "-o", "out"),
    ("optimize", "bad", "--mode", "fit", "-o", "out"),
])
def test_net_stages_refuse_a_net_set_with_a_failed_member(roof, command):
    """A set of nets whose ``optimize`` failed on p1 and p2: both named, the stage too."""
    bad = net_set(roof, "bad", {"p3": roof / "wp2"}, stage="optimize", failed=[
        {"name": "p1", "exit_code": 1, "reason": "wp1.json: the solve diverged"},
        {"name": "p2", "exit_code": 3, "reason": "wp2.json: not converged"}])
    before = files_of(roof)
    r = dgpc(*(roof / a if a in ("bad", "out") else a for a in command), expect=1)
    (line,) = r.stderr.strip().splitlines()
    assert f"{bad}.json: data.failed: members p1 (exit 1), p2 (exit 3) failed in " \
           "`dgpc optimize`" in line, line
    assert files_of(roof) == before
    with pytest.raises(DgpcError, match="p1 .* p2 .* failed in `dgpc optimize`"):
        member_stems(bad)
    (roof / "bad.json").unlink()


def test_a_whole_set_still_goes_through(roof, tmp_path):
    """Without the stock length both members unfold: the set has no ``failed`` and nests
    (the parts of both members on the sheets)."""
    r = dgpc("unfold", roof / "s", "-o", tmp_path / "g")
    doc = read_patch_set(tmp_path / "g")
    assert "failed" not in doc["data"] and doc["status"]["exit_code"] == 0
    assert [m["name"] for m in doc["data"]["members"]] == ["p1", "p2"]
    assert r.stdout.split()[-1] == str(tmp_path / "g.json")
    dgpc("nest", tmp_path / "g", "--sheet", "8000x3000", "-o", tmp_path / "sheets")
    sheets = json.loads((tmp_path / "sheets.json").read_text())["data"]["sheets"]
    assert {p.split(":")[0] for sheet in sheets for p in sheet["parts"]} == {"g.p1", "g.p2"}


def test_a_rerun_that_passes_replaces_the_failed_set(roof, tmp_path):
    """The failed set is replaced by the rerun with a stock length both members take (each
    member's output listed, nothing failed), and a rerun that fails again over a whole set
    removes the failed member's old files."""
    dgpc("unfold", roof / "s", "--stock-length", "0.7m", "-o", tmp_path / "f", expect=1)
    dgpc("unfold", roof / "s", "-o", tmp_path / "f", "--force")
    assert "failed" not in read_patch_set(tmp_path / "f")["data"]
    assert (tmp_path / "f.p1.json").is_file()
    dgpc("unfold", roof / "s", "--stock-length", "0.7m", "-o", tmp_path / "f", "--force",
         expect=1)
    assert [m["name"] for m in read_patch_set(tmp_path / "f")["data"]["failed"]] == ["p1"]
    assert not list(tmp_path.glob("f.p1.*"))


def test_every_member_failed_is_recorded_too(roof, tmp_path):
    """Stock shorter than both members' strips are wide: the set lists no output, only the
    failures (and is refused downstream)."""
    dgpc("unfold", roof / "s", "--stock-length", "0.1m", "-o", tmp_path / "f", expect=1)
    doc = read_patch_set(tmp_path / "f")
    assert doc["data"]["members"] == []
    assert [m["name"] for m in doc["data"]["failed"]] == ["p1", "p2"]
    r = dgpc("nest", tmp_path / "f", "--sheet", "8000x3000", "-o", tmp_path / "o", expect=1)
    assert "members p1 (exit 1), p2 (exit 1) failed in `dgpc unfold`" in r.stderr


@pytest.mark.parametrize("bad, field", [
    ({"name": "p1", "stage": "unfold", "exit_code": 0, "reason": "x"}, "exit_code"),
    ({"name": "p1", "stage": "unfold", "exit_code": 1}, "reason"),
    ({"name": "p2", "stage": "unfold", "exit_code": 1, "reason": "x"}, "more than once"),
])
def test_a_damaged_failure_record_is_refused(roof, tmp_path, bad, field):
    doc = json.loads((roof / "f.json").read_text())
    doc["data"]["failed"] = [bad]
    for name in ("f.json", "f.p2.json", "f.p2.obj"):
        (tmp_path / name).write_bytes((roof / name).read_bytes())
    (tmp_path / "f.json").write_text(json.dumps(doc))
    listed = [m["files"] for m in doc["data"]["members"]]
    for files in listed:
        for name in files:
            (tmp_path / name).write_bytes((roof / name).read_bytes())
    with pytest.raises(DgpcError, match=field):
        read_patch_set(tmp_path / "f")
