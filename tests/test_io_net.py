"""The net artifact: OBJ format, round trip, determinism, schema (valid and invalid cases)."""

import json

import numpy as np
import pytest
import trimesh

from dgpc_cli import __version__
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import load_envelope, sha256_bytes
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.obj import format_net_obj, parse_net_obj
from dgpc_cli.io.units import REACH_ULPS, stored


def grid(m=4, n=3, seed=0):
    rng = np.random.default_rng(seed)
    u, v = np.meshgrid(np.arange(m), np.arange(n), indexing="ij")
    return np.stack([u * 1.0, v * 1.0, 0.1 * np.sin(u + v)], axis=-1) + 1e-3 * rng.random((m, n, 3))


def net(f=None, **kw):
    return NetArtifact(f=grid() if f is None else f, parameters={"seed": 0}, **kw)


# OBJ ---------------------------------------------------------------------------------------
def test_format_net_obj_layout():
    f = grid(3, 2)
    lines = format_net_obj(f).decode().splitlines()
    assert lines[:3] == [f"# dgpc {__version__}", "# net 3 x 2, vertex u*n+v+1 is f(u, v)",
                         "o net"]
    vs = [line for line in lines if line.startswith("v ")]
    assert vs[1] == "v " + " ".join(repr(float(x)) for x in f[0, 1])  # u*n+v+1 = 2
    assert vs[4] == "v " + " ".join(repr(float(x)) for x in f[2, 0])  # 2*2+0+1 = 5
    faces = [line for line in lines if line.startswith("f ")]
    # (u,v),(u+1,v),(u+1,v+1),(u,v+1) for u=0, v=0 and u=1, v=0
    assert faces == ["f 1 3 4 2", "f 3 5 6 4"]


def test_format_parse_round_trip_is_exact():
    f = grid(5, 7) * np.pi * 1e3
    assert np.array_equal(parse_net_obj(format_net_obj(f), 5, 7, "x.obj"), f)


def test_net_obj_readable_by_mesh_tools():
    f = grid(4, 3)
    mesh = trimesh.load(trimesh.util.wrap_as_stream(format_net_obj(f)), file_type="obj",
                        process=False, force="mesh")
    assert np.allclose(mesh.vertices, f.reshape(-1, 3))
    assert len(mesh.faces) == 2 * 3 * 2  # quads triangulated
    normals = mesh.face_normals
    assert (normals[:, 2] > 0).all()  # (u,v),(u+1,v),(u+1,v+1): counterclockwise in x-y


def test_parse_tolerates_other_lines_and_columns():
    data = b"# c\nmtllib x.mtl\nv 0 0 0 1.0\nv 1 0 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\nv 0 1 0\n" \
           b"v 1 1 2\nf 1 2 4 3\n"
    f = parse_net_obj(data, 2, 2, "x.obj")
    assert f.shape == (2, 2, 3) and f[1, 1].tolist() == [1.0, 1.0, 2.0]


@pytest.mark.parametrize("data, m, n, message", [
    (b"# nothing\n", 2, 2, "no vertices"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", 2, 2, "3 vertices, but the net is 2 x 2 = 4"),
    (b"v 0 0 0\nv 1 0 0\nv 0 x 0\nv 1 1 0\n", 2, 2, "line 3: not a number"),
    (b"v 0 0 0\nv 1 0\n", 1, 2, "line 2: vertex needs 3 coordinates"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 nan 0\n", 2, 2, r"vertex 4 \(u, v\) = \(1, 1\)"),
    (b"v 0 0 0\nv 1 0 inf\nv 0 1 0\nv 1 1 0\n", 2, 2, r"vertex 2 \(u, v\) = \(0, 1\)"),
])
def test_parse_errors(data, m, n, message):
    with pytest.raises(DgpcError, match=message) as err:
        parse_net_obj(data, m, n, "dir/x.obj")
    assert str(err.value).startswith("dir/x.obj: ")


# write/read --------------------------------------------------------------------------------
def test_round_trip(tmp_path):
    src = net(data={"surface": {"name": "wave"}}, metrics={"R": np.float64(1e-12)},
              status={"converged": True}, inputs={})
    json_path, obj_path = write_net(tmp_path / "a", src)
    assert (json_path.name, obj_path.name) == ("a.json", "a.obj")
    back = read_net(tmp_path / "a.obj")
    # stored exactly as every unit gets it back: within a few ulps of the input
    assert np.array_equal(back.f, stored(src.f, "mm")) and back.shape == (4, 3)
    assert np.all(np.abs(back.f - src.f) <= REACH_ULPS * np.spacing(np.abs(src.f)))
    assert back.parameters == {"seed": 0} and back.metrics == {"R": 1e-12}
    assert back.data == {"surface": {"name": "wave"}, "shape": [4, 3], "geodesic_family": "u",
                         "units": "mm", "obj": "a.obj",
                         "obj_sha256": sha256_bytes(obj_path.read_bytes())}
    assert back.units == "mm"
    doc = json.loads(json_path.read_text())
    assert doc["kind"] == "net" and doc["schema_version"] == 2
    assert doc["created_by"] == f"dgpc {__version__}"


def test_write_is_deterministic(tmp_path):
    write_net(tmp_path / "a", net())
    write_net(tmp_path / "b", net())
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()
    a = json.loads((tmp_path / "a.json").read_text())
    b = json.loads((tmp_path / "b.json").read_text())
    assert a["data"].pop("obj") == "a.obj" and b["data"].pop("obj") == "b.obj"
    assert a == b
    first = (tmp_path / "a.json").read_bytes()
    write_net(tmp_path / "a", net(), force=True)
    assert (tmp_path / "a.json").read_bytes() == first


def test_write_refuses_existing(tmp_path):
    write_net(tmp_path / "a", net())
    with pytest.raises(DgpcError, match="already exists; use --force"):
        write_net(tmp_path / "a", net())


@pytest.mark.parametrize("f, message", [
    (np.zeros((1, 3, 3)), r"shape \(1, 3, 3\)"),
    (np.zeros((3, 3)), r"shape \(3, 3\)"),
    (np.where(np.arange(36).reshape(4, 3, 3) == 20, np.nan, 0.0),
     r"vertex \(u, v\) = \(2, 0\) has a non-finite"),
])
def test_write_rejects_bad_nets_and_writes_nothing(tmp_path, f, message):
    with pytest.raises(DgpcError, match=message):
        write_net(tmp_path / "a", net(f))
    assert list(tmp_path.iterdir()) == []


def test_write_rejects_bad_inputs_field(tmp_path):
    with pytest.raises(DgpcError, match=r"inputs\.mesh\.sha256"):
        write_net(tmp_path / "a", net(inputs={"mesh": {"path": "x", "sha256": "nope"}}))
    assert list(tmp_path.iterdir()) == []


def test_read_detects_edited_obj(tmp_path):
    _, obj_path = write_net(tmp_path / "a", net())
    obj_path.write_bytes(obj_path.read_bytes().replace(b"o net", b"o edited"))
    with pytest.raises(DgpcError, match=r"a\.obj: does not match a\.json \(edited separately\?\)"):
        read_net(tmp_path / "a")


def test_read_missing_obj(tmp_path):
    _, obj_path = write_net(tmp_path / "a", net())
    obj_path.unlink()
    with pytest.raises(DgpcError) as err:
        read_net(tmp_path / "a.json")
    assert err.value.source == str(obj_path) and "missing" in str(err.value)


def test_read_vertex_count_mismatch(tmp_path):
    json_path, obj_path = write_net(tmp_path / "a", net())
    doc = json.loads(json_path.read_text())
    doc["data"]["shape"] = [3, 3]
    json_path.write_text(json.dumps(doc))
    with pytest.raises(DgpcError, match="12 vertices, but the net is 3 x 3 = 9"):
        read_net(tmp_path / "a")


# schema ------------------------------------------------------------------------------------
def edit(tmp_path, change):
    json_path, _ = write_net(tmp_path / "a", net(inputs={}))
    doc = json.loads(json_path.read_text())
    change(doc)
    json_path.write_text(json.dumps(doc))
    return json_path


def test_schema_accepts_written_artifact(tmp_path):
    doc = load_envelope(edit(tmp_path, lambda d: None), "net")
    assert doc["data"]["shape"] == [4, 3]


def _set(path, value):
    def change(doc):
        *head, last = path
        target = doc
        for key in head:
            target = target[key]
        if value is KeyError:
            del target[last]
        else:
            target[last] = value
    return change


@pytest.mark.parametrize("path, value, message", [
    (["kind"], KeyError, "kind: missing required field"),
    (["kind"], "mold", "kind: is a 'mold' artifact, expected 'net'"),
    (["kind"], 3, "kind: must be 'net', got 3"),
    (["schema_version"], "1", "schema_version: must be of type integer"),
    (["schema_version"], 3, "schema_version: 3 is not supported"),
    (["schema_version"], 1, "schema_version: 1 is no longer read, it predates length units"),
    (["data", "units"], "km", r"data\.units: must be a length unit: mm, cm, m, in or ft"),
    (["data", "units"], KeyError, r"data\.units: missing required field"),
    (["created_by"], "me", "created_by: must be 'dgpc <version>'"),
    (["data", "shape"], [4], r"data\.shape: must have at least 2 items"),
    (["data", "shape"], [4, 3, 1], r"data\.shape: must have at most 2 items"),
    (["data", "shape"], [1, 12], r"data\.shape\[0\]: must be ≥ 2, got 1"),
    (["data", "shape"], [4, 3.5], r"data\.shape\[1\]: must be of type integer"),
    (["data", "shape"], KeyError, r"data\.shape: missing required field"),
    (["data", "geodesic_family"], "v", r"data\.geodesic_family: must be one of \[\"u\"\]"),
    (["data", "obj_sha256"], "ABC", r"data\.obj_sha256: must be a sha256"),
    (["data", "obj"], 5, r"data\.obj: must be of type string"),
    (["inputs"], {"mesh": {"path": "m.obj"}}, r"inputs\.mesh\.sha256: missing required field"),
    (["inputs"], {"mesh": "m.obj"}, r"inputs\.mesh: must be of type object"),
    (["parameters"], [], "parameters: must be of type object, got array"),
    (["metrics"], KeyError, "metrics: missing required field"),
    (["status"], None, "status: must be of type object, got null"),
])
def test_schema_rejects(tmp_path, path, value, message):
    json_path = edit(tmp_path, _set(path, value))
    with pytest.raises(DgpcError, match=message) as err:
        read_net(json_path)
    text = str(err.value)
    assert text.startswith(f"{json_path}: ") and "\n" not in text
