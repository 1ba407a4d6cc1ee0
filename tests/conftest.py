"""Shared fixtures and how the suite runs in parallel.

``make test`` runs pytest-xdist (``-n auto --dist loadgroup``): every test goes to whichever
worker process is free, except the tests of a module that share a module- or class-scoped
fixture, which go together to one worker, so the fixture is built once (tests/parallel.py;
nothing to mark by hand). Tests must not depend on their order or on the worker they run on.

Something expensive that tests of *several* modules read (a pipeline's output, a fitted net)
is built once per run for all workers with :func:`build_once`: the first worker to ask builds
it into a folder of the run's temporary root, under a file lock, and the others wait for it
and read the same folder. The pattern, for a new fixture::

    @pytest.fixture(scope="session")
    def fitted_roof(tmp_path_factory):
        def build(d):                    # d: an empty folder; write everything into it
            dgpc("init", ..., "-o", d / "n0")
            dgpc("optimize", d / "n0", ..., "-o", d / "n1")
        return build_once(tmp_path_factory, "fitted-roof", build)   # the folder d, built

Readers must treat the folder as read-only (copy what they change into their own
``tmp_path``). Without xdist (``pytest`` alone) the same code builds once per session.
"""

import os
import shutil
import sys
from collections.abc import Callable
from pathlib import Path

import parallel
import pytest
from filelock import FileLock

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import ROOT, run  # noqa: E402


def _run_root(tmp_path_factory) -> Path:
    """The temporary folder of this test run that every xdist worker sees."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def build_once(tmp_path_factory, name: str, build: Callable[[Path], object]) -> Path:
    """The folder ``name`` of this run, made by ``build(folder)`` by the first worker that asks
    (under a file lock; the others wait and reuse it). A build that raised is retried by the
    next caller, from an empty folder."""
    root = _run_root(tmp_path_factory)
    d, done = root / f"shared-{name}", root / f"shared-{name}.done"
    with FileLock(root / f"shared-{name}.lock"):
        if not done.exists():
            shutil.rmtree(d, ignore_errors=True)
            d.mkdir()
            build(d)
            done.touch()
    return d


@pytest.fixture(scope="session")
def pipeline_run(tmp_path_factory):
    """``pipeline_run(name)``: the output folder of the small version of pipeline ``name``
    (pipelines/*.mk through make), made once per run for every worker."""
    return lambda name: build_once(tmp_path_factory, f"pipeline-{name}",
                                   lambda d: run(name, d)) / name


@pytest.fixture(scope="session")
def demo_run(tmp_path_factory):
    """The output folder of ``make demo`` (the timber-cladding pipeline at its default size,
    as the README's quick start runs it), made once per run for every worker that reads it
    (the README's figures, the end marks of its cut sheets); what make printed is in
    ``make-demo.log`` beside it."""
    import subprocess

    def build(d: Path) -> None:
        env = {**os.environ,
               "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
        made = subprocess.run(["make", "-s", "-o", ".venv/.installed", "demo", f"DEMO={d}",
                               f"BIN={Path(sys.executable).parent}"],
                              cwd=ROOT, check=True, env=env, capture_output=True, text=True)
        (d / "make-demo.log").write_text(made.stdout)

    return build_once(tmp_path_factory, "demo", build) / "timber-cladding"


def pytest_xdist_make_scheduler(config, log):
    """``--dist loadgroup``: tests sharing a module- or class-scoped fixture on one worker."""
    if config.getoption("dist") == "loadgroup":
        return parallel.SharedFixtureScheduling(config, log)
    return None


def pytest_configure_node(node):
    node.workerinput[parallel.GROUPS_KEY] = str(parallel.groups_file(node.config))


def pytest_collection_modifyitems(config, items):
    parallel.record(config, items)


def pytest_unconfigure(config):
    parallel.cleanup(config)
