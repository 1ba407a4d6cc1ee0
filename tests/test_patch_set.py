"""The patch set (issue "a real roof clad by the default command"): ``init --patches`` writes
``STEM.json`` listing its nets; ``optimize`` given a set runs on each member and writes the set
of its outputs (exit code: the worst member's), ``inspect`` shows each member; a rerun with
fewer members removes the files of those it no longer makes (by the set's lists, nothing
else); one net over an old set removes the set's members."""

import json

import pytest
from cli_helpers import dgpc
from outline_meshes import write
from patch_meshes import two_lobes, vault

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.net import read_net
from dgpc_cli.io.patch_set import is_patch_set, member_stems, read_patch_set

ALONG = ("--method", "geodesic", "--direction", "1,0,0", "--units", "m")


@pytest.fixture(scope="module")
def lobes(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    return write(d / "lobes.obj", two_lobes())


def test_init_writes_the_set_of_its_nets(lobes, tmp_path):
    for name in ("one", "two"):
        (tmp_path / name).mkdir()
        dgpc("init", lobes, *ALONG, "--patches", 2, "-o", tmp_path / name / "a")
    a = tmp_path / "one" / "a"
    doc = read_patch_set(a)                                     # validated by its schema
    assert doc["kind"] == "patchset" and doc["data"]["stage"] == "init"
    members = doc["data"]["members"]
    assert [m["name"] for m in members] == ["p1", "p2"]
    for k, m in enumerate(members, start=1):
        assert m["path"] == f"a.p{k}.json" and m["kind"] == "net" and m["exit_code"] == 0
        assert {f"a.p{k}.json", f"a.p{k}.obj", f"a.p{k}.patch.obj"} <= set(m["files"])
        assert all((a.parent / f).is_file() for f in m["files"])
        read_net(a.parent / m["path"])
    # deterministic bytes
    assert (tmp_path / "one" / "a.json").read_bytes() == (tmp_path / "two" / "a.json").read_bytes()


def test_a_stage_runs_on_every_member(lobes, tmp_path):
    dgpc("init", lobes, *ALONG, "--patches", 2, "-o", tmp_path / "a")
    r = dgpc("optimize", tmp_path / "a", "--mode", "fit", "-o", tmp_path / "b")
    assert r.stdout.split()[-1] == str(tmp_path / "b.json")
    assert [line.split(":")[1].strip() for line in r.stderr.splitlines()
            if line.startswith("optimize: p")] == ["p1", "p2"]
    assert [s.name for _, s in member_stems(tmp_path / "b")] == ["b.p1", "b.p2"]
    for k in (1, 2):                 # each member fitted to its own patch
        net = read_net(tmp_path / f"b.p{k}")
        assert net.data["reference"]["path"] == f"a.p{k}.patch.obj"
        assert net.metrics["coverage"]["area_fraction"] > 0.9
    shown = json.loads(dgpc("inspect", tmp_path / "b").stdout)
    assert set(shown["members"]) == {"p1", "p2"}
    assert all(m["kind"] == "net" and "R" in m for m in shown["members"].values())
    written = dgpc("report", tmp_path / "b", "-o", tmp_path / "r").stdout.split()
    assert written[-1].endswith("r-index.html")
    assert all(any(f"r-b.p{k}-" in p for p in written) for k in (1, 2))
    # members that do not converge: the set is written, the exit code is theirs (3)
    r = dgpc("optimize", tmp_path / "a", "--mode", "fit", "--max-iter", 1, "-o",
             tmp_path / "c", expect=3)
    assert [m["exit_code"] for m in read_patch_set(tmp_path / "c")["data"]["members"]] == [3, 3]


def test_a_rerun_removes_the_members_it_no_longer_makes(lobes, tmp_path):
    dgpc("init", lobes, *ALONG, "--patches", 3, "-o", tmp_path / "a")
    assert (tmp_path / "a.p3.json").is_file() and (tmp_path / "a.p3.patch.obj").is_file()
    other = tmp_path / "a.p9.json"                      # not the set's: never removed
    other.write_text("{}")
    dgpc("init", lobes, *ALONG, "--patches", 2, "--force", "-o", tmp_path / "a")
    assert [m["name"] for m in read_patch_set(tmp_path / "a")["data"]["members"]] == \
        ["p1", "p2"]
    assert not list(tmp_path.glob("a.p3.*")) and other.is_file()
    # one net over the set: the set's members go, the net is STEM
    dgpc("init", lobes, *ALONG, "--force", "-o", tmp_path / "a")
    assert not is_patch_set(tmp_path / "a") and read_net(tmp_path / "a").shape[0] >= 3
    assert sorted(p.name for p in tmp_path.glob("a.*")) == ["a.json", "a.obj", "a.p9.json"]


def test_a_damaged_set_is_refused(lobes, tmp_path):
    dgpc("init", lobes, *ALONG, "--patches", 2, "-o", tmp_path / "a")
    doc = json.loads((tmp_path / "a.json").read_text())
    doc["data"]["members"][0]["path"] = "../elsewhere.json"
    (tmp_path / "a.json").write_text(json.dumps(doc))
    with pytest.raises(DgpcError, match="members"):
        read_patch_set(tmp_path / "a")
    r = dgpc("optimize", tmp_path / "a", "--mode", "fit", "-o", tmp_path / "b", expect=1)
    assert "data.members[0].path" in r.stderr


def test_a_good_single_net_is_not_split(tmp_path):
    """Where the automatic single net is good, init MESH writes it as before: one net, no set,
    no record of patches."""
    mesh = write(tmp_path / "vault.obj", vault())
    r = dgpc("init", mesh, "--units", "m", "-o", tmp_path / "v")
    assert r.stdout.split() == [str(tmp_path / "v.json")]
    assert "patches" not in read_net(tmp_path / "v").data and "--patches" not in r.stderr
