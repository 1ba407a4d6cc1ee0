"""Patch set artifact (``kind: patchset``): the member artifacts of one stage run on several
patches of a reference, one net each (``init --patches``: ``STEM.p1``, ``STEM.p2``, ...), and
every file each member wrote.

``STEM.json`` of a patch set lists its members (``data.members``: name ``pK``, kind, JSON path
relative to the set's folder, its sha256, the files it wrote and the exit code of its stage),
so that a later stage given ``STEM`` runs on each member, and so that a rerun with ``--force``
removes the files of the members it no longer makes (by these lists, never by a pattern).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

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
    folder."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    for k, member in enumerate(doc["data"]["members"]):
        listed_path(member["path"], json_path, f"data.members[{k}].path")
        for i, name in enumerate(member["files"]):
            listed_path(name, json_path, f"data.members[{k}].files[{i}]")
    return doc


def member_stems(stem: str | Path) -> list[tuple[str, Path]]:
    """``(name, member stem)`` of every member of the patch set ``stem``, in order."""
    json_path, _ = artifact_paths(stem)
    doc = read_patch_set(json_path)
    return [(m["name"], (json_path.parent / m["path"]).with_suffix(""))
            for m in doc["data"]["members"]]


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
                    inputs: dict | None = None, parameters: dict | None = None) -> bytes:
    """The JSON of a patch set at ``json_path`` of ``members``: dicts with ``name``, ``kind``,
    ``json`` (the member's JSON path), ``files`` (every file it wrote) and ``exit_code``."""
    folder = Path(json_path).parent
    records = [{"name": m["name"], "kind": m["kind"],
                "path": _relative(m["json"], folder),
                "sha256": sha256_file(m["json"]),
                "files": sorted({_relative(f, folder) for f in m["files"]}),
                "exit_code": int(m["exit_code"])} for m in members]
    doc = make_envelope(KIND, inputs=inputs, parameters=parameters,
                        data={"stage": stage, "members": records},
                        status={"exit_code": max(m["exit_code"] for m in members)})
    validate_envelope(json.loads(dumps_json(doc)), KIND, json_path)
    return dumps_json(doc)


def _relative(path, folder: Path) -> str:
    return Path(os.path.relpath(os.path.abspath(path), os.path.abspath(folder))).as_posix()
