"""``dgpc batch`` on a Dask LocalCluster of 2 worker processes (loopback only, no dashboard),
started and closed here: the four-patch facade of samples/projects/gehry-facade.toml at 9×7
against the same commands typed one by one, reruns that reuse what has not changed, a patch
with a bad input failing alone, project file errors.

The facade runs with the small versions' tolerances (tests/golden/pipelines.py SMALL_VARS)
and one strip per patch (``planarize-strips --strips 0:0``): the nesting's previews take a
few seconds per part.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import pytest
from cli_helpers import dgpc
from click.testing import CliRunner

from dgpc_cli.batch.cluster import local_cluster_options
from dgpc_cli.batch.summary import exit_code
from dgpc_cli.cli.main import cli
from dgpc_cli.io.flat import read_flat
from dgpc_cli.stages.combine_flats import combine_flats, flat_tags

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"
DGPC = str(Path(sys.executable).parent / "dgpc")
PATCHES = [f"facade-{k}" for k in range(1, 5)]


@contextmanager
def inside(folder: Path):
    """Run from ``folder`` (the batch's paths are relative to where it runs)."""
    here = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(here)


def small_project(text: str) -> str:
    """The sample facade project at 9×7 with the small versions' tolerances, one strip per
    patch and no figures."""
    subs = [("rows = 21", "rows = 9"), ("cols = 13", "cols = 7"), ("-21x13.json", "-9x7.json"),
            ("max-strain = 3e-4", "max-strain = 2e-3"), ("gpc-tol = 1e-4", "gpc-tol = 5e-4"),
            ("report = true", "report = false"),
            ("[defaults.planarize-strips]\n", '[defaults.planarize-strips]\nstrips = "0:0"\n')]
    for old, new in subs:
        assert old in text, old
        text = text.replace(old, new)
    return text


def workspace(folder: Path) -> Path:
    """``folder`` with the samples the facade reads, laid out as in the repository."""
    for sub in ("profiles", "handles"):
        (folder / "samples" / sub).mkdir(parents=True)
    shutil.copy(SAMPLES / "profiles" / "gehry.csv", folder / "samples" / "profiles")
    for k in range(1, 5):
        shutil.copy(SAMPLES / "handles" / f"gehry-{k}-9x7.json", folder / "samples" / "handles")
    (folder / "samples" / "projects").mkdir()
    text = (SAMPLES / "projects" / "gehry-facade.toml").read_text(encoding="utf-8")
    (folder / "samples" / "projects" / "facade.toml").write_text(small_project(text),
                                                                 encoding="utf-8")
    return folder


def batch(*args, expect=0):
    result = CliRunner().invoke(cli, ["batch", *map(str, args)], catch_exceptions=False)
    assert expect is None or result.exit_code == expect, \
        (result.exit_code, result.stdout, result.stderr)
    return result


def files(folder: Path) -> dict[str, bytes]:
    """Every file below ``folder`` but the batch's own summary, by relative path."""
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and p.relative_to(folder).as_posix() not in ("batch.json",
                                                                        "index.html")}


def stamps(folder: Path) -> dict[str, tuple[int, int]]:
    """(inode, mtime) of every file below ``folder``: an atomic rewrite changes both."""
    return {p.relative_to(folder).as_posix(): (p.stat().st_ino, p.stat().st_mtime_ns)
            for p in folder.rglob("*") if p.is_file()}


def cli_chain(out: str) -> None:
    """The facade typed command by command (as pipelines/gehry-facade.mk, with the layout of
    the batch's output folder): the patches two at a time, then the mold and the nesting."""
    def run(*args):
        subprocess.run([DGPC, "-q", *args, "--force"], check=True, stdout=subprocess.DEVNULL)

    def patch(k: int):
        d = f"{out}/facade-{k}"
        os.makedirs(d, exist_ok=True)
        run("init", "--surface", "revolution", "--profile", "samples/profiles/gehry.csv",
            "--rows", "9", "--cols", "7", "--span", "90", "--units", "m", "-o", f"{d}/base")
        run("optimize", f"{d}/base", "--mode", "isometric", "--handles",
            f"samples/handles/gehry-{k}-9x7.json", "--steps", "5", "--max-strain", "2e-3",
            "--gpc-tol", "5e-4", "-o", f"{d}/net")
        run("planarize-strips", f"{d}/net", "--strips", "0:0", "-o", f"{d}/strips")
        run("unfold", f"{d}/strips", "-o", f"{d}/flat")

    with ThreadPoolExecutor(2) as pool:
        list(pool.map(patch, range(1, 5)))
    os.makedirs(f"{out}/shared", exist_ok=True)
    run("extract-mold", *(f"{out}/facade-{k}/net" for k in range(1, 5)), "--lambda", "compact",
        "--panel-size", "2",
        "--max-strain", "2e-3", "-o", f"{out}/shared/mold-gehry")
    run("nest", *(f"{out}/facade-{k}/flat" for k in range(1, 5)), "--mold",
        f"{out}/shared/mold-gehry", "--sheet", "6000x1250", "-o", f"{out}/shared/sheets")


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster of 2 single-threaded worker processes on the loopback address."""
    from distributed import LocalCluster

    with LocalCluster(**local_cluster_options(2)) as c:
        yield c


@pytest.fixture(scope="module")
def facade(cluster, tmp_path_factory):
    """The facade through `dgpc batch` and through the CLI; the batch's first output (bytes)
    and its batch.json, kept before any test changes the workspace."""
    ws = workspace(tmp_path_factory.mktemp("facade"))
    with inside(ws):
        result = batch("samples/projects/facade.toml", "-o", "out/batch", "--scheduler",
                       cluster.scheduler_address)
        first = files(ws / "out" / "batch")
        doc = json.loads((ws / "out" / "batch" / "batch.json").read_text())
        cli_chain("out/cli")
    return {"ws": ws, "first": first, "doc": doc, "result": result,
            "scheduler": cluster.scheduler_address}


def test_facade_batch_writes_the_bytes_of_the_cli(facade):
    first, typed = facade["first"], files(facade["ws"] / "out" / "cli")
    assert sorted(first) == sorted(typed)
    assert len(first) > 40
    different = [name for name in typed if first[name] != typed[name]]
    assert different == []
    doc = facade["doc"]
    assert doc["status"] == "ok" and doc["exit_code"] == 0
    assert set(doc["patches"]) == set(PATCHES)
    for name in PATCHES:
        patch = doc["patches"][name]
        assert patch["status"] == "ok" and patch["message"] == ""
        assert patch["metrics"]["net"]["state"] == "converged"
        assert patch["metrics"]["net"]["max_strain"] <= 2e-3
        assert patch["outputs"]["flat"] == f"{name}/flat.json"
        assert doc["this_run"]["patches"][name]["wall_time_s"] > 0
    assert len(doc["this_run"]["executed"]) == len(doc["tasks"]) == 4 * 4 + 2
    assert doc["shared"]["status"] == "ok"
    assert facade["result"].stdout == "out/batch/batch.json\n"
    assert "4/5 " in facade["result"].stderr and "ETA" in facade["result"].stderr


def test_one_nesting_sums_the_classes_of_all_patches(facade):
    sheets = json.loads(facade["first"]["shared/sheets.json"])
    placed = sorted(p["part"] for p in sheets["data"]["placements"])
    assert placed == [f"facade-{k}:S-v00" for k in range(1, 5)]
    combined = sheets["data"]["combined"]
    assert combined["tags"] == PATCHES
    assert sum(c["quantity"] for c in combined["classes"]) == 4
    assert sum(sum(c["per_tag"].values()) for c in combined["classes"]) == 4
    for c in combined["classes"]:
        assert c["quantity"] == len(c["members"]) and c["representative"] in c["members"]
    assert sheets["metrics"]["classes"] == {c["id"]: c["quantity"]
                                            for c in combined["classes"]}
    assert sorted(sheets["inputs"]) == ["flat1", "flat2", "flat3", "flat4", "mold"]
    assert sheets["inputs"]["flat2"]["path"] == "../facade-2/flat.json"


def test_reruns_run_only_what_changed(facade):
    ws = facade["ws"]
    out = ws / "out" / "batch"
    before = stamps(out)
    with inside(ws):
        result = batch("samples/projects/facade.toml", "-o", "out/batch", "--scheduler",
                       facade["scheduler"], "-q")
    assert result.stderr == ""
    doc = json.loads((out / "batch.json").read_text())
    assert doc["this_run"]["executed"] == []
    assert len(doc["this_run"]["reused"]) == 18
    after = stamps(out)
    assert {k: v for k, v in after.items() if before.get(k) != v} \
        .keys() <= {"batch.json", "index.html"}
    strip = {k: v for k, v in doc.items() if k != "this_run"}
    assert strip == {k: v for k, v in facade["doc"].items() if k != "this_run"}

    # a designer moves one handle of facade-2: that patch, its mold and the nesting run again
    handles = ws / "samples" / "handles" / "gehry-2-9x7.json"
    moved = json.loads(handles.read_text())
    moved["handles"][3]["target"][2] -= 0.01
    handles.write_text(json.dumps(moved, indent=1))
    with inside(ws):
        batch("samples/projects/facade.toml", "-o", "out/batch", "--scheduler",
              facade["scheduler"], "-q")
    doc = json.loads((out / "batch.json").read_text())
    assert doc["this_run"]["executed"] == [
        "facade-2/optimize", "facade-2/planarize-strips", "facade-2/unfold",
        "shared/mold-gehry", "shared/nest"]
    changed = {k for k, v in stamps(out).items() if after.get(k) != v}
    assert not any(k.startswith(("facade-1/", "facade-3/", "facade-4/")) for k in changed)
    assert "facade-2/base.json" not in changed and "facade-2/net.json" in changed
    assert doc["status"] == "ok"


BAD_PROJECT = """
[project]
report = true

[defaults.init]
surface = "revolution"
profile = "gehry.csv"
rows = 7
cols = 5
span = 60
units = "m"

[patches.left]

[patches.broken.init]
profile = "broken.csv"

[patches.stiff.optimize]
mode = "isometric"
handles = "push.json"
max-iter = 1

[patches.right]

[molds.all]
patches = ["left", "right"]
"""


def test_a_patch_with_a_bad_input_fails_alone(tmp_path):
    shutil.copy(SAMPLES / "profiles" / "gehry.csv", tmp_path / "gehry.csv")
    (tmp_path / "broken.csv").write_text("r,h\n2.0,0.0\n2.1,oops\n")
    (tmp_path / "push.json").write_text(json.dumps(
        {"handles": [{"index": [0, 0], "offset": [0, 0, 0]},
                     {"index": [6, 4], "offset": [0.3, 0.0, 0.0]}]}))
    (tmp_path / "p.toml").write_text(BAD_PROJECT)
    with inside(tmp_path):
        result = batch("p.toml", "-o", "out", "--workers", "2", expect=1)
    doc = json.loads((tmp_path / "out" / "batch.json").read_text())
    broken = doc["patches"]["broken"]
    assert broken["status"] == "failed"
    assert broken["message"].startswith("broken/init: ") and "broken.csv" in broken["message"]
    assert "\n" not in broken["message"]
    assert doc["tasks"]["broken/report"]["status"] == "blocked"
    assert doc["patches"]["stiff"]["status"] == "not_converged"
    for name in ("left", "right"):
        assert doc["patches"][name]["status"] == "ok"
        assert (tmp_path / "out" / name / "report-index.html").is_file()
    assert doc["shared"]["status"] == "ok"
    assert doc["status"] == "failed" and doc["exit_code"] == 1
    assert "broken failed: broken/init: " in result.stderr
    assert "Error: out/batch.json: 1 of 4 patches failed (broken)" in result.stderr
    page = (tmp_path / "out" / "index.html").read_text()
    assert 'href="left/report-index.html"' in page and 'href="right/report-index.html"' in page
    assert 'href="broken/' not in page and 'href="shared/mold-all-report-index.html"' in page


@pytest.mark.parametrize("text, message", [
    ("[patches.a\n", "not valid TOML"),
    ("[patches]\n", "patches: no patch"),
    ("[defaults.init]\nrows = 3\n[patches.a.optimize]\nfoo = 1\n",
     "patches.a.optimize.foo: dgpc optimize has no option --foo"),
    ("[patches.a.init]\noutput = 'x'\n", "patches.a.init.output: not in a project file"),
    ("[patches.a.init]\nrows = [1, 2]\n", "patches.a.init.rows: takes one value"),
    ("[patches.a.init]\n[molds.m]\npatches = ['b']\n", "molds.m.patches: no patch 'b'"),
    ("[patches.a.init]\n[nest]\nsheet = '1x1'\n", "nest: no patch unfolds its strips"),
    ("[patches.shared.init]\n", "patches.shared: 'shared' is not a name"),
])
def test_a_bad_project_file_is_one_line_exit_1(tmp_path, text, message):
    (tmp_path / "p.toml").write_text(text)
    result = batch(tmp_path / "p.toml", "-o", tmp_path / "out", expect=1)
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert result.stderr.startswith(f"Error: {tmp_path / 'p.toml'}: ")
    assert message in result.stderr
    assert not (tmp_path / "out").exists()


def test_usage_errors_exit_2(tmp_path):
    (tmp_path / "p.toml").write_text("[patches.a.init]\n")
    assert batch(tmp_path / "missing.toml", "-o", tmp_path / "o", expect=2).exit_code == 2
    result = batch(tmp_path / "p.toml", "-o", tmp_path / "o", "--workers", "2", "--scheduler",
                   "tcp://127.0.0.1:1", expect=2)
    assert "--workers" in result.stderr


def test_exit_code_of_the_batch():
    assert exit_code({"a": {"exit_code": 0}, "b": {"exit_code": 0}}) == 0
    assert exit_code({"a": {"exit_code": 0}, "b": {"exit_code": 3}}) == 3
    assert exit_code({"a": {"exit_code": 3}, "b": {"exit_code": 1}}) == 1
    assert exit_code({"a": {"exit_code": 0}, "b": {"exit_code": None}}) == 1


def test_the_cli_imports_no_dask():
    code = ("import sys, dgpc_cli.cli.main; "
            "print(sorted(m for m in ('dask', 'distributed') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                         text=True).stdout
    assert out.strip() == "[]"


def test_flat_tags():
    assert flat_tags(["out/a/flat", "out/b/flat"]) == ["a", "b"]
    assert flat_tags(["out/a-flat", "out/b-flat.json"]) == ["a-flat", "b-flat"]
    assert flat_tags(["out/flat", "out/flat"]) == ["F1", "F2"]


def test_congruent_parts_of_several_flats_are_one_class(tmp_path):
    def flat(profile):
        stem = tmp_path / profile
        dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", 7, "--cols", 5,
             "--span", 120, "-o", stem)
        dgpc("planarize-strips", stem, "-o", f"{stem}-strips")
        # parts some 5 units long (mm: the built-in profiles' radius 5): 1e-3 of that
        dgpc("unfold", f"{stem}-strips", "--congruence-tol", "0.005", "-o", f"{stem}-flat")
        return read_flat(f"{stem}-flat")

    cat, cyl = flat("catenoid"), flat("cylinder")
    assert [c["quantity"] for c in cat.classes] == [4]
    both = combine_flats([("east", cat), ("west", cat), ("north", cyl)])
    assert [p["id"] for p in both.parts][:5] == [
        "east:S-v00", "east:S-v01", "east:S-v02", "east:S-v03", "west:S-v00"]
    assert [(c["id"], c["quantity"], c["per_tag"]) for c in both.classes] == [
        ("C01", 8, {"east": 4, "west": 4}), ("C02", 4, {"north": 4})]
    assert both.classes[0]["representative"] == "east:S-v00"
    assert all(p["alignment"]["relative_error"] <= 1e-3 for p in both.parts)
    assert {p["class"] for p in both.parts if p["id"].startswith("north:")} == {"C02"}
