"""Shared fixtures: the small pipelines (pipelines/*.mk through make), each run once per session
for every test that reads their output (the golden files, the DXF checks)."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import ROOT, run  # noqa: E402


@pytest.fixture(scope="session")
def pipeline_run(tmp_path_factory):
    """``pipeline_run(name)``: the output folder of the small version of pipeline ``name``,
    made on first use."""
    done: dict[str, Path] = {}

    def get(name: str) -> Path:
        if name not in done:
            done[name] = run(name, tmp_path_factory.mktemp(name))
        return done[name]

    return get


@pytest.fixture(scope="session")
def demo_run(tmp_path_factory):
    """The output folder of ``make demo`` (the timber-cladding pipeline at its default size,
    as the README's quick start runs it), made once per session for every test that reads it
    (the README's figures, the end marks of its cut sheets); what make printed is in
    ``make-demo.log`` beside it."""
    import os
    import subprocess

    out = tmp_path_factory.mktemp("demo")
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    run = subprocess.run(["make", "-s", "-o", ".venv/.installed", "demo", f"DEMO={out}",
                          f"BIN={Path(sys.executable).parent}"],
                         cwd=ROOT, check=True, env=env, capture_output=True, text=True)
    (out / "make-demo.log").write_text(run.stdout)
    return out / "timber-cladding"
