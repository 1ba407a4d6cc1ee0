"""io.atomic and io.artifact: all-or-nothing writes, deterministic JSON, validated envelopes."""

import json
import os
from pathlib import Path

import numpy as np
import pytest

from dgpc_cli import __version__
from dgpc_cli.errors import DgpcError
from dgpc_cli.io import artifact as artifact_mod
from dgpc_cli.io import atomic
from dgpc_cli.io.artifact import (
    artifact_paths,
    dumps_json,
    file_input,
    load_envelope,
    make_envelope,
    sha256_bytes,
)
from dgpc_cli.io.atomic import write_files


def listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# write_files -------------------------------------------------------------------------------
def test_write_files_writes_all(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "a.obj"
    write_files({a: b"{}\n", b: b"v 0 0 0\n"})
    assert a.read_bytes() == b"{}\n" and b.read_bytes() == b"v 0 0 0\n"
    assert listing(tmp_path) == ["a.json", "a.obj"]  # no temp files left


def test_write_files_refuses_existing_and_writes_nothing(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "a.obj"
    b.write_bytes(b"old")
    with pytest.raises(DgpcError) as err:
        write_files({a: b"new", b: b"new"})
    assert str(err.value) == f"{b}: already exists; use --force to overwrite"
    assert listing(tmp_path) == ["a.obj"] and b.read_bytes() == b"old"


def test_write_files_force_overwrites(tmp_path):
    a = tmp_path / "a.json"
    a.write_bytes(b"old")
    write_files({a: b"new"}, force=True)
    assert a.read_bytes() == b"new" and listing(tmp_path) == ["a.json"]


def test_write_files_missing_directory(tmp_path):
    good, bad = tmp_path / "x.json", tmp_path / "nope" / "x.obj"
    with pytest.raises(DgpcError) as err:
        write_files({good: b"1", bad: b"2"})
    assert err.value.source == str(tmp_path / "nope")
    assert "does not exist" in str(err.value)
    assert listing(tmp_path) == []


def test_write_files_failure_during_replace_leaves_nothing(tmp_path, monkeypatch):
    a, b = tmp_path / "a.json", tmp_path / "a.obj"
    a.write_bytes(b"old a")
    real_replace, calls = os.replace, []

    def flaky(src, dst):
        calls.append(dst)
        if Path(dst) == b:
            raise OSError(28, "No space left on device")
        return real_replace(src, dst)

    monkeypatch.setattr(atomic.os, "replace", flaky)
    with pytest.raises(DgpcError, match="No space left on device"):
        write_files({a: b"new a", b: b"new b"}, force=True)
    assert a.read_bytes() == b"old a"  # restored
    assert listing(tmp_path) == ["a.json"]  # no temp, backup or partial file
    assert len(calls) >= 2


def test_write_files_failure_during_write_removes_temps(tmp_path, monkeypatch):
    real = atomic.os.fsync
    count = []

    def failing_fsync(fd):
        count.append(fd)
        if len(count) == 2:
            raise OSError(5, "Input/output error")
        return real(fd)

    monkeypatch.setattr(atomic.os, "fsync", failing_fsync)
    with pytest.raises(DgpcError) as err:
        write_files({tmp_path / "a.json": b"1", tmp_path / "a.obj": b"2"})
    assert err.value.source == str(tmp_path / "a.obj")
    assert listing(tmp_path) == []


def test_write_files_permissions_follow_umask(tmp_path):
    target = tmp_path / "a.json"
    write_files({target: b"x"})
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


# dumps_json ---------------------------------------------------------------------------------
def test_dumps_json_is_deterministic_and_converts_numpy():
    obj = {"b": np.float64(1.5), "a": (np.int64(2), np.array([[1.0, np.nan]])),
           "c": float("inf"), "d": "π", "e": np.bool_(True)}
    out = dumps_json(obj)
    assert out.endswith(b"}\n") and out == dumps_json(dict(reversed(list(obj.items()))))
    assert "π".encode() in out
    assert json.loads(out) == {"a": [2, [[1.0, None]]], "b": 1.5, "c": None, "d": "π",
                               "e": True}
    assert out.index(b'"a"') < out.index(b'"b"') < out.index(b'"c"')
    assert b'\n  "a": [\n' in out  # indent 2


def test_dumps_json_rejects_unknown_types():
    with pytest.raises(TypeError):
        dumps_json({"x": object()})


# paths and inputs --------------------------------------------------------------------------
@pytest.mark.parametrize("given", ["out/wave", "out/wave.json", "out/wave.obj"])
def test_artifact_paths(given):
    assert artifact_paths(given) == (Path("out/wave.json"), Path("out/wave.obj"))


def test_artifact_paths_keeps_inner_dots():
    assert artifact_paths("a/b.v2") == (Path("a/b.v2.json"), Path("a/b.v2.obj"))


def test_file_input_relative_and_hashed(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "runs").mkdir()
    src = tmp_path / "data" / "ref.obj"
    src.write_bytes(b"v 0 0 0\n")
    entry = file_input(src, tmp_path / "runs")
    assert entry == {"path": "../data/ref.obj", "sha256": sha256_bytes(b"v 0 0 0\n")}


def test_file_input_missing_file(tmp_path):
    with pytest.raises(DgpcError, match="ref.obj"):
        file_input(tmp_path / "ref.obj", tmp_path)


# load_envelope -----------------------------------------------------------------------------
def write_doc(path: Path, doc) -> Path:
    path.write_text(json.dumps(doc))
    return path


def test_make_envelope_fields():
    env = make_envelope("net", parameters={"a": 1})
    assert env["created_by"] == f"dgpc {__version__}" and env["schema_version"] == 2
    assert sorted(env) == sorted(artifact_mod.ENVELOPE_KEYS)


def test_load_envelope_generic_kind_and_stem(tmp_path):
    doc = make_envelope("probe", data={"x": 1})
    write_doc(tmp_path / "p.json", doc)
    assert load_envelope(tmp_path / "p.obj", "probe") == json.loads(json.dumps(doc))


@pytest.mark.parametrize("content, message", [
    (None, "no such file"),
    ("{not json", "not valid JSON"),
    ("[1, 2]", "top level is a JSON list"),
])
def test_load_envelope_unreadable(tmp_path, content, message):
    path = tmp_path / "a.json"
    if content is not None:
        path.write_text(content)
    with pytest.raises(DgpcError) as err:
        load_envelope(path, "probe")
    assert str(err.value).startswith(f"{path}: ") and message in str(err.value)
    assert "\n" not in str(err.value)


def test_load_envelope_wrong_kind(tmp_path):
    path = write_doc(tmp_path / "a.json", make_envelope("mold"))
    with pytest.raises(DgpcError, match="is a 'mold' artifact, expected 'net'"):
        load_envelope(path, "net")


def test_load_envelope_unsupported_version(tmp_path):
    path = write_doc(tmp_path / "a.json", {**make_envelope("probe"), "schema_version": 7})
    with pytest.raises(DgpcError, match=r"schema_version: 7 is not supported \(supported: 2\)"):
        load_envelope(path, "probe")


def test_load_envelope_refuses_artifacts_without_units(tmp_path):
    """Version 1 predates data.units: one line saying how to re-run."""
    path = write_doc(tmp_path / "a.json", {**make_envelope("net"), "schema_version": 1})
    with pytest.raises(DgpcError) as err:
        load_envelope(path, "net")
    text = str(err.value)
    assert "\n" not in text and text.startswith(f"{path}: schema_version: 1 ")
    assert "data.units" in text and "re-run" in text and "dgpc init" in text
    assert "--units mm|cm|m|in|ft" in text


@pytest.mark.parametrize("drop, field", [("status", "status"), ("inputs", "inputs")])
def test_load_envelope_generic_missing_field(tmp_path, drop, field):
    doc = make_envelope("probe")
    del doc[drop]
    path = write_doc(tmp_path / "a.json", doc)
    with pytest.raises(DgpcError, match=rf"a.json: {field}: missing required field$"):
        load_envelope(path, "probe")


def test_load_envelope_bad_input_hash(tmp_path):
    doc = make_envelope("probe", inputs={"mesh": {"path": "x.obj", "sha256": "abc"}})
    path = write_doc(tmp_path / "a.json", doc)
    with pytest.raises(DgpcError, match=r"inputs\.mesh\.sha256"):
        load_envelope(path, "probe")


@pytest.mark.parametrize("text", ["/etc/passwd", "../x.obj", "a/../../x.obj", "..",
                                  "C:\\x.obj", "C:x.obj", "\\\\host\\share\\x.obj", "..\\x.obj",
                                  "", ".", None, 3])
def test_listed_path_refuses_a_file_outside_the_folder(tmp_path, text):
    with pytest.raises(DgpcError) as err:
        artifact_mod.listed_path(text, tmp_path / "a.json", "data.files.x")
    assert str(err.value).startswith(f"{tmp_path / 'a.json'}: data.files.x: ")


@pytest.mark.parametrize("text", ["a.obj", "sub/a.obj", "./a.obj"])
def test_listed_path_is_read_against_the_artifacts_folder(tmp_path, text, monkeypatch):
    monkeypatch.chdir(tmp_path.parent)
    path = artifact_mod.listed_path(text, Path(tmp_path.name) / "a.json", "data.obj")
    assert path == tmp_path.resolve() / Path(text)
