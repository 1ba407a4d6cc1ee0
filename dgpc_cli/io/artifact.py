"""The artifact envelope of SPEC §3: deterministic JSON, input hashes, validated reading."""

from __future__ import annotations

import functools
import hashlib
import json
import os
import time
from pathlib import Path, PurePosixPath, PureWindowsPath
from typing import Any

from .. import __version__
from ..errors import DgpcError
from .bounded_read import read_regular
from .journal import finish_interrupted
from .jsonable import load_schema, read_json, schema_exists, to_jsonable, validate

#: Version 2: every artifact records its length unit, ``data.units`` (:mod:`.units`).
SCHEMA_VERSION = 2
SUPPORTED_VERSIONS = (2,)
#: Why an artifact of an older version cannot be read, and what to do.
OLDER_VERSIONS = {1: "it predates length units (data.units): re-run its pipeline from "
                     "`dgpc init ... --units mm|cm|m|in|ft` with this dgpc"}
KINDS = ("net", "mold", "strips", "flat", "sheets", "laths")
#: The stage that makes each kind, for messages about an artifact of the wrong kind.
MADE_BY = {"net": "dgpc init (or dgpc optimize NET)", "mold": "dgpc extract-mold NET",
           "strips": "dgpc planarize-strips NET", "flat": "dgpc unfold STRIPS",
           "sheets": "dgpc nest FLAT", "laths": "dgpc laths NET_A NET_B",
           "patchset": "dgpc init MESH --patches"}
ENVELOPE_KEYS = ("kind", "schema_version", "created_by", "inputs", "parameters", "data",
                 "metrics", "status")

#: Envelope check for kinds without a shipped schema of their own.
ENVELOPE_SCHEMA: dict = {
    "type": "object",
    "required": list(ENVELOPE_KEYS),
    "properties": {
        "kind": {"type": "string"},
        "schema_version": {"type": "integer"},
        "created_by": {"type": "string"},
        "inputs": {"type": "object", "additionalProperties": {
            "type": "object", "required": ["path", "sha256"],
            "properties": {"path": {"type": "string"},
                           "sha256": {"type": "string", "pattern": "^[0-9a-f]{64}$"}}}},
        **{k: {"type": "object"} for k in ("parameters", "data", "metrics", "status")},
    },
}


def created_by() -> str:
    """``"dgpc <version>"``."""
    return f"dgpc {__version__}"


def dumps_json(obj: Any) -> bytes:
    """Deterministic UTF-8 JSON: sorted keys, indent 2, trailing newline, numpy converted,
    non-finite floats as ``null``."""
    text = json.dumps(to_jsonable(obj), sort_keys=True, indent=2, allow_nan=False,
                      ensure_ascii=False)
    return (text + "\n").encode("utf-8")


def sha256_bytes(data: bytes) -> str:
    """Hex sha256 of ``data``."""
    return hashlib.sha256(data).hexdigest()


def sha256_file(path: str | Path) -> str:
    """Hex sha256 of a file's bytes; DgpcError naming the file if it cannot be read."""
    return sha256_bytes(read_regular(path))


def file_input(path: str | Path, relative_to: str | Path) -> dict[str, str]:
    """``{"path", "sha256"}`` of an input file, the path POSIX and relative to the artifact's
    folder ``relative_to`` (``os.path.relpath``)."""
    rel = os.path.relpath(Path(path).resolve(), Path(relative_to).resolve())
    return {"path": Path(rel).as_posix(), "sha256": sha256_file(path)}


def relative_input(path: str | Path, relative_to: str | Path, data: bytes) -> dict[str, str]:
    """Like :func:`file_input` for a file about to be written with the bytes ``data``."""
    rel = os.path.relpath(Path(path).resolve(), Path(relative_to).resolve())
    return {"path": Path(rel).as_posix(), "sha256": sha256_bytes(data)}


def resolve_input(record: dict, artifact_json: str | Path) -> Path:
    """The path of an input recorded as ``{"path", "sha256"}`` relative to the artifact (it
    may lie anywhere: read it through :func:`recorded_file`, which checks its sha256)."""
    return Path(artifact_json).resolve().parent / record["path"]


def recorded_file(record: Any, json_path: str | Path, field: str) -> Path:
    """The file an artifact records under ``field`` as ``{"path", "sha256"}`` outside its own
    folder as well (a reference mesh, an input), checked before use: a path and a sha256 are
    recorded, the file is there, and its bytes still have that sha256. DgpcError naming the
    artifact and ``field`` otherwise."""
    if not isinstance(record, dict) or not isinstance(record.get("path"), str) \
            or not record["path"]:
        raise DgpcError(f"{field}: no path recorded", source=json_path)
    sha256 = record.get("sha256")
    if not isinstance(sha256, str) or len(sha256) != 64:
        raise DgpcError(f"{field}: no sha256 recorded for {record['path']}, so it cannot be "
                        "checked", source=json_path)
    path = resolve_input(record, json_path)
    if not path.is_file():
        raise DgpcError(f"{field}: {record['path']} is missing (recorded relative to the "
                        "artifact's folder)", source=json_path)
    if sha256_file(path) != sha256:
        raise DgpcError(f"{field}: {record['path']} changed since the artifact was written "
                        "(sha256 differs)", source=json_path)
    return path


def listed_path(text: Any, json_path: str | Path, field: str) -> Path:
    """The path of a file that the artifact ``json_path`` lists under ``field`` (its OBJ, a
    DXF, CSV or PNG): relative to the artifact's folder and inside it. An absolute path or one
    with a ``..`` step, or a symbolic link whose target lies outside the folder, is a DgpcError
    naming the artifact and ``field`` (a listed file is never looked for elsewhere)."""
    if not isinstance(text, str) or not text or text in (".", "./"):
        raise DgpcError(f"{field}: {text!r} is not a file name", source=json_path)
    posix, windows = PurePosixPath(text), PureWindowsPath(text)
    if posix.is_absolute() or windows.is_absolute() or windows.drive or windows.root:
        raise DgpcError(f"{field}: {text!r} is an absolute path; the files an artifact lists "
                        "lie in its own folder", source=json_path)
    if ".." in posix.parts or ".." in windows.parts:
        raise DgpcError(f"{field}: {text!r} leads out of the artifact's folder ('..'); the "
                        "files an artifact lists lie in its own folder", source=json_path)
    folder = Path(os.path.realpath(json_path)).parent
    path = folder / posix
    if not Path(os.path.realpath(path)).is_relative_to(folder):   # a loop stays: read says
        raise DgpcError(f"{field}: {text!r} is a symbolic link that leads out of the "
                        "artifact's folder; the files an artifact lists lie in its own folder",
                        source=json_path)
    return path


def listed_file(text: Any, json_path: str | Path, field: str) -> Path:
    """:func:`listed_path`, which must name a file (not a folder): the file an artifact lists
    is read from where it says, never from another name."""
    path = listed_path(text, json_path, field)
    if path.is_dir():
        raise DgpcError(f"{field}: {text!r} is a folder, not the artifact's file",
                        source=json_path)
    return path


def check_listed_paths(doc: dict, json_path: str | Path) -> None:
    """Every file an artifact lists (``data.obj``, ``data.cut_list``, ``data.files.*.path``,
    ``data.rhino_3dm.path``) lies in its folder (:func:`listed_path`); the recorded reference
    mesh and the inputs may lie anywhere, checked by sha256 where used."""
    data = doc.get("data")
    if not isinstance(data, dict):
        return
    for key in ("obj", "cut_list"):
        if key in data:
            listed_path(data[key], json_path, f"data.{key}")
    files = data.get("files")
    if isinstance(files, dict):
        for key in sorted(files):
            record = files[key]
            listed_path(record.get("path") if isinstance(record, dict) else record, json_path,
                        f"data.files.{key}")
    rhino = data.get("rhino_3dm")
    if isinstance(rhino, dict):
        listed_path(rhino.get("path"), json_path, "data.rhino_3dm")


def artifact_files(kind: str, stem: str | Path, obj_bytes: bytes, data: dict, *,
                   inputs: dict, parameters: dict, metrics: dict, status: dict
                   ) -> dict[Path, bytes]:
    """The bytes of ``STEM.json`` and ``STEM.obj`` of a ``kind`` artifact (nothing written).

    ``data`` gets the OBJ's name and sha256; the envelope is checked against the kind's JSON
    Schema, so an invalid artifact is never written. Callers add their extra files (DXF, CSV)
    to the returned dict and write everything in one :func:`write_files` call.
    """
    json_path, obj_path = artifact_paths(stem)
    data = {**data, "obj": obj_path.name, "obj_sha256": sha256_bytes(obj_bytes)}
    doc = make_envelope(kind, inputs=inputs, parameters=parameters, data=data,
                        metrics=metrics, status=status)
    json_bytes = dumps_json(doc)
    validate(json.loads(json_bytes), load_schema(kind), json_path)
    return {json_path: json_bytes, obj_path: obj_bytes}


def read_listed(path: Path, sha256: str, json_path: Path, field: str) -> bytes:
    """The bytes of a file an artifact lists (its OBJ, DXF, CSV ...), checked against the sha256
    the JSON records under ``field``; DgpcError naming the file when missing or edited."""
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        raise DgpcError(f"missing; {Path(json_path).name} needs it beside it ({field})",
                        source=path)
    data = read_regular(path, f"the file {field} names")
    if sha256_bytes(data) != sha256:
        raise ListedFileChanged(f"does not match {Path(json_path).name} (edited separately?): "
                                f"its sha256 differs from {field}", source=path)
    return data


class ListedFileChanged(DgpcError):
    """A listed file's sha256 differs from the one its JSON records: edited separately, or
    replaced by a write that committed between the reading of the JSON and of the file."""


#: How often an artifact is read again when a listed file did not match its JSON.
READ_ATTEMPTS = 3


def reread(read):
    """Decorate an artifact reader: a listed file that does not match the JSON read just before
    may belong to a write that committed in between, so the whole artifact is read again (at
    most :data:`READ_ATTEMPTS` times; the reading of the JSON waits for a live writer's
    renames): a reader gets the old set or the new one, never a false mismatch."""
    @functools.wraps(read)
    def wrapper(*args, **kwargs):
        for attempt in range(1, READ_ATTEMPTS + 1):
            try:
                return read(*args, **kwargs)
            except ListedFileChanged:
                if attempt == READ_ATTEMPTS:
                    raise
                time.sleep(0.05 * attempt)
    return wrapper


def listed_files(json_path: str | Path) -> list[Path]:
    """The files an existing artifact ``json_path`` lists besides itself (``data.obj``, each
    ``data.files`` record, ``data.rhino_3dm``, ``data.cut_list``), for ``--force`` to remove
    those a new artifact of the same stem no longer writes.

    Only files in the artifact's own folder named ``STEM.*`` count (a path that leads
    elsewhere is never followed); a missing or unreadable JSON lists nothing.
    """
    json_path = Path(json_path)
    try:
        return listed_in(json.loads(read_regular(json_path)), json_path)
    except (DgpcError, ValueError, RecursionError):
        return []


def listed_in(doc: Any, json_path: str | Path) -> list[Path]:
    """:func:`listed_files` of the parsed JSON ``doc`` of the artifact ``json_path``."""
    json_path = Path(json_path)
    data = doc.get("data") if isinstance(doc, dict) else None
    if not isinstance(data, dict) or doc.get("kind") not in KINDS:
        return []
    rhino = data.get("rhino_3dm")
    names = [data.get("obj"), data.get("cut_list"),
             rhino.get("path") if isinstance(rhino, dict) else None]
    files = data.get("files")
    if isinstance(files, dict):
        names += [r.get("path") for r in files.values() if isinstance(r, dict)]
    prefix = json_path.name[: -len(".json")] + "."
    return [json_path.parent / n for n in names
            if isinstance(n, str) and "/" not in n and "\\" not in n and n.startswith(prefix)
            and n != json_path.name]


def recorded_sha256s(doc: Any) -> dict[str, str]:
    """Every ``path → sha256`` an artifact's JSON ``doc`` records in ``data`` (the files it
    wrote, and the references it read there): the ``{"path", "sha256"}`` records and the
    ``KEY``/``KEY_sha256`` pairs (``obj`` and ``obj_sha256``), paths as written (relative to
    the artifact's folder)."""
    found: dict[str, str] = {}

    def walk(node, depth=0):
        if depth > 8:
            return
        if isinstance(node, dict):
            if isinstance(node.get("path"), str) and isinstance(node.get("sha256"), str):
                found.setdefault(node["path"], node["sha256"])
            for key, value in node.items():
                pair = node.get(f"{key}_sha256")
                if isinstance(value, str) and isinstance(pair, str):
                    found.setdefault(value, pair)
                walk(value, depth + 1)
        elif isinstance(node, list):
            for value in node:
                walk(value, depth + 1)

    if isinstance(doc, dict):
        walk(doc.get("data"))
    return found


def holds_as_written(path: str | Path, recorded: dict[str, str], name: str) -> bool:
    """Whether the file ``path`` exists and its bytes have the sha256 ``recorded`` for
    ``name`` (so it is still the file that recorded it was written with)."""
    sha256 = recorded.get(name)
    if sha256 is None or not Path(path).is_file():
        return False
    try:
        return sha256_file(path) == sha256
    except DgpcError:
        return False


def owned_files(json_path: str | Path) -> list[Path]:
    """The files of :func:`listed_files` that still hold the bytes the JSON records for them
    (its sha256): the files the artifact wrote, which ``--force`` may remove. A file listed
    without a sha256, or changed since, is not the artifact's to remove."""
    json_path = Path(json_path)
    try:
        doc = json.loads(read_regular(json_path))
    except (DgpcError, ValueError, RecursionError):
        return []
    recorded = recorded_sha256s(doc)
    return [p for p in listed_in(doc, json_path) if holds_as_written(p, recorded, p.name)]


def artifact_paths(stem: str | Path) -> tuple[Path, Path]:
    """``(STEM.json, STEM.obj)`` for a stem given as ``STEM``, ``STEM.json`` or ``STEM.obj``."""
    text = os.fspath(stem)
    for suffix in (".json", ".obj"):
        if text.lower().endswith(suffix):
            text = text[: -len(suffix)]
            break
    if not text or text.endswith(("/", os.sep)):
        raise DgpcError("not an artifact stem (needs a file name)", source=stem)
    return Path(text + ".json"), Path(text + ".obj")


def make_envelope(kind: str, *, inputs: dict | None = None, parameters: dict | None = None,
                  data: dict | None = None, metrics: dict | None = None,
                  status: dict | None = None) -> dict:
    """A complete envelope dict of ``kind`` (schema version and ``created_by`` filled in)."""
    return {"kind": kind, "schema_version": SCHEMA_VERSION, "created_by": created_by(),
            "inputs": dict(inputs or {}), "parameters": dict(parameters or {}),
            "data": dict(data or {}), "metrics": dict(metrics or {}),
            "status": dict(status or {})}


def validate_envelope(doc: Any, kind: str, source: str | Path) -> None:
    """Check an envelope: a JSON object, its ``kind``, a supported ``schema_version``, then the
    kind's JSON Schema (``io/schemas/<kind>.schema.json``, else the generic envelope schema)."""
    if not isinstance(doc, dict):
        raise DgpcError(f"not a dgpc artifact: top level is a JSON "
                        f"{type(doc).__name__}, expected an object", source=source)
    found = doc.get("kind")
    if isinstance(found, str) and found != kind:
        raise DgpcError(f"kind: is a '{found}' artifact, expected '{kind}' (made by "
                        f"`{MADE_BY.get(kind, kind)}`)", source=source)
    version = doc.get("schema_version")
    if isinstance(version, int) and not isinstance(version, bool) \
            and version in OLDER_VERSIONS:
        raise DgpcError(f"schema_version: {version} is no longer read, {OLDER_VERSIONS[version]}",
                        source=source)
    if isinstance(version, int) and not isinstance(version, bool) \
            and version not in SUPPORTED_VERSIONS:
        raise DgpcError(f"schema_version: {version} is not supported (supported: "
                        f"{', '.join(map(str, SUPPORTED_VERSIONS))}); "
                        f"written by {doc.get('created_by', 'an unknown program')}",
                        source=source)
    schema = load_schema(kind) if schema_exists(kind) else {
        **ENVELOPE_SCHEMA, "properties": {**ENVELOPE_SCHEMA["properties"], "kind": {"const": kind}}}
    validate(doc, schema, source)


def load_envelope(path: str | Path, kind: str) -> dict:
    """Read and validate the JSON envelope of a ``kind`` artifact; ``path`` may be a stem. A
    write of it interrupted after its commit is finished first (:mod:`.journal`)."""
    json_path, _ = artifact_paths(path)
    finish_interrupted(json_path)
    doc = read_json(json_path)
    validate_envelope(doc, kind, json_path)
    check_listed_paths(doc, json_path)
    return doc
