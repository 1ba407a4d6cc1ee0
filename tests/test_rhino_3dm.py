"""Issue 7 item 5: `--format 3dm` writes STEM.3dm beside the artifact (Rhino, mm, named layers).

Read back with rhino3dm: layers, object counts and names, millimeters, and coordinates equal to
the artifact's (after the mm scale) within 1e-9. A net m×n gives one mesh of (m−1)(n−1) quads
on layer "net" and n geodesic polylines (every u-line f[:, v]) on layer "geodesics".
"""

import json

import numpy as np
import pytest
import rhino3dm
from cli_helpers import dgpc

from dgpc_cli.io.artifact import sha256_file
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.mold import read_mold
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.obj import net_quads
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.io.strips import read_strips
from dgpc_cli.nesting.geometry import transform
from dgpc_cli.surfaces.minding import minding_bend

TOL = 1e-9
ROWS, COLS = 9, 6
SCALE = 100.0


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rhino")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", ROWS, "--cols",
         COLS, "--span", 360, "-o", folder / "cat", "--format", "3dm")
    write_net(folder / "iso", NetArtifact(f=minding_bend(read_net(folder / "cat").f, 0.7)))
    dgpc("planarize-strips", folder / "iso", "-o", folder / "s", "--format", "3dm")
    dgpc("unfold", folder / "s", "-o", folder / "flat", "--format", "3dm")
    dgpc("extract-mold", folder / "iso", "--unit", "cm", "-o", folder / "mold", "--format", "3dm")
    dgpc("nest", folder / "flat", "--sheet", "700x500", "--scale", SCALE, "-o", folder / "sh",
         "--format", "3dm")
    return folder


def _read(folder, stem):
    """The 3dm of an artifact, after checking that the JSON lists it (path, sha256)."""
    doc = json.loads((folder / f"{stem}.json").read_text())
    record = doc["data"]["rhino_3dm"]
    assert record["path"] == f"{stem}.3dm"
    assert record["sha256"] == sha256_file(folder / f"{stem}.3dm")
    assert (folder / f"{stem}.obj").exists()                  # the OBJ is still written
    model = rhino3dm.File3dm.Read(str(folder / f"{stem}.3dm"))
    assert model is not None
    assert model.Settings.ModelUnitSystem == rhino3dm.UnitSystem.Millimeters
    return model


def _objects(model, layer):
    index = {ly.Name: ly.Index for ly in model.Layers}[layer]
    return [o for o in model.Objects if o.Attributes.LayerIndex == index]


def _layers(model):
    return {ly.Name for ly in model.Layers}


def _mesh_vertices(mesh):
    """The vertices in double precision (``Vertices[i]`` gives the single-precision copy)."""
    return np.array([[p.X, p.Y, p.Z] for p in (mesh.Vertices.Point3dAt(i) for i in
                                              range(len(mesh.Vertices)))])


def _mesh_faces(mesh):
    return np.array([list(mesh.Faces[i]) for i in range(len(mesh.Faces))])


def _curve_points(curve):
    return np.array([[p.X, p.Y, p.Z] for p in (curve.Point(i) for i in
                                              range(curve.PointCount))])


def test_net(sample):
    model = _read(sample, "cat")
    f = read_net(sample / "cat").f
    assert {"net", "geodesics"} <= _layers(model)
    (mesh,) = _objects(model, "net")
    assert mesh.Geometry.ObjectType == rhino3dm.ObjectType.Mesh
    assert len(mesh.Geometry.Faces) == (ROWS - 1) * (COLS - 1)
    assert np.abs(_mesh_vertices(mesh.Geometry) - f.reshape(-1, 3)).max() < TOL
    faces = _mesh_faces(mesh.Geometry)
    assert faces.shape == ((ROWS - 1) * (COLS - 1), 4)
    assert (faces == net_quads(ROWS, COLS)).all()
    geod = _objects(model, "geodesics")
    assert [o.Attributes.Name for o in geod] == [f"u-v{v:02d}" for v in range(COLS)]
    for v, obj in enumerate(geod):
        assert np.abs(_curve_points(obj.Geometry) - f[:, v]).max() < TOL


def test_strips(sample):
    model = _read(sample, "s")
    strips = read_strips(sample / "s")
    meshes = _objects(model, "strips")
    assert [o.Attributes.Name for o in meshes] == [r["id"] for r in strips.records]
    assert meshes[0].Attributes.Name.startswith("S-v")
    for obj, (A, B) in zip(meshes, strips.geometry, strict=True):
        grid = np.stack([A, B], axis=1).reshape(-1, 3)
        assert np.abs(_mesh_vertices(obj.Geometry) - grid).max() < TOL
        assert len(obj.Geometry.Faces) == len(A) - 1


def test_flat(sample):
    model = _read(sample, "flat")
    parts = read_flat(sample / "flat").parts
    assert {"flat-parts", "score", "labels"} <= _layers(model)
    outlines = _objects(model, "flat-parts")
    assert [o.Attributes.Name for o in outlines] == [p["id"] for p in parts]
    for obj, part in zip(outlines, parts, strict=True):
        pts = _curve_points(obj.Geometry)
        outline = np.asarray(part["outline"])
        assert obj.Geometry.IsClosed
        assert np.abs(pts[:-1, :2] - outline).max() < TOL and np.abs(pts[:, 2]).max() == 0
    score = _objects(model, "score")
    assert len(score) == sum(len(p["score"]) for p in parts)
    first = [o for o in score if o.Attributes.Name == f"{parts[0]['id']}/score"]
    for obj, line in zip(first, parts[0]["score"], strict=True):
        assert np.abs(_curve_points(obj.Geometry)[:, :2] - np.asarray(line)).max() < TOL
    dots = _objects(model, "labels")
    assert [d.Geometry.Text for d in dots] == [p["id"] for p in parts]
    for dot, part in zip(dots, parts, strict=True):
        pt = dot.Geometry.Point
        assert np.abs(np.array([pt.X, pt.Y]) - np.asarray(part["label"])).max() < TOL


def test_sheets(sample):
    model = _read(sample, "sh")
    sheets = read_sheets(sample / "sh")
    parts = {p["id"]: p for p in read_flat(sample / "flat").parts}
    data = sheets.data
    W = data["sheet"]["width"]
    names = {f"sheet{s + 1:02d}" for s in range(data["sheet_count"])}
    assert names <= _layers(model)
    for sheet in data["sheets"]:
        s = sheet["index"]
        objs = _objects(model, f"sheet{s + 1:02d}")
        outline = [o for o in objs if o.Attributes.Name == sheet["id"]]
        assert len(outline) == 1
        dx = np.array([s * 1.1 * W, 0.0])
        for pl in (p for p in data["placements"] if p["sheet"] == s):
            part = parts[pl["part"]]
            (obj,) = [o for o in objs if o.Attributes.Name == pl["part"]]
            want = transform(SCALE * np.asarray(part["outline"]), pl["rotation"],
                             pl["translation"]) + dx
            assert np.abs(_curve_points(obj.Geometry)[:-1, :2] - want).max() < TOL * SCALE
            assert len([o for o in objs if o.Attributes.Name == f"{pl['part']}/score"]) \
                == len(part["score"])
            (dot,) = [o for o in objs if o.Attributes.Name == f"{pl['part']}/label"]
            assert dot.Geometry.Text == pl["part"]
        assert len(objs) == 1 + sum(2 + len(parts[p]["score"]) for p in sheet["parts"])


def test_mold(sample):
    model = _read(sample, "mold")
    mold = read_mold(sample / "mold")
    (surface,) = _objects(model, "mold-surface")
    (sector,) = _objects(model, "mold-sector")
    rows, cols = mold.data["rows"], mold.data["surface"]["columns"]
    assert len(surface.Geometry.Faces) == (rows - 1) * (cols - 1)
    v = _mesh_vertices(surface.Geometry).reshape(rows, cols, 3)
    # column 0 of the surface at angle 0: (r, 0, h) in cm, scaled to mm
    assert np.abs(v[:, 0, 0] - 10 * np.asarray(mold.r)).max() < TOL * 10
    assert np.abs(v[:, 0, 2] - 10 * np.asarray(mold.h)).max() < TOL * 10
    assert len(sector.Geometry.Faces) == (rows - 1) * (mold.data["sector"]["columns"] - 1)


def test_obj_only_by_default(sample, tmp_path):
    dgpc("unfold", sample / "s", "-o", tmp_path / "flat")
    assert not (tmp_path / "flat.3dm").exists()
    assert "rhino_3dm" not in json.loads((tmp_path / "flat.json").read_text())["data"]
    assert (tmp_path / "flat.json").read_bytes() != b""


def test_ids_deterministic(sample, tmp_path):
    dgpc("unfold", sample / "s", "-o", tmp_path / "flat", "--format", "3dm")
    a = rhino3dm.File3dm.Read(str(tmp_path / "flat.3dm"))
    b = rhino3dm.File3dm.Read(str(sample / "flat.3dm"))
    assert [o.Attributes.Id for o in a.Objects] == [o.Attributes.Id for o in b.Objects]
    assert len({o.Attributes.Id for o in a.Objects}) == len(a.Objects)


def test_laths_model_layers():
    from dgpc_cli.io.rhino import laths_model

    pts = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.25], [2.0, 1.0, 1.0 / 3.0]])
    model = laths_model([("A1", "A", pts), ("B1", "B", pts + 1.0)]).file
    assert model.Settings.ModelUnitSystem == rhino3dm.UnitSystem.Millimeters
    (a,) = _objects(model, "laths-A")
    (b,) = _objects(model, "laths-B")
    assert (a.Attributes.Name, b.Attributes.Name) == ("A1", "B1")
    assert np.abs(_curve_points(b.Geometry) - (pts + 1.0)).max() < TOL
