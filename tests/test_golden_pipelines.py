"""Golden-file tests: small versions of every pipeline (pipelines/*.mk, run through make)
against tests/golden/NAME.json. Refresh with `make golden` only after a reviewed change."""

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import GOLDEN, SIZES, collect, compare, planned  # noqa: E402


@pytest.mark.parametrize("name", list(SIZES))
def test_pipeline_matches_golden(pipeline_run, name):
    """Every figure within its tolerance (tests/golden/tolerances.py: from the stopping rule of
    the stage that made it), counts, DXF entity counts and the artifacts' JSON skeletons
    exact."""
    want = json.loads((GOLDEN / f"{name}.json").read_text())
    got = collect(name, pipeline_run(name))
    assert got["size"] == want["size"]
    assert got["metrics"].keys() == want["metrics"].keys()
    assert got["nets"].keys() == want["nets"].keys()
    for figure, (deviation, tolerance) in compare(name, got, want).items():
        assert deviation <= tolerance, (figure, deviation, tolerance)
    assert got["counts"] == want["counts"]
    assert got["dxf"] == want["dxf"]
    assert got["json"] == want["json"]  # paths, keys, parameters, states (numbers above)


def test_make_rebuilds_only_what_changed(pipeline_run, tmp_path):
    """Targets are the artifact files: a finished pipeline has nothing to do, and a newer
    intermediate artifact reruns only the stages downstream of it (on a copy of the shared
    run, times kept)."""
    import os
    import shutil

    d = shutil.copytree(pipeline_run("timber-cladding"), tmp_path / "timber-cladding")
    assert planned("timber-cladding", tmp_path) == []
    later = max(p.stat().st_mtime for p in d.iterdir()) + 10   # newer than every output
    os.utime(d / "strips.json", (later, later))
    assert [w[0] for w in planned("timber-cladding", tmp_path)] == ["unfold", "nest", "report"]
