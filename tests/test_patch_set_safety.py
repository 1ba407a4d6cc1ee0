"""A patch set is an artifact like any other (issue "nothing destroyed, nothing corrupt"):

* ``-o`` may not name an input set or any of its members, ``--force`` or not (one line, exit 1,
  nothing written);
* ``--force`` over an existing set removes only the files the set wrote itself (named
  ``STEM.*``, with the sha256 recorded for them), never a file it merely lists (a user's notes,
  the command's own input, another artifact);
* reading a set checks every member's sha256 and kind, as for inputs;
* an option wrong for every member writes nothing;
* the set and its members are one commit: a writer killed at any moment leaves, after a
  reader, the old set and members or the new ones, never a mix.

Two walls of revolution stand in for two patches (``wp1``, ``wp2``), made into the net set
``n``; ``s`` is its strips set (``s.p1``, ``s.p2``).
"""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
from pathlib import Path

import pytest
from cli_helpers import dgpc
from click.testing import CliRunner
from refusals import refused, tree

from dgpc_cli.cli.main import cli
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.patch_set import member_files, read_patch_set
from dgpc_cli.io.strips import read_strips
from dgpc_cli.stages.patch_set_run import write_patch_set

PROFILE = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"


def wall(path: Path, rows: int, span: float, profile: Path = PROFILE) -> Path:
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", rows, "--cols", 5,
         "--span", span, "--units", "m", "-o", path)
    return path


def make_set(folder: Path, name: str, members: dict[str, Path], extra_files=None) -> Path:
    """The set ``folder/name`` of the net artifacts ``members`` (name -> stem); ``extra_files``
    (name -> list of paths) are listed among a member's files besides its own."""
    extra_files = extra_files or {}
    write_patch_set(folder / name, "init", [
        {"name": k, "kind": "net", "json": artifact_paths(s)[0], "exit_code": 0,
         "files": [*member_files(artifact_paths(s)[0]), *extra_files.get(k, [])]}
        for k, s in members.items()], force=False)
    return folder / name


@pytest.fixture(scope="module")
def roof(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("roof")
    make_set(d, "n", {"p1": wall(d / "wp1", 9, 40), "p2": wall(d / "wp2", 7, 30)})
    dgpc("planarize-strips", d / "n", "-o", d / "s")
    return d


@pytest.fixture
def folder(roof, tmp_path) -> Path:
    """A copy of the roof's files to spoil."""
    for path in roof.iterdir():
        shutil.copy2(path, tmp_path / path.name)
    return tmp_path


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


@pytest.mark.parametrize("args, hit", [
    (("planarize-strips", "n", "-o", "wp1"), "wp1.json, a file of the input STEM n"),
    (("planarize-strips", "n", "-o", "wp1", "--force"), "wp1.json, a file of the input STEM n"),
    (("planarize-strips", "n", "-o", "n", "--force"), "is also an input (STEM n)"),
    (("unfold", "s", "-o", "s.p1", "--force"), "s.p1.json, a file of the input STEM s"),
    (("unfold", "s", "-o", "s", "--force"), "is also an input (STEM s)"),
])
def test_o_may_not_name_an_input_set_or_a_member(folder, args, hit, monkeypatch):
    before = tree(folder)
    monkeypatch.chdir(folder)
    r = run(*args)
    refused(r.stderr, r.exit_code, 1, hit, "write the output elsewhere")
    assert tree(folder) == before


def test_o_naming_an_existing_set_whose_member_is_the_input(folder):
    """``optimize t.p1 -o t --force``: writing ``t`` would remove the set's member ``t.p1``,
    which is the input: refused; a net of another name over the set is fine, and removes
    the set's own members only."""
    make_set(folder, "t", {"p1": wall(folder / "t.p1", 9, 40), "p2": wall(folder / "t.p2", 7, 30)})
    before = tree(folder)
    r = run("planarize-strips", folder / "t.p1", "-o", folder / "t", "--force")
    refused(r.stderr, r.exit_code, 1, "would remove t.p1.json, the input STEM",
            "a member of that patch set")
    assert tree(folder) == before
    r = run("planarize-strips", folder / "wp1", "-o", folder / "t", "--force")
    assert r.exit_code == 0, r.stderr
    assert not list(folder.glob("t.p*"))
    assert json.loads((folder / "t.json").read_text())["kind"] == "strips"


def test_force_removes_only_the_files_the_set_wrote(folder):
    """The set ``a`` lists, besides its members' own files, a user's notes, a file named like
    a member's but not recorded by it, a profile the rerun reads, another artifact and an
    edited member file: a rerun with ``--force`` removes the members' own files only."""
    (folder / "notes.txt").write_text("site visit 3 May\n")
    (folder / "a.p1.notes.txt").write_text("my notes\n")
    shutil.copy(PROFILE, folder / "a.p1.wall.csv")
    make_set(folder, "a", {"p1": wall(folder / "a.p1", 9, 40), "p2": wall(folder / "a.p2", 7, 30)},
             extra_files={"p1": [folder / "notes.txt", folder / "a.p1.notes.txt",
                                 folder / "a.p1.wall.csv", folder / "wp1.json",
                                 folder / "wp1.obj"]})
    with open(folder / "a.p2.obj", "a") as fh:              # edited since: not the set's any more
        fh.write("# moved a vertex by hand\n")
    kept = {name: (folder / name).read_bytes() for name in
            ("notes.txt", "a.p1.notes.txt", "a.p1.wall.csv", "wp1.json", "wp1.obj", "a.p2.obj")}
    r = run("init", "--surface", "revolution", "--profile", folder / "a.p1.wall.csv", "--rows", 9,
            "--cols", 5, "--units", "m", "-o", folder / "a", "--force")
    assert r.exit_code == 0, r.stderr
    assert {name: (folder / name).read_bytes() for name in kept} == kept
    for gone in ("a.p1.json", "a.p1.obj", "a.p2.json"):
        assert not (folder / gone).exists(), gone
    assert json.loads((folder / "a.json").read_text())["kind"] == "net"


def test_a_member_changed_or_of_another_kind_is_refused(folder):
    """A member replaced after the set was written (its sha256 differs), or one of another
    kind than the set records: refused as an input is, one line, nothing written."""
    wall(folder / "other", 11, 40)
    for suffix in (".json", ".obj"):
        shutil.copy(folder / f"other{suffix}", folder / f"wp2{suffix}")
    before = tree(folder)
    r = run("planarize-strips", folder / "n", "-o", folder / "x")
    refused(r.stderr, r.exit_code, 1, "data.members[1]: member p2 (wp2.json) changed since "
            "the set was written")
    r = run("inspect", folder / "n")
    refused(r.stderr, r.exit_code, 1, "member p2 (wp2.json) changed")
    assert tree(folder) == before
    doc = json.loads((folder / "s.json").read_text())
    doc["data"]["members"][0]["kind"] = "flat"
    (folder / "s.json").write_text(json.dumps(doc))
    before = tree(folder)
    r = run("unfold", folder / "s", "-o", folder / "f")
    refused(r.stderr, r.exit_code, 1, "member p1 (s.p1.json) is a 'strips' artifact, the set "
            "records a 'flat'")
    assert tree(folder) == before


def test_an_option_wrong_for_every_member_writes_nothing(folder):
    """A plain --stock-length of 2500 on strips in metres is a usage error (likely mm): it is
    found in the first member; nothing is written, not even a set of failures."""
    before = tree(folder)
    r = run("unfold", folder / "s", "--stock-length", 2500, "-o", folder / "f")
    refused(r.stderr, r.exit_code, 2, "--stock-length")
    assert tree(folder) == before


# the random-kill test -------------------------------------------------------------------------

#: The system calls of a commit at which the writer may die: writing a temporary file ends in
#: fsync, the journal appears by rename, the files by rename, backups and stale files go by
#: unlink, backups come by link.
KILL_AT = ("fsync", "replace", "rename", "link", "unlink")
KILLS = 14


def _member_names(folder: Path) -> dict[str, bytes]:
    """The visible files of the strips set ``s`` (the set and its members) with their bytes."""
    return {p.name: p.read_bytes() for p in sorted(folder.glob("s.*"))}


def _child(folder: Path, args: list[str], kill_at: int | None, counter_fd: int) -> None:
    """In a forked child: run ``dgpc ARGS`` from ``folder`` and SIGKILL itself at its
    ``kill_at``-th file-system call of :data:`KILL_AT` (never: count them and write the count
    to ``counter_fd``)."""
    calls = [0]

    def counted(function):
        def wrapper(*a, **k):
            calls[0] += 1
            if calls[0] == kill_at:
                os.kill(os.getpid(), signal.SIGKILL)
            return function(*a, **k)
        return wrapper

    for name in KILL_AT:
        setattr(os, name, counted(getattr(os, name)))
    os.chdir(folder)
    code = 1
    try:
        code = CliRunner().invoke(cli, args).exit_code
        os.write(counter_fd, str(calls[0]).encode())
    finally:
        os._exit(code)


def _fork_run(folder: Path, args: list[str], kill_at: int | None) -> tuple[int, int]:
    """``(wait status, calls counted)`` of :func:`_child`."""
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:                                                  # pragma: no cover - child
        os.close(read_fd)
        _child(folder, args, kill_at, write_fd)
    os.close(write_fd)
    _, status = os.waitpid(pid, 0)
    counted = os.read(read_fd, 64)
    os.close(read_fd)
    return status, int(counted) if counted else 0


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_a_killed_rerun_leaves_the_old_set_or_the_new_one(folder, monkeypatch):
    """``planarize-strips n -o s --force`` over the old 2-member set (made of strips 0:1 only),
    killed with SIGKILL at randomly chosen (seeded) points of its run: its file-system calls
    (fsync, rename, link, unlink), the commit's among them. After a reader (reading the set
    and every member, which finishes a committed write), the set and its members are all the
    old ones or all the new ones, byte for byte; never a mix, never a journal left. Every
    other reader reads a member first (its read finishes the set's committed write too)."""
    monkeypatch.chdir(folder)
    dgpc("planarize-strips", "n", "--strips", "0:1", "-o", "s", "--force")
    old = _member_names(folder)
    args = ["planarize-strips", "n", "-o", "s", "--force"]
    status, calls = _fork_run(folder, args, None)                # a whole run: count its calls
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0 and calls > 10
    new = _member_names(folder)
    assert set(new) == set(old) and all(new[k] != old[k] for k in new if k.endswith(".json"))
    points = sorted(random.Random(39).sample(range(1, calls + 1), min(KILLS, calls)))
    seen, seen_points = set(), []
    for point in points:
        for name in _member_names(folder):
            (folder / name).unlink()
        for name, data in old.items():
            (folder / name).write_bytes(data)
        status, _ = _fork_run(folder, args, point)
        assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL, point
        if len(seen_points) % 2:            # a reader of one member finishes the set's write
            read_strips(folder / "s.p2")
        doc = read_patch_set(folder / "s")                       # the reader
        for m in doc["data"]["members"]:
            read_strips((folder / m["path"]).with_suffix(""))
        seen_points.append(point)
        state = _member_names(folder)
        assert state in (old, new), (point, sorted(k for k in state
                                                   if state.get(k) != new.get(k)))
        assert not list(folder.glob(".s.json.journal")), point
        seen.add("new" if state == new else "old")
    assert seen == {"old", "new"}, seen                # kills before and after the commit
    r = run("planarize-strips", "n", "-o", "s", "--force")      # the next writer tidies up
    assert r.exit_code == 0 and _member_names(folder) == new
    assert not [p.name for p in folder.iterdir() if p.name.startswith(".s.")]
