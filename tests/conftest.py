"""Shared fixtures: the small pipelines (pipelines/*.mk through make), each run once per session
for every test that reads their output (the golden files, the DXF checks)."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import run  # noqa: E402


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
