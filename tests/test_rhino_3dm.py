"""Issues 7 and 14: `--format 3dm` writes STEM.3dm beside the artifact (Rhino, the artifact's
unit, layers and sublayers, user text on every object).

Read back with rhino3dm: the unit system, layers and sublayers, object counts and names, user
text, and coordinates equal to the artifact's within 1e-9. A net m×n gives one mesh of
(m−1)(n−1) quads on layer "Net" and n geodesic polylines (every u-line f[:, v]) on layer
"Geodesics"; flat parts lie side by side, none on another; the mold's panels are meshes named
by their ids.
"""

import json
import struct

import numpy as np
import pytest
import rhino3dm
from cli_helpers import dgpc
from shapely.geometry import Point, Polygon

from dgpc_cli.io.artifact import sha256_file
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.mold import read_mold
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.obj import net_quads
from dgpc_cli.io.sheets import read_sheets, transform
from dgpc_cli.io.strips import read_strips
from dgpc_cli.surfaces.minding import minding_bend

TOL = 1e-9
ROWS, COLS = 9, 6
SCALE = 100.0
CM = rhino3dm.UnitSystem.Centimeters


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    """A catenoid net in cm, bent isometrically; strips, flat parts, mold and sheets."""
    folder = tmp_path_factory.mktemp("rhino")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", ROWS, "--cols",
         COLS, "--span", 360, "--units", "cm", "-o", folder / "cat", "--format", "3dm")
    write_net(folder / "iso", NetArtifact(f=minding_bend(read_net(folder / "cat").f, 0.7),
                                          units="cm"))
    dgpc("planarize-strips", folder / "iso", "-o", folder / "s", "--format", "3dm")
    dgpc("unfold", folder / "s", "-o", folder / "flat", "--format", "3dm")
    dgpc("extract-mold", folder / "iso", "-o", folder / "mold", "--format", "3dm")
    dgpc("nest", folder / "flat", "--sheet", "7000x5000", "--scale", SCALE, "-o", folder / "sh",
         "--format", "3dm")
    return folder


def _read(folder, stem, unit=CM):
    """The 3dm of an artifact, after checking that the JSON lists it (path, sha256), its unit
    system, and that every object carries user text (its id and the artifact's kind)."""
    doc = json.loads((folder / f"{stem}.json").read_text())
    record = doc["data"]["rhino_3dm"]
    assert record["path"] == f"{stem}.3dm"
    assert record["sha256"] == sha256_file(folder / f"{stem}.3dm")
    assert (folder / f"{stem}.obj").exists()                  # the OBJ is still written
    model = rhino3dm.File3dm.Read(str(folder / f"{stem}.3dm"))
    assert model is not None
    assert model.Settings.ModelUnitSystem == unit
    assert len(model.Objects) > 0
    for o in model.Objects:
        text = _user(o)
        assert text["kind"] == doc["kind"] and text["id"] == o.Attributes.Name, text
    return model


def _user(obj):
    return dict(obj.Attributes.GetUserStrings())


def _objects(model, layer):
    """The objects on the layer of full path ``layer`` (e.g. ``Sheet01::CUT``)."""
    index = {ly.FullPath: ly.Index for ly in model.Layers}[layer]
    return [o for o in model.Objects if o.Attributes.LayerIndex == index]


def _layers(model):
    return {ly.FullPath for ly in model.Layers}


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
    assert {"Net", "Geodesics"} <= _layers(model)
    (mesh,) = _objects(model, "Net")
    assert mesh.Geometry.ObjectType == rhino3dm.ObjectType.Mesh
    assert len(mesh.Geometry.Faces) == (ROWS - 1) * (COLS - 1)
    assert np.abs(_mesh_vertices(mesh.Geometry) - f.reshape(-1, 3)).max() < TOL
    faces = _mesh_faces(mesh.Geometry)
    assert faces.shape == ((ROWS - 1) * (COLS - 1), 4)
    assert (faces == net_quads(ROWS, COLS)).all()
    geod = _objects(model, "Geodesics")
    assert [o.Attributes.Name for o in geod] == [f"u-v{v:02d}" for v in range(COLS)]
    for v, obj in enumerate(geod):
        assert np.abs(_curve_points(obj.Geometry) - f[:, v]).max() < TOL
        assert _user(obj)["column"] == str(v)


def test_strips(sample):
    model = _read(sample, "s")
    strips = read_strips(sample / "s")
    ids = [r["id"] for r in strips.records]
    assert {"Strips", *(f"Strips::{i}" for i in ids)} <= _layers(model)    # a sublayer each
    for rec, (A, B) in zip(strips.records, strips.geometry, strict=True):
        (obj,) = _objects(model, f"Strips::{rec['id']}")
        assert obj.Attributes.Name == rec["id"] and rec["id"].startswith("S-v")
        grid = np.stack([A, B], axis=1).reshape(-1, 3)
        assert np.abs(_mesh_vertices(obj.Geometry) - grid).max() < TOL
        assert len(obj.Geometry.Faces) == len(A) - 1
        assert float(_user(obj)["width"]) == pytest.approx(rec["width"], rel=1e-5)


def test_flat(sample):
    model = _read(sample, "flat")
    parts = read_flat(sample / "flat").parts
    assert {"Flat::CUT", "Flat::SCORE", "Flat::LABEL"} <= _layers(model)
    outlines = _objects(model, "Flat::CUT")
    assert [o.Attributes.Name for o in outlines] == [p["id"] for p in parts]
    polygons = []
    for obj, part in zip(outlines, parts, strict=True):
        pts = _curve_points(obj.Geometry)
        info = _user(obj)
        shift = np.array([float(v) for v in info["place"].split(",")])
        assert obj.Geometry.IsClosed
        assert np.abs(pts[:-1, :2] - (np.asarray(part["outline"]) + shift)).max() < TOL
        assert np.abs(pts[:, 2]).max() == 0
        assert info["class"] == part["class"]
        assert float(info["length"]) == pytest.approx(part["length"], rel=1e-5)
        assert float(info["width_max"]) == pytest.approx(part["width"][1], rel=1e-5)
        polygons.append(Polygon(pts[:-1, :2]))
    for i in range(len(polygons)):                 # side by side, never on top of each other
        for j in range(i + 1, len(polygons)):
            assert polygons[i].distance(polygons[j]) > 0
    score = _objects(model, "Flat::SCORE")
    assert len(score) == sum(len(p["score"]) for p in parts)
    dots = _objects(model, "Flat::LABEL")
    assert [d.Geometry.Text for d in dots] == [p["id"] for p in parts]
    for dot, poly in zip(dots, polygons, strict=True):
        assert poly.contains(Point(dot.Geometry.Point.X, dot.Geometry.Point.Y))


def test_sheets(sample):
    model = _read(sample, "sh", rhino3dm.UnitSystem.Millimeters)
    sheets = read_sheets(sample / "sh")
    parts = {p["id"]: p for p in read_flat(sample / "flat").parts}
    data = sheets.data
    W = data["sheet"]["width"]
    k = data["sheet"]["mm_per_unit"]
    assert k == SCALE * 10.0                                       # cm, times the scale
    for sheet in data["sheets"]:
        s = sheet["index"]
        layer = f"Sheet{s + 1:02d}"
        assert {f"{layer}::{n}" for n in ("SHEET", "CUT", "SCORE", "LABEL")} <= _layers(model)
        (outline,) = _objects(model, f"{layer}::SHEET")
        assert outline.Attributes.Name == sheet["id"]
        cut = _objects(model, f"{layer}::CUT")
        assert sorted(o.Attributes.Name for o in cut) == sheet["parts"]
        dx = np.array([s * 1.1 * W, 0.0])
        for pl in (p for p in data["placements"] if p["sheet"] == s):
            part = parts[pl["part"]]
            (obj,) = [o for o in cut if o.Attributes.Name == pl["part"]]
            want = transform(k * np.asarray(part["outline"]), pl["rotation"],
                             pl["translation"]) + dx
            assert np.abs(_curve_points(obj.Geometry)[:-1, :2] - want).max() < TOL * k
            assert _user(obj)["sheet"] == sheet["id"] and _user(obj)["class"] == part["class"]
            assert len([o for o in _objects(model, f"{layer}::SCORE")
                        if o.Attributes.Name == f"{pl['part']}/score"]) == len(part["score"])
            (dot,) = [o for o in _objects(model, f"{layer}::LABEL")
                      if o.Attributes.Name == f"{pl['part']}/label"]
            assert dot.Geometry.Text == pl["label"]["text"] == pl["part"]


def test_mold(sample):
    model = _read(sample, "mold")
    mold = read_mold(sample / "mold")
    (surface,) = _objects(model, "Mold::surface")
    (sector,) = _objects(model, "Mold::sector")
    rows, cols = mold.data["rows"], mold.data["surface"]["columns"]
    assert len(surface.Geometry.Faces) == (rows - 1) * (cols - 1)
    v = _mesh_vertices(surface.Geometry).reshape(rows, cols, 3)
    # column 0 of the surface at angle 0: (r, 0, h) in the nets' unit (cm), as stored
    assert np.abs(v[:, 0, 0] - np.asarray(mold.r)).max() < TOL
    assert np.abs(v[:, 0, 2] - np.asarray(mold.h)).max() < TOL
    assert len(sector.Geometry.Faces) == (rows - 1) * (mold.data["sector"]["columns"] - 1)
    # every panel of the net: a mesh named by its id on the net's sublayer, with its piece
    f = read_net(sample / "iso").f
    panels = _objects(model, "Panels::net1")
    assert [o.Attributes.Name for o in panels] == [p["id"] for p in mold.data["panels"]]
    for obj, p in zip(panels, mold.data["panels"], strict=True):
        (r0, r1), (c0, c1) = p["rows"], p["cols"]
        want = f[r0:r1 + 1, c0:c1 + 1].reshape(-1, 3)
        got = _mesh_vertices(obj.Geometry)
        assert got.shape == want.shape
        assert np.abs(np.sort(got, axis=0) - np.sort(want, axis=0)).max() < TOL
        assert _user(obj)["piece"] == (p["piece"] or "none (flat)")


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
    model = laths_model([("A1", "A", pts), ("B1", "B", pts + 1.0)], "ft").file
    assert model.Settings.ModelUnitSystem == rhino3dm.UnitSystem.Feet
    (a,) = _objects(model, "Laths::A")
    (b,) = _objects(model, "Laths::B")
    assert (a.Attributes.Name, b.Attributes.Name) == ("A1", "B1")
    assert np.abs(_curve_points(b.Geometry) - (pts + 1.0)).max() < TOL
    assert _user(a)["family"] == "A"
    assert float(_user(a)["length"]) == pytest.approx(
        np.linalg.norm(np.diff(pts, axis=0), axis=1).sum(), rel=1e-5)


def test_bytes_depend_on_the_content_only(sample, tmp_path):
    """Issue 39: a run into another folder at another moment writes the same .3dm bytes and so
    the same JSON (it records the .3dm's sha256): no write time (the revision history reads
    2000-01-01, the fixed time), no temporary path inside."""
    (tmp_path / "deeper").mkdir()
    for folder in (tmp_path, tmp_path / "deeper"):
        for name in ("s.json", "s.obj"):
            (folder / name).write_bytes((sample / name).read_bytes())
        dgpc("unfold", folder / "s", "-o", folder / "flat", "--format", "3dm")
    for name in ("flat.3dm", "flat.json"):
        assert (tmp_path / name).read_bytes() == (tmp_path / "deeper" / name).read_bytes()
    assert (tmp_path / "flat.3dm").read_bytes() == (sample / "flat.3dm").read_bytes()
    blob = (tmp_path / "flat.3dm").read_bytes()
    assert b"dgpc-3dm" not in blob and str(tmp_path).encode() not in blob
    assert str(tmp_path).encode("utf-16-le") not in blob
    model = rhino3dm.File3dm.Read(str(tmp_path / "flat.3dm"))
    assert str(model.Created) == str(model.LastEdited) == "2000-01-01 00:00:00"


def test_fixed_times_patches_only_a_well_formed_archive():
    from dgpc_cli.errors import DgpcError
    from dgpc_cli.io.rhino import net_model
    from dgpc_cli.io.rhino_archive import FIXED_TIME, fixed_times

    model = net_model(np.zeros((3, 3, 3)) + np.arange(3)[:, None, None], "m")
    blob = model.to_bytes()
    assert fixed_times(blob) == blob                       # already fixed: a no-op
    assert len(blob) > 1000 and struct_times(blob) == [FIXED_TIME, FIXED_TIME]
    with pytest.raises(DgpcError, match="no 3dm header"):
        fixed_times(b"not a 3dm" + blob)
    spoiled = bytearray(blob)
    offset = blob.index(struct.pack("<8i", *FIXED_TIME))
    spoiled[offset] ^= 1                                    # the CRC no longer matches
    with pytest.raises(DgpcError, match="CRC does not match"):
        fixed_times(bytes(spoiled))


def struct_times(blob: bytes) -> list[tuple[int, ...]]:
    """The 8-int times found in ``blob`` at the fixed time's bytes (both of the history)."""
    from dgpc_cli.io.rhino_archive import FIXED_TIME

    packed = struct.pack("<8i", *FIXED_TIME)
    found, start = [], 0
    while (at := blob.find(packed, start)) >= 0:
        found.append(struct.unpack_from("<8i", blob, at))
        start = at + 1
    return found
