"""The mold artifact: JSON schema (valid and invalid), DXF profile (re-read, audit), reading."""

import copy
import json

import ezdxf
import numpy as np
import pytest
from cli_helpers import dgpc
from mold_samples import gehry_nets, write

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.jsonable import load_schema, validate
from dgpc_cli.io.mold import read_mold


@pytest.fixture(scope="module")
def mold(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mold")
    stem = write(folder / "g", gehry_nets()[1], units="m")
    dgpc("extract-mold", stem, "--panel-size", 2, "--mold-max-length", 1.3, "--expect-units", "m",
         "-o", folder / "mold")
    return folder / "mold"


def doc_of(stem):
    return json.loads(stem.with_suffix(".json").read_text())


def test_written_json_is_valid(mold):
    validate(doc_of(mold), load_schema("mold"), "mold.json")
    art = read_mold(mold)
    assert art.r.shape == art.h.shape == (21,)


@pytest.mark.parametrize("path, value, field", [
    (("kind",), "net", "kind"),
    (("data", "profile", "r", 3), -1.0, "data.profile.r[3]"),
    (("data", "profile", "x", 0), None, "data.profile.x[0]"),
    (("data", "panels", 0, "id"), "panel-1", "data.panels[0].id"),
    (("data", "panels", 0, "flat"), "yes", "data.panels[0].flat"),
    (("data", "pieces", 0, "rows"), [3], "data.pieces[0].rows"),
    (("data", "obj_sha256"), "abc", "data.obj_sha256"),
    (("metrics", "pieces"), -2, "metrics.pieces"),
])
def test_schema_rejects_invalid_documents(mold, path, value, field):
    doc = copy.deepcopy(doc_of(mold))
    node = doc
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    with pytest.raises(DgpcError) as err:
        validate(doc, load_schema("mold"), "mold.json")
    assert f"mold.json: {field}:" in str(err.value)


def test_schema_rejects_a_missing_field(mold):
    doc = doc_of(mold)
    del doc["data"]["panels"][0]["isometry_error"]
    with pytest.raises(DgpcError, match=r"data.panels\[0\].isometry_error: missing"):
        validate(doc, load_schema("mold"), "mold.json")


def test_profile_dxf_reads_back_in_mm_and_passes_audit(mold):
    doc = doc_of(mold)
    path = mold.parent / doc["data"]["files"]["profile_dxf"]["path"]
    dxf = ezdxf.readfile(path)
    assert dxf.dxfversion == "AC1024"                                     # R2010
    assert dxf.header["$INSUNITS"] == 4                                   # mm
    auditor = dxf.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    msp = dxf.modelspace()
    (poly,) = msp.query('LWPOLYLINE[layer=="PROFILE"]')
    pts = np.array([(p[0], p[1]) for p in poly.get_points("xy")])
    r, h = np.array(doc["data"]["profile"]["r"]), np.array(doc["data"]["profile"]["h"])
    assert np.allclose(pts, 1000.0 * np.column_stack([r, h]), rtol=0, atol=1e-9)   # m → mm
    assert not poly.closed
    (axis,) = msp.query('LWPOLYLINE[layer=="AXIS"]')
    (start, end) = np.array(axis.get_points("xy"))
    assert start[0] == end[0] == 0.0
    assert start[1] < pts[:, 1].min() and end[1] > pts[:, 1].max()
    assert dxf.layers.get("AXIS").dxf.linetype == "CENTER"
    pieces = doc["data"]["pieces"]
    # one tick per piece end; two pieces that meet share theirs (no line drawn twice)
    ends = {row for p in pieces for row in p["rows"]}
    ticks = msp.query('LWPOLYLINE[layer=="PIECES"]')
    assert len(ticks) == len(ends) < 2 * len(pieces)
    assert sorted(np.array(t.get_points("xy"))[0, 1] for t in ticks) == \
        pytest.approx(sorted(1000.0 * h[sorted(ends)]))
    assert sorted(t.dxf.text for t in msp.query("TEXT")) == [p["id"] for p in pieces]
    assert dxf.header["$EXTMAX"][1] >= 1000.0 * h.max()                  # extents set
    assert {t.dxf.layer for t in msp.query("TEXT")} == {"LABEL"}
    assert dxf.layers.get("LABEL").color == 3                             # green, not yellow


def test_profile_and_panel_csv(mold):
    doc = doc_of(mold)
    lines = (mold.parent / "mold.profile.csv").read_text().splitlines()
    assert lines[0] == "r,h" and len(lines) == 22
    assert [float(v) for v in lines[5].split(",")] == [doc["data"]["profile"]["r"][4],
                                                        doc["data"]["profile"]["h"][4]]
    rows = (mold.parent / "mold.panels.csv").read_text().splitlines()
    assert rows[0].startswith("id,net,piece,row_start,row_stop")
    assert len(rows) == 1 + len(doc["data"]["panels"])
    first = rows[1].split(",")
    panel = doc["data"]["panels"][0]
    assert first[0] == panel["id"] and first[2] == (panel["piece"] or "")
    assert first[-1] == str(int(panel["flat"]))
    # integer rows and columns, the isometry error as a number
    assert [int(v) for v in first[3:7]] == [*panel["rows"], *panel["cols"]]
    assert float(first[9]) == pytest.approx(panel["isometry_error"], rel=1e-3)


def test_panels_obj_groups_the_net_by_panel_id(mold):
    """MOLD.panels.obj: the input net, its faces grouped by panel id (a facade model shows
    which panel is which)."""
    from dgpc_cli.io.net import read_net

    doc = doc_of(mold)
    f = read_net(mold.parent / "g").f
    lines = (mold.parent / "mold.panels.obj").read_text().splitlines()
    assert [x for x in lines if x.startswith("o ")] == ["o net1"]
    verts = np.array([[float(v) for v in x.split()[1:]] for x in lines if x.startswith("v ")])
    assert np.array_equal(verts, f.reshape(-1, 3))
    groups, faces = {}, None
    for x in lines:
        if x.startswith("g "):
            faces = groups.setdefault(x[2:], [])
        elif x.startswith("f "):
            faces.append([int(i) - 1 for i in x.split()[1:]])
    panels = doc["data"]["panels"]
    assert list(groups) == [p["id"] for p in panels]
    n = f.shape[1]
    for p in panels:
        (r0, r1), (c0, c1) = p["rows"], p["cols"]
        corners = {(i // n, i % n) for face in groups[p["id"]] for i in face}
        assert corners == {(u, v) for u in range(r0, r1 + 1) for v in range(c0, c1 + 1)}


def test_reading_detects_edited_and_missing_files(mold, tmp_path):
    for name in mold.parent.iterdir():
        if name.name.startswith("mold"):
            (tmp_path / name.name).write_bytes(name.read_bytes())
    copy_stem = tmp_path / "mold"
    read_mold(copy_stem)
    obj = tmp_path / "mold.obj"
    obj.write_text(obj.read_text().replace("o sector", "o sector2"))
    with pytest.raises(DgpcError, match="mold.obj: does not match mold.json"):
        read_mold(copy_stem)
    res = dgpc("inspect", copy_stem, expect=1)
    assert "mold.obj" in res.stderr
    obj.write_bytes((mold.parent / "mold.obj").read_bytes())
    (tmp_path / "mold.profile.dxf").unlink()
    with pytest.raises(DgpcError, match=r"mold.profile.dxf: missing.*data.files.profile_dxf"):
        read_mold(copy_stem)


def test_reading_checks_consistency(mold, tmp_path):
    doc = doc_of(mold)
    doc["data"]["profile"]["h"] = doc["data"]["profile"]["h"][:-1]
    path = tmp_path / "mold.json"
    path.write_text(json.dumps(doc))
    res = dgpc("inspect", path, expect=1)
    assert "data.profile.h: 20 values, expected 21" in res.stderr
    doc = doc_of(mold)
    doc["data"]["panels"][0]["piece"] = "M99"
    doc["data"]["panels"][0]["flat"] = False
    path.write_text(json.dumps(doc))
    res = dgpc("inspect", path, expect=1)
    assert "data.panels[0].piece: 'M99' is not a mold piece" in res.stderr
