"""Golden-file tests: small versions of every pipeline (pipelines/*.mk, run through make)
against tests/golden/NAME.json. Refresh with `make golden` only after a reviewed change."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import (  # noqa: E402
    BOUNDS,
    FLOOR,
    GOLDEN,
    SIZES,
    collect,
    coord_tol,
    make_args,
    rel_tol,
)


@pytest.mark.parametrize("name", list(SIZES))
def test_pipeline_matches_golden(pipeline_run, name):
    want = json.loads((GOLDEN / f"{name}.json").read_text())
    got = collect(name, pipeline_run(name))
    assert got["size"] == want["size"]
    assert got["metrics"].keys() == want["metrics"].keys()
    for key, w in want["metrics"].items():
        g = got["metrics"][key]
        if key in BOUNDS.get(name, {}):
            assert g <= BOUNDS[name][key], (key, g, BOUNDS[name][key])
            continue
        assert abs(g - w) <= rel_tol(name, key) * max(abs(g), abs(w)) \
            or max(abs(g), abs(w)) <= FLOOR, (key, g, w)
    assert got["counts"] == want["counts"]
    assert got["nets"].keys() == want["nets"].keys()
    for stem, w in want["nets"].items():
        w, g = np.array(w), np.array(got["nets"][stem])
        diagonal = np.linalg.norm(np.ptp(w.reshape(-1, 3), axis=0))
        assert g.shape == w.shape and np.abs(g - w).max() <= coord_tol(name) * diagonal, stem
    assert got["dxf"] == want["dxf"]
    assert got["json"] == want["json"]  # paths, keys, parameters, states (numbers above)


def _planned(name, out):
    """The dgpc subcommands `make -n pipeline-NAME` would run now (what is out of date)."""
    import os
    import subprocess

    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    text = subprocess.run(["make", "-n", "-o", ".venv/.installed", f"pipeline-{name}",
                           *make_args(name, out)],
                          cwd=Path(__file__).resolve().parents[1], check=True, env=env,
                          capture_output=True, text=True).stdout
    return [line.split()[2] for line in text.splitlines() if "/dgpc -q " in line]


def test_make_rebuilds_only_what_changed(pipeline_run, tmp_path):
    """Targets are the artifact files: a finished pipeline has nothing to do, and a newer
    intermediate artifact reruns only the stages downstream of it (on a copy of the shared
    run, times kept)."""
    import os
    import shutil

    d = shutil.copytree(pipeline_run("timber-cladding"), tmp_path / "timber-cladding")
    assert _planned("timber-cladding", tmp_path) == []
    later = max(p.stat().st_mtime for p in d.iterdir()) + 10   # newer than every output
    os.utime(d / "strips.json", (later, later))
    assert _planned("timber-cladding", tmp_path) == ["unfold", "nest", "report"]
