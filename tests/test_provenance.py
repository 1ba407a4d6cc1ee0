"""Provenance that does not depend on where dgpc runs (issue 16, item 8): every path an
artifact stores is POSIX and relative to the artifact's own folder, so the same pipeline run
from two working directories into folders at different depths writes the same bytes, JSON
included."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

DGPC = str(Path(sys.executable).parent / "dgpc")

PROFILE = "r,h\n1.0,0.0\n1.2,0.5\n1.5,1.0\n1.9,1.5\n"


def chain(cwd: Path, out: str, profile: str):
    """init (a CSV profile, its reference mesh written beside the net), optimize --mode fit on
    the recorded reference, planarize-strips, unfold, nest: every path typed relative to ``cwd``
    and leading into the folder ``out``."""
    steps = [
        ["init", "--surface", "revolution", "--profile", profile, "--rows", "7", "--cols", "5",
         "--reference-out", f"{out}/ref.obj", "-o", f"{out}/net"],
        ["optimize", f"{out}/net", "--mode", "fit", "--max-iter", "3", "-o", f"{out}/fit"],
        # a fit of 3 iterations may stop short of its tolerance (exit 3): the chain goes on
        # with it on purpose, and says so at every stage
        ["planarize-strips", f"{out}/fit", "--accept-status", "-o", f"{out}/strips"],
        ["unfold", f"{out}/strips", "--accept-status", "-o", f"{out}/flat"],
        ["nest", f"{out}/flat.json", "--sheet", "2500x1250", "--scale", "100",
         "--rotations", "0", "--accept-status", "-o", f"{out}/sheets"],
    ]
    for args in steps:
        result = subprocess.run([DGPC, "-q", *args], cwd=cwd, capture_output=True, text=True,
                                check=False)
        assert result.returncode in (0, 3), (args, result.stderr)


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    """The chain run at depth 1 from its parent folder, and at depth 3 from a sibling folder
    (``../deep/er/out``); each output folder has its profile in the folder above it."""
    root = tmp_path_factory.mktemp("provenance")
    near = root / "near"
    (near / "out").mkdir(parents=True)
    (near / "profile.csv").write_text(PROFILE)
    chain(near, "out", "profile.csv")
    far = root / "far"
    (far / "deep" / "er" / "out").mkdir(parents=True)
    (far / "elsewhere").mkdir()
    (far / "deep" / "er" / "profile.csv").write_text(PROFILE)
    chain(far / "elsewhere", "../deep/er/out", "../deep/er/profile.csv")
    return near / "out", far / "deep" / "er" / "out"


def test_same_bytes_from_any_working_directory_and_depth(two_runs):
    a, b = two_runs
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    assert {"net.json", "fit.json", "strips.json", "flat.json", "sheets.json",
            "sheets.sheet01.dxf"} <= set(names)
    differ = [n for n in names if (a / n).read_bytes() != (b / n).read_bytes()]
    assert differ == []


def test_recorded_paths_are_relative_to_the_artifact(two_runs):
    a, _ = two_runs
    net = json.loads((a / "net.json").read_text())
    assert net["inputs"]["profile"]["path"] == "../profile.csv"
    assert net["parameters"]["profile"] == "../profile.csv"
    assert net["data"]["surface"]["profile"] == "../profile.csv"
    assert net["data"]["reference"]["path"] == "ref.obj"
    assert net["parameters"]["reference_out"] == "ref.obj"
    fit = json.loads((a / "fit.json").read_text())
    assert fit["inputs"]["net"]["path"] == "net.json"
    assert fit["inputs"]["reference"]["path"] == "ref.obj"
    sheets = json.loads((a / "sheets.json").read_text())
    assert sheets["inputs"]["flat"]["path"] == "flat.json"
    assert all("/" not in r["path"] for r in sheets["data"]["files"].values())


def test_recorded_paths_are_read_against_the_artifact_folder(two_runs, tmp_path):
    """A later command run from anywhere finds what the artifact records (the reference of a
    fit, the net of a report) by the artifact's folder, not by the working directory."""
    _, b = two_runs
    result = subprocess.run([DGPC, "-q", "optimize", str(b / "net"), "--mode", "fit",
                             "--max-iter", "1", "-o", str(tmp_path / "again")],
                            cwd=tmp_path, capture_output=True, text=True, check=False)
    assert result.returncode in (0, 3), result.stderr
    again = json.loads((tmp_path / "again.json").read_text())
    ref = Path(again["inputs"]["reference"]["path"])
    assert not ref.is_absolute() and (tmp_path / ref).resolve() == (b / "ref.obj").resolve()
