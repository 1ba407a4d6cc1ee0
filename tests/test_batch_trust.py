"""``dgpc batch`` cannot lose a file or hang: outputs tracked by the exact names the artifacts
list (never a pattern), names checked before anything runs, every network step bounded in
time with one clear line and nothing written before the cluster answers. Servers are tiny
loopback ones started here; each run that could hang runs in a thread given a deadline.
"""

from __future__ import annotations

import http.server
import json
import socket
import threading

import pytest
from click.testing import CliRunner

from dgpc_cli.batch.cluster import local_cluster_options
from dgpc_cli.cli.main import cli

#: Seconds a run that must not hang is given before the test fails.
DEADLINE = 240

SMALL = """
[project]
report = false

[defaults.init]
surface = "revolution"
profile = "catenoid"
rows = 5
cols = 4
span = 90
"""


def run_batch(*args, deadline: float = DEADLINE):
    """``dgpc batch ARGS`` in a thread; the result, or a failure when it outlasts
    ``deadline`` seconds (the thread is left behind, as daemon)."""
    box = {}

    def target():
        box["result"] = CliRunner().invoke(cli, ["batch", *map(str, args)])

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(deadline)
    if thread.is_alive():
        pytest.fail(f"dgpc batch still running after {deadline} s")
    return box["result"]


def one_line(result, code: int, *needles):
    assert result.exit_code == code, (result.exit_code, result.stderr, result.exception)
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in result.stderr, result.stderr


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(**local_cluster_options(1)) as c:
        yield c


# -- exact names -----------------------------------------------------------------------------

def test_outputs_are_the_files_each_artifact_lists(cluster, tmp_path):
    """Molds ``m`` and ``m.x`` (the pattern ``mold-m.*`` matches the other's files) and a
    user's ``a/base.notes.txt`` (matches ``base.*``): every rerun keeps every file, and
    recomputes nothing."""
    (tmp_path / "p.toml").write_text(SMALL + """
[patches.a]
[patches.b]
[molds.m]
patches = ["a"]
[molds."m.x"]
patches = ["b"]
""")
    out = tmp_path / "out"
    first = run_batch(tmp_path / "p.toml", "-o", out, "--scheduler", cluster.scheduler_address)
    assert first.exit_code == 0, first.stderr
    notes = out / "a" / "base.notes.txt"
    notes.write_text("site visit: check the east edge")
    doc = json.loads((out / "batch.json").read_text())
    assert doc["patches"]["a"]["outputs"]["base"] == "a/base.json"
    assert doc["shared"]["outputs"]["mold-m.x"] == "shared/mold-m.x.json"
    m, mx = (set(doc["tasks"][f"shared/mold-{k}"]["outputs"]) for k in ("m", "m.x"))
    assert {"shared/mold-m.json", "shared/mold-m.obj", "shared/mold-m.panels.csv"} <= m
    assert {"shared/mold-m.x.json", "shared/mold-m.x.obj"} <= mx
    assert not any(name.startswith("shared/mold-m.x.") for name in m)
    assert {name.replace("mold-m.", "mold-m.x.") for name in m} == mx
    assert sorted(doc["tasks"]["a/init"]["outputs"]) == ["a/base.json", "a/base.obj"]
    assert doc["shared"]["metrics"]["mold-m.x"]["pieces"] >= 1
    files = {p.relative_to(out).as_posix(): p.read_bytes() for p in out.rglob("*")
             if p.is_file() and p.name not in ("batch.json", "index.html")}
    for _ in range(2):
        again = run_batch(tmp_path / "p.toml", "-o", out, "--scheduler",
                          cluster.scheduler_address, "-q")
        assert again.exit_code == 0, again.stderr
        rerun = json.loads((out / "batch.json").read_text())
        assert rerun["this_run"]["executed"] == []
        assert {p.relative_to(out).as_posix(): p.read_bytes() for p in out.rglob("*")
                if p.is_file() and p.name not in ("batch.json", "index.html")} == files
        for record in rerun["tasks"].values():
            for name in record["outputs"]:
                assert (out / name).is_file(), name
    assert notes.read_text() == "site visit: check the east edge"


# -- names -----------------------------------------------------------------------------------

@pytest.mark.parametrize("tables, message", [
    ("[patches." + "a" * 300 + "]\n", "at most 64"),
    ('[patches."a\\n"]\n', "is not a name"),
    ('[patches."batch.json"]\n', "reserved"),
    ('[patches."Index.HTML"]\n', "reserved"),
    ("[patches.nul]\n", "reserved"),
    ('[patches."net.json"]\n', "ends like a file name"),
    ("[patches.A]\n[patches.a]\n", "differing only in case"),
    ('[patches.a]\n[molds.x]\npatches = ["a"]\n[molds."x.json"]\npatches = ["a"]\n',
     "ends like a file name"),
    ('[patches.a]\n[molds.x]\npatches = ["a"]\n[molds.x-report]\npatches = ["a"]\n',
     "collide with those of molds.x's report"),
])
def test_names_are_checked_before_anything_runs(tmp_path, tables, message):
    (tmp_path / "p.toml").write_text(SMALL.replace("report = false", "report = true") + tables)
    result = run_batch(tmp_path / "p.toml", "-o", tmp_path / "out", "--workers", 1)
    one_line(result, 1, "p.toml", message)
    assert not (tmp_path / "out").exists()


def test_a_project_file_that_is_not_utf8_is_one_line(tmp_path):
    (tmp_path / "p.toml").write_bytes(SMALL.encode() + b"[patches.caf\xe9]\n")
    one_line(run_batch(tmp_path / "p.toml", "-o", tmp_path / "out"), 1,
             "not UTF-8 text: byte 0xe9 at line 11")
    assert not (tmp_path / "out").exists()


# -- the cluster -----------------------------------------------------------------------------

@pytest.fixture()
def project(tmp_path):
    (tmp_path / "p.toml").write_text(SMALL + "[patches.a]\n")
    return tmp_path / "p.toml"


@pytest.fixture()
def silent_port():
    """A loopback port that accepts connections and never says a word."""
    server = socket.create_server(("127.0.0.1", 0))
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except TimeoutError:
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield server.getsockname()[1]
    stop.set()
    thread.join()
    for conn in held:
        conn.close()
    server.close()


@pytest.fixture()
def http_port():
    """A loopback HTTP server (it answers a Dask handshake with ``HTTP/1.0 400``)."""
    class Quiet(http.server.BaseHTTPRequestHandler):
        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


def test_a_silent_port_is_one_line_within_the_timeout(project, silent_port):
    out = project.parent / "out"
    result = run_batch(project, "-o", out, "--scheduler", f"tcp://127.0.0.1:{silent_port}",
                       "--timeout", 2)
    one_line(result, 1, "--scheduler", "no answer from a Dask scheduler within 2 s")
    assert not out.exists()


def test_an_http_server_is_not_a_scheduler(project, http_port):
    out = project.parent / "out"
    result = run_batch(project, "-o", out, "--scheduler", f"127.0.0.1:{http_port}",
                       "--timeout", 5)
    one_line(result, 1, "--scheduler", "not a Dask scheduler")
    assert "MemoryError" not in result.stderr or "could not be read" in result.stderr
    assert not out.exists()


def test_a_scheduler_without_workers_is_one_line(project):
    from distributed import LocalCluster

    out = project.parent / "out"
    with LocalCluster(**local_cluster_options(0)) as empty:
        result = run_batch(project, "-o", out, "--scheduler", empty.scheduler_address,
                           "--timeout", 2)
    one_line(result, 1, "the scheduler has no workers (none joined within 2 s)")
    assert not out.exists()


@pytest.mark.parametrize("address, message", [
    ("ucx://127.0.0.1:8786", "the scheme ucx:// is not supported"),
    ("inproc://127.0.0.1/1/1", "the scheme inproc:// is not supported"),
    ("127.0.0.1", "not HOST:PORT"),
    ("tcp://127.0.0.1:1", "cannot connect"),
])
def test_unusable_addresses_are_one_line_and_write_nothing(project, address, message):
    out = project.parent / "out"
    result = run_batch(project, "-o", out, "--scheduler", address, "--timeout", 1)
    one_line(result, 1, message)
    assert not out.exists()


def test_workers_beyond_the_cores_are_capped_in_one_line(project):
    from dgpc_cli.stages.batch import machine_cores

    out = project.parent / "out"
    result = run_batch(project, "-o", out, "--workers", 100000, "-q")
    assert result.exit_code == 0, result.stderr
    assert result.stderr.count("\n") == 1 and "--workers 100000" in result.stderr
    assert "cores" in result.stderr
    doc = json.loads((out / "batch.json").read_text())
    assert doc["this_run"]["cluster"]["workers"] == machine_cores()
