"""Patch set artifact (``kind: patchset``): the member artifacts of one stage run on several
patches of a reference, one net each (``init --patches``: ``STEM.p1``, ``STEM.p2``, ...), and
every file each member wrote.

``STEM.json`` of a patch set lists its members (``data.members``: name ``pK``, kind, JSON path
relative to the set's folder, its sha256, the files it wrote and the exit code of its stage),
so that a later stage given ``STEM`` runs on each member, and so that a rerun with ``--force``
removes the files of the members it no longer makes (by these lists, never by a pattern).

A member whose stage failed without writing its output is recorded in ``data.failed`` (name,
stage, exit code, the one-line reason; it has no files) and the set's ``status.exit_code`` is
the worst member's. Such a set holds part of the design only: every stage given it refuses it
(:func:`member_stems`); ``inspect`` shows it (:func:`listed_members`, :func:`failed_members`).
Sets written before ``data.failed`` existed have none and read as before.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from ..errors import DgpcError
from .artifact import (
    artifact_paths,
    dumps_json,
    listed_files,
    listed_path,
    load_envelope,
    make_envelope,
    sha256_file,
    validate_envelope,
)

KIND = "patchset"


def is_patch_set(stem: str | Path) -> bool:
    """Whether the artifact ``stem`` (a stem or its JSON) is a patch set (a missing or
    unreadable JSON is not)."""
    json_path, _ = artifact_paths(stem)
    try:
        doc = json.loads(json_path.read_bytes())
    except (OSError, ValueError, RecursionError):
        return False
    return isinstance(doc, dict) and doc.get("kind") == KIND


def read_patch_set(stem: str | Path) -> dict:
    """The validated envelope of the patch set ``stem``; every member path lies in its
    folder, and no member is named twice (among those written and those that failed)."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    for k, member in enumerate(doc["data"]["members"]):
        listed_path(member["path"], json_path, f"data.members[{k}].path")
        for i, name in enumerate(member["files"]):
            listed_path(name, json_path, f"data.members[{k}].files[{i}]")
    names = [m["name"] for m in doc["data"]["members"]] + \
        [m["name"] for m in failed_members(doc)]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise DgpcError(f"data: member {', '.join(twice)} listed more than once",
                        source=json_path)
    return doc


def failed_members(doc: dict) -> list[dict]:
    """The records of the members that failed (``data.failed``) of a patch set's envelope."""
    return list(doc["data"].get("failed", []))


def listed_members(stem: str | Path) -> list[tuple[str, Path]]:
    """``(name, member stem)`` of every member the patch set ``stem`` lists as written, in
    order, whether or not others failed (for readers that report, like ``inspect``)."""
    json_path, _ = artifact_paths(stem)
    doc = read_patch_set(json_path)
    return [(m["name"], (json_path.parent / m["path"]).with_suffix(""))
            for m in doc["data"]["members"]]


def member_stems(stem: str | Path) -> list[tuple[str, Path]]:
    """``(name, member stem)`` of every member of the patch set ``stem``, in order. A set with
    a failed member holds part of the design only: refused (DgpcError naming the members and
    the stage), so that no later stage makes a cuttable output of part of it."""
    json_path, _ = artifact_paths(stem)
    failed = failed_members(read_patch_set(json_path))
    if failed:
        names = ", ".join(f"{m['name']} (exit {m['exit_code']})" for m in failed)
        stages = " / ".join(sorted({m["stage"] for m in failed}))
        raise DgpcError(f"data.failed: {_plural(len(failed), 'member')} {names} failed in "
                        f"`dgpc {stages}`, so this set holds part of the design only and is "
                        f"refused; `dgpc inspect` shows why; re-run {stages} once "
                        f"{'they pass' if len(failed) > 1 else 'it passes'}", source=json_path)
    return listed_members(json_path)


def _plural(count: int, word: str) -> str:
    return word if count == 1 else f"{word}s"


def with_members(stems) -> list[Path]:
    """``stems`` with every patch set among them replaced by its members' stems, in order."""
    out: list[Path] = []
    for stem in stems:
        out += ([s for _, s in member_stems(stem)] if is_patch_set(stem) else [Path(stem)])
    return out


def member_files(json_path: Path, extra: tuple[Path, ...] = ()) -> list[Path]:
    """The files a member artifact ``json_path`` wrote: itself, the files it lists and
    ``extra`` (e.g. the patch mesh ``init`` writes beside its net)."""
    return [json_path, *listed_files(json_path), *extra]


def previous_files(json_path: Path) -> list[Path]:
    """The files the output now at ``json_path`` wrote besides the JSON itself: a patch set's
    member files (as it lists them), else what the artifact lists; nothing when absent."""
    try:
        doc = json.loads(Path(json_path).read_bytes())
    except (OSError, ValueError, RecursionError):
        return []
    if not (isinstance(doc, dict) and doc.get("kind") == KIND):
        return listed_files(json_path)
    try:
        doc = read_patch_set(json_path)
    except Exception:       # a damaged set: nothing is removed on its word
        return []
    return [Path(json_path).parent / name for m in doc["data"]["members"]
            for name in m["files"]]


def patch_set_bytes(json_path: Path, stage: str, members: list[dict], *,
                    failed: list[dict] = (), inputs: dict | None = None,
                    parameters: dict | None = None) -> bytes:
    """The JSON of a patch set at ``json_path`` of ``members``: dicts with ``name``, ``kind``,
    ``json`` (the member's JSON path), ``files`` (every file it wrote) and ``exit_code``;
    ``failed``: dicts with ``name``, ``exit_code`` and ``reason`` of the members whose
    ``stage`` failed without writing (``data.failed``, only when there are some)."""
    folder = Path(json_path).parent
    records = [{"name": m["name"], "kind": m["kind"],
                "path": relative_path(m["json"], folder),
                "sha256": sha256_file(m["json"]),
                "files": sorted({relative_path(f, folder) for f in m["files"]}),
                "exit_code": int(m["exit_code"])} for m in members]
    data = {"stage": stage, "members": records}
    if failed:
        data["failed"] = [{"name": m["name"], "stage": stage, "exit_code": int(m["exit_code"]),
                           "reason": " ".join(str(m["reason"]).split())} for m in failed]
    doc = make_envelope(KIND, inputs=inputs, parameters=parameters, data=data,
                        status={"exit_code": max(int(m["exit_code"])
                                                 for m in (*members, *failed))})
    validate_envelope(json.loads(dumps_json(doc)), KIND, json_path)
    return dumps_json(doc)


def relative_path(path, folder: Path) -> str:
    """``path`` relative to ``folder``, POSIX (what a set records)."""
    return Path(os.path.relpath(os.path.abspath(path), os.path.abspath(folder))).as_posix()
