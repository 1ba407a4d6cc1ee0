"""Cutting templates (issue "Strips that build the design", items 3 and 4): congruence within a
length in the shop's unit (default 0.5 mm) whatever the order of the parts, a cut list with one
line per template, one DXF per template, the copies nested each with its own id; and the unit
traps of `unfold` (lengths with units, warnings on an implausible scale)."""

import csv
import json
import random

import ezdxf
import numpy as np
import pytest
from cli_helpers import dgpc, revolution_strips
from dxf_checks import END_MARK, check_cam_ready

from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.io.strips import read_strips, strips_files
from dgpc_cli.nesting.labels import short_id
from dgpc_cli.stages.unfold import unfold_strips
from dgpc_cli.strips.congruence import align, congruence_classes

#: How much (mm) the end of side B of strip v is lengthened: a chain of parts 0.3 mm apart, so
#: that which parts share a class depends on the order a greedy grouping meets them.
STRETCH_MM = [0.0, 0.3, 0.6, 0.9, 1.2, 1.5]


def _stretched(strips, stretch_mm):
    """The strips with the last vertex of side B of strip v moved ``stretch_mm[v]`` along
    its last edge (it stays in the plane of its quad: the strip stays planar)."""
    k = {"m": 1000.0, "mm": 1.0}[strips.units]
    geometry = []
    for (A, B), s in zip(strips.geometry, stretch_mm, strict=True):
        B = np.array(B, float)
        e = B[-1] - B[-2]
        B[-1] += (s / k) * e / np.linalg.norm(e)
        geometry.append((np.array(A, float), B))
    strips.geometry = geometry
    return strips


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """A 9×7 cone net in metres (six congruent strips), its strips stretched by STRETCH_MM."""
    d = tmp_path_factory.mktemp("templates")
    strips = revolution_strips(d, "cone", 9, 7, 60, "m", net="cone")
    write_files(strips_files(d / "chain", _stretched(read_strips(strips), STRETCH_MM)))
    dgpc("unfold", d / "chain", "-o", d / "flat")
    return d


def _mm_geodesics(part, units="m"):
    k = {"m": 1000.0, "mm": 1.0}[units]
    return tuple(k * np.asarray(g, float) for g in part["geodesics"])


def _partition(flat):
    return {frozenset(c["members"]) for c in flat.classes}


def test_every_two_copies_of_a_template_agree_within_half_a_millimetre(chain):
    """The default tolerance is 0.5 mm on strips in metres (not a fraction of their 3.9 m:
    1e-3 of it, 3.9 mm, would have made one class); deviations recorded in mm."""
    flat = read_flat(chain / "flat")
    assert flat.units == "m" and flat.parameters["congruence_tol_mm"] == 0.5
    parts = {p["id"]: p for p in flat.parts}
    assert 2 <= len(flat.classes) <= 4
    for c in flat.classes:
        members = [_mm_geodesics(parts[i]) for i in c["members"]]
        for a in members:
            for b in members:
                assert align(*a, *b).error <= 0.5 + 1e-9
        rep = _mm_geodesics(parts[c["representative"]])
        devs = [align(*m, *rep).error for m in members]
        assert c["max_deviation_mm"] == pytest.approx(max(devs), abs=1e-9)
        for i, dev in zip(c["members"], devs, strict=True):
            assert parts[i]["alignment"]["deviation_mm"] == pytest.approx(dev, abs=1e-9)
    # strips farther apart than 0.5 mm are in different classes
    ends = {i: STRETCH_MM[int(i[3:])] for i in parts}
    assert any(max(ends[i] for i in c["members"]) - min(ends[i] for i in c["members"]) > 0
               for c in flat.classes)


def test_tolerance_with_a_unit_or_in_the_strips_unit(chain, tmp_path):
    dgpc("unfold", chain / "chain", "--congruence-tol", "2mm", "-o", tmp_path / "mm")
    dgpc("unfold", chain / "chain", "--congruence-tol", "0.002", "-o", tmp_path / "m")
    in_mm, in_m = read_flat(tmp_path / "mm"), read_flat(tmp_path / "m")
    assert _partition(in_mm) == _partition(in_m) == {frozenset(p["id"] for p in in_m.parts)}
    assert in_m.parameters["congruence_tol_mm"] == in_mm.parameters["congruence_tol_mm"] == 2.0
    assert in_m.classes[0]["max_deviation_mm"] <= 2.0


def test_classes_do_not_depend_on_the_order_of_the_parts(chain):
    """Shuffled parts give the same classes and representatives (a greedy grouping that lets
    each part join the first class it matches splits this chain differently by order)."""
    strips = read_strips(chain / "chain")
    geometry = [(1000.0 * np.asarray(A), 1000.0 * np.asarray(B)) for A, B in strips.geometry]
    ids = [r["id"] for r in strips.records]
    cols = [r["v"] for r in strips.records]

    def run(order):
        _, classes, _ = unfold_strips([geometry[i] for i in order], [ids[i] for i in order],
                                      [cols[i] for i in order], congruence_tol=0.5)
        return {(frozenset(c["members"]), c["representative"]) for c in classes}

    reference = run(list(range(len(ids))))
    rng = random.Random(7)
    for _ in range(8):
        order = list(range(len(ids)))
        rng.shuffle(order)
        assert run(order) == reference
    # the same on the developed parts directly, with a tolerance that chains them
    flat = read_flat(chain / "flat")
    parts = [_mm_geodesics(p) for p in flat.parts]
    names = [p["id"] for p in flat.parts]
    first = None
    for _ in range(8):
        order = list(range(len(parts)))
        rng.shuffle(order)
        classes = congruence_classes([parts[i] for i in order], 0.35, [names[i] for i in order])
        got = {frozenset(names[order[i]] for i in c.members) for c in classes}
        first = first or got
        assert got == first


def test_cut_list_one_line_per_template_and_quantities_add_up(chain):
    flat = read_flat(chain / "flat")
    rows = list(csv.DictReader((chain / "flat.parts.csv").open()))
    assert [r["class"] for r in rows] == [c["id"] for c in flat.classes]
    copies = [i for r in rows for i in r["parts"].split()]
    assert sorted(copies) == sorted(p["id"] for p in flat.parts)          # each part once
    assert sum(int(r["quantity"]) for r in rows) == len(flat.parts)
    for r, c in zip(rows, flat.classes, strict=True):
        assert int(r["quantity"]) == len(r["parts"].split()) == c["quantity"]
        assert r["representative"] in r["parts"].split()
        assert float(r["max_deviation_mm"]) == pytest.approx(c["max_deviation_mm"], abs=1e-3)
        rep = flat.part(r["representative"])
        assert float(r["length_mm"]) == pytest.approx(1000.0 * rep["length"], abs=1e-3)
    assembly = list(csv.DictReader((chain / "flat.assembly.csv").open()))
    assert [(a["id"], a["class"]) for a in assembly] == [(p["id"], p["class"])
                                                         for p in flat.parts]


def test_one_dxf_per_template_reads_back_to_its_representative(chain):
    flat = read_flat(chain / "flat")
    rows = {r["class"]: r for r in csv.DictReader((chain / "flat.parts.csv").open())}
    doc_files = json.loads((chain / "flat.json").read_text())["data"]["files"]
    for c in flat.classes:
        name = rows[c["id"]]["dxf"]
        assert doc_files[f"template_{c['id']}_dxf"]["path"] == name == f"flat.{c['id']}.dxf"
        doc = ezdxf.readfile(chain / name)
        assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
        assert not doc.audit().has_errors
        msp = doc.modelspace()
        cuts = msp.query("LWPOLYLINE[layer=='CUT']")
        assert len(cuts) == 1 and cuts[0].closed
        outline = np.array([p[:2] for p in cuts[0].get_points("xy")])
        rep = 1000.0 * np.asarray(flat.part(c["representative"])["outline"], float)
        assert np.abs(outline - (rep - rep.min(axis=0))).max() <= 1e-6       # mm
        scores = msp.query("LWPOLYLINE[layer=='SCORE']")
        assert len(scores) == len(flat.part(c["representative"])["score"])
        # labelled as on a sheet: the class and its quantity, then every copy's id once
        texts = [t.dxf.text for t in msp.query("TEXT") if not END_MARK.fullmatch(t.dxf.text)]
        assert texts[0] == f"{c['id']} x{c['quantity']}"
        assert " ".join(texts[1:]).split() == c["members"]
        assert {e.dxf.layer for e in msp} <= {"CUT", "SCORE", "LABEL"}
        assert check_cam_ready(chain / name)["CUT:LWPOLYLINE"] == 1


def test_template_dxfs_take_the_label_style_and_layers_of_the_sheets(chain, tmp_path):
    """``unfold --label-style stroke``: the labels as single strokes on ENGRAVE, as ``nest
    --label-style stroke`` draws a sheet (the same layer table), inside the part clear of
    every cut and score line; the geometry is that of the text style's drawing."""
    dgpc("unfold", chain / "chain", "--label-style", "stroke", "-o", tmp_path / "flat")
    dgpc("nest", tmp_path / "flat", "--sheet", "6100x2500", "--label-style", "stroke",
         "--no-preview", "-o", tmp_path / "sheets")
    flat = read_flat(tmp_path / "flat")
    assert flat.parameters["label_style"] == "stroke"
    sheet = ezdxf.readfile(tmp_path / "sheets.sheet01.dxf")
    sheet_layers = {(la.dxf.name, la.dxf.color, la.dxf.plot) for la in sheet.layers}
    for c in flat.classes:
        doc = ezdxf.readfile(tmp_path / f"flat.{c['id']}.dxf")
        assert {(la.dxf.name, la.dxf.color, la.dxf.plot) for la in doc.layers} == sheet_layers
        msp = doc.modelspace()
        assert not msp.query("TEXT") and msp.query("LWPOLYLINE[layer=='ENGRAVE']")
        summary = check_cam_ready(tmp_path / f"flat.{c['id']}.dxf")
        assert summary["CUT:LWPOLYLINE"] == 1
        text = ezdxf.readfile(chain / f"flat.{c['id']}.dxf").modelspace()
        for layer in ("CUT", "SCORE"):
            assert [e.get_points("xy") for e in msp.query(f"LWPOLYLINE[layer=='{layer}']")] == \
                [e.get_points("xy") for e in text.query(f"LWPOLYLINE[layer=='{layer}']")]
        # every stroke lies inside the part's outline (no leader needed on these parts)
        from shapely.geometry import LineString, Polygon

        (cut,) = msp.query("LWPOLYLINE[layer=='CUT']")
        part = Polygon(cut.get_points("xy"))
        for e in msp.query("LWPOLYLINE[layer=='ENGRAVE']"):
            assert part.contains(LineString(e.get_points("xy")))


def test_template_labels_fit_the_cells_of_the_part():
    """A class of 12 copies on a part of 20 cells: the class line and 3 lines of 4 ids; on a
    part of 3 cells, 2 lines of 6 ids; on one cell, one line of everything. The runs of
    cells cover the part in order, each around one of the longest cells."""
    from dgpc_cli.nesting.template import cell_runs, template_texts

    cls = {"id": "C01", "quantity": 12, "members": [f"S-v{i:02d}" for i in range(12)]}
    assert template_texts(cls, 20) == ["C01 x12", "S-v00 S-v01 S-v02 S-v03",
                                       "S-v04 S-v05 S-v06 S-v07", "S-v08 S-v09 S-v10 S-v11"]
    assert [len(t.split()) for t in template_texts(cls, 3)] == [2, 6, 6]
    assert template_texts(cls, 1) == ["C01 x12: " + " ".join(cls["members"])]
    x = np.array([0.0, 10, 12, 40, 42, 44, 80])                # cells 10, 2, 28, 2, 2, 36 long
    A = np.column_stack([x, np.zeros_like(x)])
    B = A + [0.0, 5.0]
    runs = cell_runs(A, B, 3)
    assert runs[0][0] == 0 and runs[-1][1] == len(x) - 1
    assert all(a[1] == b[0] for a, b in zip(runs[:-1], runs[1:], strict=True))
    assert [any(u in (0, 2, 5) for u in range(a, b)) for a, b in runs] == [True] * 3


def test_nest_places_every_copy_labelled_with_its_own_id(chain, tmp_path):
    dgpc("nest", chain / "flat", "--sheet", "6100x2500", "-o", tmp_path / "sheets")
    sheets = read_sheets(tmp_path / "sheets")
    flat = read_flat(chain / "flat")
    placements = sheets.data["placements"]
    assert sorted(p["part"] for p in placements) == sorted(p["id"] for p in flat.parts)
    for p in placements:
        assert p["label"]["text"] in (p["part"], short_id(p["part"]))
        assert p["class"] == flat.part(p["part"])["class"]
    texts = []
    for s in sheets.data["sheets"]:
        doc = ezdxf.readfile(sheets.file(s["dxf"]))
        texts += [t.dxf.text for t in doc.modelspace().query("TEXT[layer=='LABEL']")
                  if not END_MARK.fullmatch(t.dxf.text)]
    assert sorted(texts) == sorted(p["label"]["text"] for p in placements)


def test_a_plain_stock_length_meant_in_millimetres_is_a_usage_error(chain, tmp_path):
    """``--stock-length 2500`` on strips in metres is 2500 m, longer than every strip (4.5 m),
    while 2500 mm would cut them: exit 2, one line naming both readings, nothing written."""
    res = dgpc("unfold", chain / "chain", "--stock-length", 2500, "-o", tmp_path / "f",
               expect=2)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(err) == 1 and err[0].startswith("Error")
    assert "--stock-length 2500 read as m (the strips' unit) is a 2500 m stock length, above " \
           "every strip's length (the longest is 4.47" in err[0]
    assert "did you mean 2500mm? (to mean it as typed, give its unit: 2500m)" in err[0]
    assert list(tmp_path.iterdir()) == []
    # with its unit: cut into boards no longer than 2.5 m, no warning
    res = dgpc("unfold", chain / "chain", "--stock-length", "2500mm", "-o", tmp_path / "g")
    assert "--stock-length" not in res.stderr
    flat = read_flat(tmp_path / "g")
    assert flat.parameters["stock_length"] == 2.5
    assert all(np.ptp(np.asarray(p["outline"])[:, 0]) <= 2.5 + 1e-9 for p in flat.parts)
    assert len(flat.parts) > 6


@pytest.mark.parametrize("stock", ["5m", "6000mm"])
def test_a_stock_length_longer_than_every_strip_only_warns(chain, tmp_path, stock):
    """Longer than every strip with its unit: nothing to cut, one warning, each strip one
    board (a plain number that long is a usage error, below)."""
    res = dgpc("unfold", chain / "chain", "--stock-length", stock, "-o", tmp_path / "f")
    warnings = [line for line in res.stderr.splitlines() if "--stock-length" in line]
    assert len(warnings) == 1 and "nothing is cut into boards" in warnings[0]
    parts = read_flat(tmp_path / "f").parts
    assert sorted(p["strip"] for p in parts) == list(range(6))         # one board per strip


@pytest.mark.parametrize("stock, words", [
    (9000, "9000 m stock length, above every strip's length"),
    (0.1, "0.1 m stock length, below the widest part"),
])
def test_a_plain_stock_length_outside_its_span_is_a_usage_error(chain, tmp_path, stock, words):
    """A plain number longer than every strip (nothing to cut) or no longer than the widest
    part, with no other reading inside: exit 2, one line naming the reading, nothing written."""
    res = dgpc("unfold", chain / "chain", "--stock-length", stock, "-o", tmp_path / "f",
               expect=2)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(err) == 1 and words in err[0] and "did you mean" not in err[0]
    assert f"give its unit: {stock}m)" in err[0]
    assert list(tmp_path.iterdir()) == []


def test_a_plain_stagger_meant_in_millimetres_is_a_usage_error(chain, tmp_path):
    """``--stagger 400`` with 2 m stock on strips in metres: 400 m, longer than the stock,
    where 400 mm would do: exit 2, nothing written; ``400mm`` is fine."""
    res = dgpc("unfold", chain / "chain", "--stock-length", "2m", "--stagger", 400,
               "-o", tmp_path / "f", expect=2)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(err) == 1 and "--stagger 400 read as m (the strips' unit) is a 400 m " \
        "stagger, above the stock length (2m); did you mean 400mm?" in err[0]
    assert list(tmp_path.iterdir()) == []
    dgpc("unfold", chain / "chain", "--stock-length", "2m", "--stagger", "400mm",
         "-o", tmp_path / "g")
    assert read_flat(tmp_path / "g").parameters["stagger"] == pytest.approx(0.4)


def test_a_part_under_10_mm_warns(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 4,
         "--span", 60, "--units", "mm", "-o", tmp_path / "tiny")
    dgpc("planarize-strips", tmp_path / "tiny", "-o", tmp_path / "s")
    res = dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "under 10 mm" in lines[0] and "--units m" in lines[0]


@pytest.mark.parametrize("option", ["--congruence-tol", "--stock-length", "--stagger"])
def test_help_names_units_and_ranges(option):
    text = " ".join(dgpc("unfold", "--help").stdout.split())
    at = text.index(f"{option} LENGTH")
    line = text[at:at + 400]
    assert "LENGTH" in line and "unit" in line and ("> 0" in line or ">= 0" in line)


@pytest.mark.parametrize("args", [["--congruence-tol", "0.5 parsecs"],
                                  ["--stock-length", "-2m"], ["--stagger", "nan"]])
def test_bad_lengths_are_usage_errors(chain, tmp_path, args):
    extra = ["--stock-length", "3m"] if args[0] == "--stagger" else []
    res = dgpc("unfold", chain / "chain", *extra, *args, "-o", tmp_path / "f", expect=2)
    assert args[0] in res.stderr
    assert list(tmp_path.iterdir()) == []


def test_force_with_fewer_templates_removes_the_old_template_dxfs_only(chain, tmp_path):
    """A rerun with --force that finds fewer classes removes the template DXFs the previous
    artifact listed and the new one does not write; files it did not list (a user's
    ``flat.C09.dxf``, ``flat.notes.dxf``) stay."""
    dgpc("unfold", chain / "chain", "-o", tmp_path / "flat")
    before = read_flat(tmp_path / "flat")
    assert len(before.classes) >= 2
    old = {tmp_path / f"flat.{c['id']}.dxf" for c in before.classes}
    assert all(p.is_file() for p in old)
    mine = [tmp_path / "flat.C09.dxf", tmp_path / "flat.notes.dxf"]
    for p in mine:
        p.write_bytes(b"mine")
    dgpc("unfold", chain / "chain", "--congruence-tol", "5mm", "-o", tmp_path / "flat",
         "--force")
    after = read_flat(tmp_path / "flat")
    assert [c["id"] for c in after.classes] == ["C01"]
    dxfs = sorted(p.name for p in tmp_path.glob("flat.C*.dxf"))
    assert dxfs == ["flat.C01.dxf", "flat.C09.dxf"]
    assert all(p.read_bytes() == b"mine" for p in mine)
    rows = list(csv.DictReader((tmp_path / "flat.parts.csv").open()))
    assert [r["dxf"] for r in rows] == ["flat.C01.dxf"]


@pytest.mark.parametrize("dim", [2, 3])
def test_kabsch_recovers_a_rigid_motion_and_refuses_a_mirror_unless_allowed(dim):
    """The one Kabsch of the package, in the plane (developed parts) and in space: a rotated
    and moved point set comes back exactly; its mirror image gets the best rotation (an error
    left), or the reflection itself when reflections are allowed."""
    from dgpc_cli.strips.congruence import kabsch

    rng = np.random.default_rng(3)
    X = rng.normal(size=(12, dim))
    Q, _ = np.linalg.qr(rng.normal(size=(dim, dim)))
    Q[:, -1] *= np.sign(np.linalg.det(Q))                            # a rotation
    t = rng.normal(size=dim)
    R, s = kabsch(X, X @ Q.T + t, allow_reflection=False)
    assert np.allclose(R, Q, atol=1e-12) and np.allclose(s, t, atol=1e-12)
    M = np.diag([1.0] * (dim - 1) + [-1.0])
    Y = X @ M.T
    R, s = kabsch(X, Y, allow_reflection=False)
    assert np.linalg.det(R) == pytest.approx(1.0) and np.abs(X @ R.T + s - Y).max() > 0.1
    R, s = kabsch(X, Y, allow_reflection=True)
    assert np.allclose(R, M, atol=1e-12) and np.abs(X @ R.T + s - Y).max() < 1e-12
