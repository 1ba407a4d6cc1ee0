"""Patch set artifact (``kind: patchset``): the member artifacts of one stage run on several
patches of a reference, one net each (``init --patches``: ``STEM.p1``, ``STEM.p2``, ...), and
every file each member wrote.

``STEM.json`` of a patch set lists its members (``data.members``: name ``pK``, kind, JSON path
relative to the set's folder, its sha256, the files it wrote and the exit code of its stage),
so that a later stage given ``STEM`` runs on each member, and so that a rerun with ``--force``
removes the files of the members it no longer makes: of those the set lists, only the files it
wrote itself (:func:`previous_files`: named ``STEM.*``, a member's own ``STEM.pK.*``, with the
sha256 recorded for them), never a file it merely lists. Reading a set checks every member
as an input is checked: its JSON's sha256 and its kind (:func:`listed_members`).

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
    ListedFileChanged,
    artifact_paths,
    dumps_json,
    holds_as_written,
    listed_in,
    listed_path,
    load_envelope,
    make_envelope,
    owned_files,
    recorded_sha256s,
    sha256_bytes,
    sha256_file,
    validate_envelope,
)
from .bounded_read import read_regular

KIND = "patchset"


def is_patch_set(stem: str | Path) -> bool:
    """Whether the artifact ``stem`` (a stem or its JSON) is a patch set (a missing or
    unreadable JSON is not)."""
    json_path, _ = artifact_paths(stem)
    doc = _doc(json_path)
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
    order, whether or not others failed (for readers that report, like ``inspect``). Every
    member is checked as an input is: its JSON still has the sha256 the set records (else
    it was replaced or edited since), and is of the kind the set records."""
    json_path, _ = artifact_paths(stem)
    doc = read_patch_set(json_path)
    for k, m in enumerate(doc["data"]["members"]):
        _check_member(m, json_path.parent / m["path"], json_path, f"data.members[{k}]")
    return [(m["name"], (json_path.parent / m["path"]).with_suffix(""))
            for m in doc["data"]["members"]]


def _check_member(member: dict, path: Path, json_path: Path, field: str) -> None:
    """DgpcError naming the set and ``field`` unless the member JSON ``path`` is there, has the
    recorded sha256 and is of the recorded kind."""
    if not path.exists():
        raise DgpcError(f"{field}: member {member['name']} ({member['path']}) is missing",
                        source=json_path)
    try:
        data = read_regular(path, "a member's JSON")
    except DgpcError as e:
        raise DgpcError(f"{field}: member {member['name']} ({member['path']}): {e.reason}",
                        source=json_path) from None
    if sha256_bytes(data) != member["sha256"]:
        raise ListedFileChanged(f"{field}: member {member['name']} ({member['path']}) changed "
                                "since the set was written (sha256 differs); write the set "
                                "again", source=json_path)
    try:
        kind = json.loads(data).get("kind")
    except (ValueError, RecursionError, AttributeError):
        kind = None
    if kind != member["kind"]:
        raise DgpcError(f"{field}: member {member['name']} ({member['path']}) is "
                        f"{'a ' + repr(kind) if isinstance(kind, str) else 'not an'} artifact, "
                        f"the set records a '{member['kind']}'", source=json_path)


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


def member_files(json_path: Path, extra: tuple[Path, ...] = (), *,
                 read=lambda path: Path(path).read_bytes()) -> list[Path]:
    """The files a member artifact ``json_path`` wrote: itself, the files it lists and
    ``extra`` (e.g. the patch mesh ``init`` writes beside its net). ``read(path)``: its
    bytes (those of a write still held, :func:`~dgpc_cli.io.atomic.held_writes`)."""
    return [json_path, *listed_in(json.loads(read(json_path)), json_path), *extra]


def previous_files(json_path: Path) -> list[Path]:
    """The files the output now at ``json_path`` wrote besides the JSON itself, which a
    ``--force`` over it may remove; nothing when absent. A single artifact: the files it lists
    that still hold what it wrote (:func:`~dgpc_cli.io.artifact.owned_files`). A patch set:
    of the files its members list, those it wrote itself: a member JSON named ``STEM.*`` in
    the set's folder that still has the sha256 the set records, and its files named like it
    (``STEM.pK.*``) that still have the sha256 that member JSON records for them. A file the
    set merely lists (a user's notes, an input mesh, another artifact) is never one of them."""
    json_path = Path(json_path)
    doc = _doc(json_path)
    if not (isinstance(doc, dict) and doc.get("kind") == KIND):
        return owned_files(json_path)
    try:
        doc = read_patch_set(json_path)
    except Exception:       # a damaged set: nothing is removed on its word
        return []
    folder, stem = json_path.parent, json_path.name[: -len(".json")]
    own = []
    for m in doc["data"]["members"]:
        path = folder / m["path"]
        if not _named_for(m["path"], stem) or not holds_as_written(
                path, {m["path"]: m["sha256"]}, m["path"]):
            continue
        member_doc = _doc(path)
        if member_doc is None:
            continue
        recorded = recorded_sha256s(member_doc)
        own.append(path)
        member = m["path"][: -len(".json")]
        own += [folder / name for name in m["files"]
                if name != m["path"] and _named_for(name, member)
                and holds_as_written(folder / name, recorded, name)]
    return own


def _named_for(name: str, stem: str) -> bool:
    """Whether ``name`` (as a set records it) is a file of the stem ``stem`` in the set's own
    folder: ``STEM.*``."""
    return "/" not in name and "\\" not in name and name.startswith(f"{stem}.") \
        and len(name) > len(stem) + 1


def patch_set_bytes(json_path: Path, stage: str, members: list[dict], *,
                    failed: list[dict] = (), inputs: dict | None = None,
                    parameters: dict | None = None, read=None) -> bytes:
    """The JSON of a patch set at ``json_path`` of ``members``: dicts with ``name``, ``kind``,
    ``json`` (the member's JSON path), ``files`` (every file it wrote) and ``exit_code``;
    ``failed``: dicts with ``name``, ``exit_code`` and ``reason`` of the members whose
    ``stage`` failed without writing (``data.failed``, only when there are some).
    ``read(path)``: a member JSON's bytes (default: the file's)."""
    folder = Path(json_path).parent
    digest = sha256_file if read is None else (lambda path: sha256_bytes(read(path)))
    records = [{"name": m["name"], "kind": m["kind"],
                "path": relative_path(m["json"], folder),
                "sha256": digest(m["json"]),
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


def files_read(path: str | Path) -> set[Path]:
    """The files (resolved) that the input ``path`` of a command names and the command may
    read: the path itself and, as an artifact stem, its JSON and OBJ, every file its JSON
    lists or records (with a sha256: its reference mesh, its inputs); for a patch set, the
    same of each member. For ``-o`` to be checked against (:func:`files_written`)."""
    found = {real_path(path)}
    try:
        json_path, obj_path = artifact_paths(path)
    except DgpcError:
        return found
    found |= {real_path(json_path), real_path(obj_path)}
    docs = [(json_path, _doc(json_path))]
    if isinstance(docs[0][1], dict) and docs[0][1].get("kind") == KIND:
        members = (docs[0][1].get("data") or {}).get("members")
        for m in members if isinstance(members, list) else []:
            if not isinstance(m, dict):
                continue
            for name in [m.get("path"), *(m.get("files") or [])]:
                if isinstance(name, str) and name:
                    found.add(real_path(json_path.parent / name))
            if isinstance(m.get("path"), str) and m["path"]:
                member = json_path.parent / m["path"]
                docs.append((member, _doc(member)))
    for where, doc in docs:
        recorded = dict(recorded_sha256s(doc))
        if isinstance(doc, dict) and isinstance(doc.get("inputs"), dict):
            recorded.update({r["path"]: "" for r in doc["inputs"].values()
                             if isinstance(r, dict) and isinstance(r.get("path"), str)})
        found |= {real_path(where.parent / name) for name in recorded if name}
        found |= {real_path(p) for p in listed_in(doc, where)}
    return found


def files_written(stem: str | Path, members: list[str] = ()) -> set[Path]:
    """The files (resolved) that writing the output ``stem`` may write or, with ``--force``,
    remove: its JSON and OBJ and the files the output now there wrote
    (:func:`previous_files`); with ``members`` (the names ``pK`` of an input set's members),
    the same of each ``STEM.pK``."""
    json_path, obj_path = artifact_paths(stem)
    found = {real_path(json_path), real_path(obj_path),
             *(real_path(p) for p in previous_files(json_path))}
    for name in members:
        found |= files_written(json_path.parent / f"{json_path.name[:-len('.json')]}.{name}")
    return found


def _doc(json_path: Path):
    """The parsed JSON at ``json_path``; None when missing, unreadable (not a regular file,
    too large: :mod:`.bounded_read`) or not JSON."""
    try:
        return json.loads(read_regular(json_path))
    except (DgpcError, ValueError, RecursionError):
        return None


def real_path(path: str | Path) -> Path:
    """``path`` absolute, its symbolic links followed as far as they lead (a loop, which
    ``Path.resolve`` raises on, is left as it is: reading it reports it)."""
    return Path(os.path.realpath(path))
