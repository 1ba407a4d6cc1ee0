"""Which tasks a rerun can skip: the fingerprint of a task is the sha256 of its command line,
the dgpc version and the sha256 of each of its input files; a task is reused when the last
run's ``batch.json`` records the same fingerprint for it, a result whose artifacts were
written (exit 0, or 3: a tolerance missed), and every file it wrote (by the exact names its
artifact listed) still has the sha256 recorded then. A failed task always runs again."""

from __future__ import annotations

import json
import os
from pathlib import Path

from dgpc_cli import __version__
from dgpc_cli.io.artifact import sha256_bytes

from .graph import Task

#: Exit codes whose outputs are kept and may be reused (ok, tolerance missed).
REUSABLE = (0, 3)


def file_sha256(path: Path) -> str | None:
    """sha256 of a file, None when it cannot be read (the task will fail on it)."""
    try:
        return sha256_bytes(Path(path).read_bytes())
    except OSError:
        return None


def fingerprint(task: Task, base: Path) -> str:
    """sha256 of the task's command line, the dgpc version and its inputs' sha256."""
    inputs = {Path(os.path.relpath(p, base)).as_posix(): file_sha256(p) for p in task.inputs}
    doc = {"dgpc": __version__, "argv": task.argv, "inputs": inputs}
    return sha256_bytes(json.dumps(doc, sort_keys=True).encode("utf-8"))


def hash_outputs(names, out: Path) -> dict[str, str | None]:
    """Path relative to ``out`` → sha256 of each of the files ``names`` (None: unreadable)."""
    return {name: file_sha256(Path(out) / name) for name in sorted(names)}


def reusable(previous: dict | None, fp: str, task: Task, out: Path) -> bool:
    """Whether the record ``previous`` (of the last run's batch.json) lets ``task`` be
    skipped."""
    if not previous or previous.get("fingerprint") != fp:
        return False
    if previous.get("exit_code") not in REUSABLE:
        return False
    recorded = previous.get("outputs") or {}
    if not isinstance(recorded, dict) or task.artifact not in recorded:
        return False
    return recorded == hash_outputs(recorded, out)


def load_previous(path: Path) -> dict[str, dict]:
    """The task records of the last run's batch.json, each with the wall time it took when
    it ran (none if the file is missing or unreadable)."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        tasks = {tid: dict(rec) for tid, rec in doc["tasks"].items()}
        times = doc.get("this_run", {}).get("tasks", {})
        for tid, rec in tasks.items():
            rec["wall_time_s"] = float(times.get(tid, {}).get("wall_time_s", 0.0))
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError):
        return {}
    return tasks
