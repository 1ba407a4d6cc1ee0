"""An artifact is several files, and a reader sees the old set or the new set, never a mix
(SPEC §3; issue: hardening, item 7): a kill at each rename of a multi-file write, a second
concurrent writer of one stem, leftovers after a kill."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from cli_helpers import dgpc

#: Runs ``dgpc ARGS`` in a child that kills itself (SIGKILL) just before its K-th
#: ``os.replace`` (K = 0: never; it prints how many renames it made).
CHILD = textwrap.dedent("""
    import os, signal, sys
    from dgpc_cli.cli.main import cli
    kill_at, calls, real = int(sys.argv[1]), [0], os.replace
    def replace(src, dst, *args, **kwargs):
        calls[0] += 1
        if calls[0] == kill_at:
            os.kill(os.getpid(), signal.SIGKILL)
        return real(src, dst, *args, **kwargs)
    os.replace = replace
    try:
        cli.main(args=sys.argv[2:], prog_name="dgpc")
    except SystemExit as e:
        print(calls[0], file=sys.stderr)
        raise
""")


def _child(kill_at: int, *args, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", CHILD, str(kill_at), *map(str, args)],
                          cwd=cwd, capture_output=True, text=True, timeout=300)


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def _visible(files: dict[str, bytes], stem: str) -> dict[str, bytes]:
    return {k: v for k, v in files.items() if k.startswith(stem + ".")}


@pytest.fixture(scope="module")
def sets(tmp_path_factory):
    """The old output (json, obj, 3dm of a revolution optimize) and the new one (json, obj of
    the same with another tolerance) of the stem ``out``, each written on its own."""
    d = tmp_path_factory.mktemp("whole")
    dgpc("init", "--surface", "revolution", "--profile", "sphere-zone", "--rows", 9,
         "--cols", 7, "-o", d / "net")
    old_args = ("optimize", "net", "--mode", "revolution", "--format", "3dm", "-o", "out")
    new_args = ("optimize", "net", "--mode", "revolution", "--tol", "1e-7", "-o", "out",
                "--force")
    (d / "old").mkdir()
    (d / "new").mkdir()
    for sub in ("old", "new"):
        for name in ("net.json", "net.obj"):
            (d / sub / name).write_bytes((d / name).read_bytes())
    assert _child(0, *old_args, cwd=d / "old").returncode == 0
    old = _visible(_files(d / "old"), "out")
    run = _child(0, *new_args, cwd=d / "new")
    assert run.returncode == 0, run.stderr
    new = _visible(_files(d / "new"), "out")
    assert set(old) == {"out.json", "out.obj", "out.3dm"} and set(new) == {"out.json",
                                                                           "out.obj"}
    assert old["out.json"] != new["out.json"]
    renames = int(run.stderr.strip().splitlines()[-1])
    return d, old_args, new_args, old, new, renames


def test_a_kill_at_each_rename_leaves_the_old_or_the_new_artifact_whole(sets, tmp_path):
    d, old_args, new_args, _, new, renames = sets
    assert renames == 3  # the journal (the commit), then out.json and out.obj
    seen = []
    for kill_at in range(1, renames + 1):
        work = tmp_path / f"kill{kill_at}"
        work.mkdir()
        for name in ("net.json", "net.obj"):
            (work / name).write_bytes((d / name).read_bytes())
        assert _child(0, *old_args, cwd=work).returncode == 0
        old = _visible(_files(work), "out")  # (a 3dm holds its write time)
        killed = _child(kill_at, *new_args, cwd=work)
        assert killed.returncode == -9, killed.stderr
        # A reader (inspect) finds a complete artifact: the old one before the commit, the
        # new one after it, never a mix.
        read = _child(0, "inspect", "out", cwd=work)
        assert read.returncode == 0, read.stderr
        now = _visible(_files(work), "out")
        assert now in (old, new), (kill_at, sorted(now))
        seen.append("old" if now == old else "new")
        # The next run of the same command succeeds and leaves no hidden file behind.
        again = _child(0, *new_args, cwd=work)
        assert again.returncode == 0, again.stderr
        assert _visible(_files(work), "out") == new
        hidden = sorted(p.name for p in work.iterdir() if p.name.startswith("."))
        assert hidden == [], (kill_at, hidden)
    assert seen == ["old"] + ["new"] * (renames - 1)


def test_a_kill_before_the_commit_leaves_temporary_files_that_the_next_writer_removes(
        sets, tmp_path):
    d, old_args, new_args, _, new, _ = sets
    for name in ("net.json", "net.obj"):
        (tmp_path / name).write_bytes((d / name).read_bytes())
    assert _child(0, *old_args, cwd=tmp_path).returncode == 0
    old = _visible(_files(tmp_path), "out")
    assert _child(1, *new_args, cwd=tmp_path).returncode == -9
    hidden = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("."))
    assert any(h.endswith(".tmp") for h in hidden), hidden  # the kill left them
    assert _visible(_files(tmp_path), "out") == old
    assert _child(0, *new_args, cwd=tmp_path).returncode == 0
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_a_second_writer_of_one_stem_is_refused_and_changes_nothing(sets, tmp_path):
    d, old_args, new_args, _, _, _ = sets
    for name in ("net.json", "net.obj"):
        (tmp_path / name).write_bytes((d / name).read_bytes())
    assert _child(0, *old_args, cwd=tmp_path).returncode == 0
    before = _files(tmp_path)
    old = _visible(before, "out")
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys; from dgpc_cli.io.lock import output_lock\n"
         "with output_lock('out'):\n    print('held', flush=True); sys.stdin.read()"],
        cwd=tmp_path, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        second = _child(0, *new_args, cwd=tmp_path)
    finally:
        holder.communicate("", timeout=60)
    assert second.returncode == 1
    errors = [line for line in second.stderr.splitlines() if line.startswith("Error")]
    assert errors == ["Error: out: another dgpc process is writing this output (it holds "
                      ".out.lock); wait for it to end or choose another -o"], second.stderr
    assert _files(tmp_path) == before
    assert holder.returncode == 0
    assert _visible(_files(tmp_path), "out") == old
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_a_reader_between_a_commit_and_its_obj_reads_the_new_set(sets, tmp_path, monkeypatch):
    """A write that commits after a reader read the JSON and before it read the OBJ: the
    reader does not report a false mismatch, it reads the artifact again (the new set)."""
    import dgpc_cli.io.net as net_io

    d, _, _, _, new, _ = sets
    old_net = d / "net.json"                         # the "old" artifact: the input net
    for name in ("out.json", "out.obj"):
        (tmp_path / name).write_bytes(old_net.with_suffix(name[3:]).read_bytes())
    doc = (tmp_path / "out.json").read_text().replace('"net.obj"', '"out.obj"')
    (tmp_path / "out.json").write_text(doc)
    real, calls = net_io.read_listed, []

    def read_listed(path, *args):
        if not calls:                                # the concurrent commit lands here
            for name, data in new.items():
                (tmp_path / name).write_bytes(data)
        calls.append(path)
        return real(path, *args)

    monkeypatch.setattr(net_io, "read_listed", read_listed)
    net = net_io.read_net(tmp_path / "out")
    assert len(calls) == 2                           # read twice: old JSON, then new
    assert net.status["state"] == "converged" and net.parameters["tol"] == 1e-7
