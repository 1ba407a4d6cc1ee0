"""Nothing is written when stdout fails (issue "nothing destroyed, nothing corrupt").

A command prints the paths it writes on stdout at the commit of its files, after the journal is
visible and before the renames (``io.atomic``): when stdout cannot take them (a full device,
a closed pipe), the commit is withdrawn. So ``init``, ``report``, ``nest`` and ``batch`` with
stdout on ``/dev/full`` exit 1 with one line and leave the folder as it was (``batch``: its
summary; the artifacts of its tasks are its cache, reused by the next run). A command started
with stdout closed does nothing at all.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import dgpc
from refusals import refused, tree

from dgpc_cli.io.patch_set import member_files
from dgpc_cli.stages.patch_set_run import write_patch_set

DGPC = str(Path(sys.executable).parent / "dgpc")
FULL = Path("/dev/full")
PROFILE = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"
WALL = ("--surface", "revolution", "--profile", PROFILE, "--rows", 9, "--cols", 5, "--span", 40,
        "--units", "m")

pytestmark = pytest.mark.skipif(not FULL.exists(), reason="needs /dev/full")


def to_full(*args, cwd: Path) -> subprocess.CompletedProcess:
    """``dgpc ARGS`` run from ``cwd`` with stdout on /dev/full."""
    with open(FULL, "w") as full:
        return subprocess.run([DGPC, *map(str, args)], cwd=cwd, stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=600)


@pytest.fixture(scope="module")
def chain(tmp_path_factory) -> Path:
    """A wall's net ``n``, strips ``s`` and flat ``f``."""
    d = tmp_path_factory.mktemp("chain")
    dgpc("init", *WALL, "-o", d / "n")
    dgpc("planarize-strips", d / "n", "-o", d / "s")
    dgpc("unfold", d / "s", "-o", d / "f")
    return d


@pytest.mark.parametrize("args", [
    ("init", *WALL, "-o", "new"),
    ("init", *WALL, "-o", "n", "--force"),                 # over an existing net: kept
    ("report", "n", "-o", "r"),
    ("nest", "f", "--sheet", "7000x3000", "--no-preview", "-o", "sheets"),
    ("unfold", "s", "-o", "f", "--force"),
], ids=["init", "init-force", "report", "nest", "unfold-force"])
def test_nothing_is_written_when_stdout_fails(chain, args):
    before = tree(chain)
    r = to_full(*args, cwd=chain)
    refused(r.stderr, r.returncode, 1, "stdout", "No space left on device", "nothing was written")
    assert tree(chain) == before


def test_a_patch_set_command_writes_nothing_when_stdout_fails(tmp_path):
    for name in ("a", "b"):
        dgpc("init", *WALL, "-o", tmp_path / name)
    write_patch_set(tmp_path / "set", "init", [
        {"name": f"p{k}", "kind": "net", "json": tmp_path / f"{name}.json", "exit_code": 0,
         "files": member_files(tmp_path / f"{name}.json")}
        for k, name in enumerate("ab", start=1)], force=False)
    before = tree(tmp_path)
    r = to_full("-q", "planarize-strips", "set", "-o", "out", cwd=tmp_path)
    refused(r.stderr, r.returncode, 1, "stdout", "nothing was written")
    assert tree(tmp_path) == before


def test_a_batch_writes_no_summary_when_stdout_fails(tmp_path):
    (tmp_path / "p.toml").write_text(
        '[defaults.init]\nsurface = "revolution"\nprofile = "wall.csv"\nrows = 5\ncols = 5\n'
        'units = "m"\n[patches.a]\n')
    (tmp_path / "wall.csv").write_bytes(PROFILE.read_bytes())
    r = to_full("-q", "batch", "p.toml", "-o", "out", "--workers", 1, cwd=tmp_path)
    refused(r.stderr, r.returncode, 1, "stdout", "nothing was written")
    assert not (tmp_path / "out" / "batch.json").exists()
    assert not (tmp_path / "out" / "index.html").exists()


def test_a_closed_stdout_is_refused_before_anything(chain):
    before = tree(chain)
    r = subprocess.run([DGPC, "init", *map(str, WALL), "-o", "closed"], cwd=chain,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       timeout=600, preexec_fn=lambda: os.close(1))
    refused(r.stderr, r.returncode, 1, "stdout is closed", "nothing done")
    assert tree(chain) == before


def test_stdout_that_works_gets_the_paths(chain, tmp_path):
    r = subprocess.run([DGPC, "init", *map(str, WALL), "-o", "ok"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0 and r.stdout.split() == ["ok.json"], r.stderr
    assert (tmp_path / "ok.json").is_file()
