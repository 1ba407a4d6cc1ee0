"""Issue 6 done-means: `dgpc nest` cut sheets checked independently (ezdxf + shapely), the
panel-to-mold map, determinism, bad input, utilization against spyrrow's single strip."""

import csv
import json

import ezdxf
import ezdxf.bbox
import numpy as np
import pytest
from cli_helpers import dgpc, metrics
from dxf_checks import END_MARK, check_cam_ready
from shapely.geometry import Point, Polygon, box

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.nesting.geometry import CLEARANCE_MM, prepare_parts, transform
from dgpc_cli.nesting.strip import strip_density
from dgpc_cli.surfaces.minding import minding_bend

SCALE = 100.0          # 1 net unit = 100 mm
SHEET = (700.0, 500.0)
MARGIN, SPACING = 10.0, 3.0


def _sample(folder, cols):
    """Flat parts (and mold) of a full-ring catenoid net bent by Minding (λ = 0.7)."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 21, "--cols",
         cols, "--span", 360, "-o", folder / "cat")
    write_net(folder / "iso", NetArtifact(f=minding_bend(read_net(folder / "cat").f, 0.7)))
    dgpc("planarize-strips", folder / "iso", "-o", folder / "s")
    dgpc("unfold", folder / "s", "-o", folder / "flat")
    return folder / "flat"


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    folder = tmp_path_factory.mktemp("nest")
    flat = _sample(folder, 13)                                  # 12 congruent strips
    dgpc("extract-mold", folder / "iso", "-o", folder / "mold")
    args = ["--sheet", f"{SHEET[0]:g}x{SHEET[1]:g}", "--margin", MARGIN, "--spacing", SPACING,
            "--scale", SCALE]
    out = dgpc("nest", flat, "--mold", folder / "mold", *args, "-o", folder / "sh")
    assert out.stdout.strip() == str(folder / "sh.json")
    dgpc("nest", flat, "--mold", folder / "mold", *args, "-o", folder / "again")
    return folder, flat, args


def _read_sheet(path):
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    return doc, {
        "sheet": [(np.array(e.get_points("xy")), e.closed)
                  for e in msp.query("LWPOLYLINE[layer=='SHEET_BORDER']")],
        "cut": [(np.array(e.get_points("xy")), e.closed)
                for e in msp.query("LWPOLYLINE[layer=='CUT']")],
        "score": [(np.array(e.get_points("xy")), e.closed)
                  for e in msp.query("LWPOLYLINE[layer=='SCORE']")],
        "label": [(e.dxf.text, np.array(e.dxf.align_point)[:2])
                  for e in msp.query("TEXT[layer=='LABEL']")
                  if not END_MARK.fullmatch(e.dxf.text)]}          # not the end marks


def test_sheet_dxfs_pass_independent_checks(sample):
    folder, flat_stem, _ = sample
    art = read_sheets(folder / "sh")
    flat = {p["id"]: p for p in read_flat(flat_stem).parts}
    placements = {p["part"]: p for p in art.data["placements"]}
    assert art.data["sheet_count"] >= 2                      # several sheets on this size
    seen = []
    for s, rec in enumerate(art.data["sheets"]):
        check_cam_ready(art.file(rec["dxf"]))               # R2010, mm, audit, extents ...
        doc, ents = _read_sheet(art.file(rec["dxf"]))
        # no border unless --border asks: a CAM would cut it
        assert {layer.dxf.name for layer in doc.layers} == {"0", "Defpoints", "CUT", "SCORE",
                                                             "LABEL"}
        assert [doc.layers.get(n).color for n in ("CUT", "SCORE", "LABEL")] == [1, 5, 3]
        inner = box(MARGIN, MARGIN, SHEET[0] - MARGIN, SHEET[1] - MARGIN)
        polys = []
        for pts, closed in ents["cut"]:
            assert closed
            poly = Polygon(pts)
            assert poly.is_valid and inner.covers(poly)      # inside the margin
            polys.append(poly)
        for i in range(len(polys)):                          # the kerf
            for j in range(i + 1, len(polys)):
                assert polys[i].distance(polys[j]) >= SPACING - 1e-9
        assert all(not closed for _, closed in ents["score"])
        for pid, at in ents["label"]:                        # label → its outline
            (k,) = [k for k, poly in enumerate(polys) if poly.contains(Point(at))]
            pts = ents["cut"][k][0]
            pl = placements[pid]
            assert pl["sheet"] == s
            a = np.radians(pl["rotation"])
            R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            want = SCALE * np.asarray(flat[pid]["outline"]) @ R.T + pl["translation"]
            assert pts.shape == want.shape
            assert np.abs(pts - want).max() <= 1e-6          # same outline, mm
            seen.append(pid)
        assert len(ents["label"]) == len(polys)
        assert sum(len(flat[p]["score"]) for p, _ in ents["label"]) == len(ents["score"])
        area = sum(p.area for p in polys)
        assert abs(rec["utilization"] - area / (SHEET[0] * SHEET[1])) <= 1e-9
    assert sorted(seen) == sorted(flat)                      # each part exactly once
    m = metrics(folder / "sh")
    assert m["sheet_count"] == art.data["sheet_count"] and m["n_parts"] == len(flat)


def test_border_stroke_labels_and_router_spacing(sample, tmp_path):
    """--border: the sheet's border, one closed polyline on its own plotted layer; --label-style
    stroke: the ids as single-stroke polylines on ENGRAVE, inside each label's box; --tool
    router: the spacing is the bit's diameter plus a web, the parameters say so."""
    from dgpc_cli.io.dxf import text_box

    folder, flat_stem, _ = sample
    out = tmp_path / "routed"
    dgpc("nest", flat_stem, "--sheet", f"{SHEET[0]:g}x{SHEET[1]:g}", "--scale", SCALE,
         "--tool", "router", "--tool-diameter", "5mm", "--border", "--label-style", "stroke",
         "-o", out)
    art = read_sheets(out)
    params = json.loads(out.with_suffix(".json").read_text())["parameters"]
    assert (params["tool"], params["tool_diameter"], params["spacing"], params["margin"]) == \
        ("router", 5.0, 7.0, 20.0)
    assert (params["border"], params["label_style"]) == (True, "stroke")
    assert art.data["sheet"]["spacing"] == 7.0
    for rec in art.data["sheets"]:
        check_cam_ready(art.file(rec["dxf"]))
        doc, ents = _read_sheet(art.file(rec["dxf"]))
        assert doc.layers.get("SHEET_BORDER").dxf.plot == 1
        ((border, closed),) = ents["sheet"]
        assert closed and np.allclose(border.min(axis=0), 0) and \
            np.allclose(border.max(axis=0), SHEET)
        assert not ents["label"] and "LABEL" not in doc.layers
        strokes = [np.array(e.get_points("xy")) for e in
                   doc.modelspace().query("LWPOLYLINE[layer=='ENGRAVE']")]
        assert strokes and all(len(p) >= 2 for p in strokes)
        boxes = [Polygon(text_box(lb["text"], lb["height"], lb["at"], lb["rotation"])
                         ).buffer(1e-6)
                 for lb in (p["label"] for p in art.data["placements"]
                            if p["sheet"] == rec["index"])]
        flat = {p["id"]: p for p in read_flat(flat_stem).parts}
        ends = []                          # the end marks' room: each part's first cell
        for pl in (p for p in art.data["placements"] if p["sheet"] == rec["index"]):
            A, B = (transform(SCALE * np.asarray(g, float), pl["rotation"], pl["translation"])
                    for g in flat[pl["part"]]["geodesics"])
            ends.append(Polygon([A[0], A[1], B[1], B[0]]).buffer(1e-6))
        homes = set()
        for p in strokes:     # a letter inside a label's box, a leader, or an end mark
            inside = [k for k, b in enumerate(boxes) if all(b.covers(Point(*q)) for q in p)]
            mark = any(all(c.covers(Point(*q)) for q in p) for c in ends)
            assert inside or len(p) == 2 or mark, p
            homes.update(inside)
        assert homes == set(range(len(boxes)))           # every label lettered
        polys = [Polygon(pts) for pts, _ in ents["cut"]]
        for i in range(len(polys)):
            for j in range(i + 1, len(polys)):
                assert polys[i].distance(polys[j]) >= 7.0 - 1e-9


@pytest.mark.parametrize("extra, option", [
    (["--tool", "router", "--spacing", "5"], "--spacing"),      # below the 6 mm bit
    (["--tool", "laser", "--tool-diameter", "6"], "--tool-diameter"),
    (["--tool", "router", "--kerf", "0.2"], "--kerf"),
])
def test_a_tool_contradiction_is_a_usage_error(sample, tmp_path, extra, option):
    _, flat_stem, _ = sample
    result = dgpc("nest", flat_stem, "--sheet", "700x500", "--scale", SCALE, *extra, "-o",
                  tmp_path / "x", expect=2)
    assert option in result.stderr and not list(tmp_path.iterdir())


def _colours(png: bytes) -> dict[str, int]:
    """Pixels of a preview that are clearly red, blue, green or mid grey."""
    import io

    from matplotlib.image import imread

    rgb = imread(io.BytesIO(png), format="png")[..., :3]
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return {"red": int(np.sum((r > 0.7) & (g < 0.3) & (b < 0.3))),
            "blue": int(np.sum((b > 0.7) & (r < 0.3) & (g < 0.3))),
            "green": int(np.sum((g > 0.6) & (r < 0.3) & (b < 0.3))),
            "grey": int(np.sum((np.abs(r - g) < 0.05) & (np.abs(g - b) < 0.05)
                               & (r > 0.3) & (r < 0.7)))}


def test_parts_csv_obj_and_previews(sample):
    folder, flat_stem, _ = sample
    art = read_sheets(folder / "sh")
    flat = {p["id"]: p for p in read_flat(flat_stem).parts}
    placed = {p["part"]: p for p in art.data["placements"]}
    rows = list(csv.DictReader(art.file("parts_csv").open()))
    assert list(rows[0]) == ["id", "class", "strip", "board", "sheet", "x_mm", "y_mm",
                             "rotation_deg", "row_start", "row_stop", "start_mm", "stop_mm",
                             "length_mm", "width_min_mm", "width_max_mm", "area_mm2"]
    assert [r["id"] for r in rows] == sorted(flat)
    for r in rows:
        part, pl = flat[r["id"]], placed[r["id"]]
        assert r["sheet"] == f"SH{pl['sheet'] + 1:02d}" and r["class"] == part["class"]
        assert (float(r["x_mm"]), float(r["y_mm"])) == pytest.approx(pl["translation"],
                                                                     abs=1e-3)
        assert float(r["rotation_deg"]) == pl["rotation"]
        assert (int(r["row_start"]), int(r["row_stop"])) == (0, 20)      # whole strips
        assert int(r["board"]) == 1 and int(r["strip"]) == part["strip"]
        # mm from the net unit (mm) × scale; the area from the outline itself
        length = float(r["length_mm"])
        assert length == pytest.approx(SCALE * part["length"], abs=1e-3)
        assert float(r["area_mm2"]) == pytest.approx(SCALE**2 * Polygon(part["outline"]).area,
                                                     rel=1e-9, abs=0.01)
        A, B = (np.asarray(g) for g in part["geodesics"])
        rulings = SCALE * np.linalg.norm(A - B, axis=1)      # a width is at most a ruling
        w0, w1 = float(r["width_min_mm"]), float(r["width_max_mm"])
        assert 0 < w0 <= w1 <= max(rulings) + 1e-3
        assert w0 * length <= float(r["area_mm2"]) <= w1 * length
    obj = (folder / "sh.obj").read_text().splitlines()
    assert sum(line.startswith("o SH") for line in obj) == art.data["sheet_count"]
    assert sum(line.startswith("l ") for line in obj) == art.data["sheet_count"] + len(rows)
    for rec in art.data["sheets"]:
        png = art.file(rec["png"]).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        assert b"<svg" in art.file(rec["svg"]).read_bytes()[:500]
        colours = _colours(png)                  # cut red, score blue, labels green, sheet grey
        assert all(colours[c] > 50 for c in ("red", "blue", "green", "grey")), colours
        # the sheet outlined in the preview by one path (not a path per dash of a border),
        # with a scale bar
        svg = art.file(rec["svg"]).read_bytes()
        assert svg.count(b'id="sheet-frame"') == 1 and svg.count(b'id="scale-bar"') == 1
        assert len(svg) < 300_000, len(svg)
    assert art.file("moldmap_png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_mold_map(sample):
    folder, _, _ = sample
    art = read_sheets(folder / "sh")
    mold = json.loads((folder / "mold.json").read_text())["data"]
    check_cam_ready(art.file("moldmap_dxf"))        # no line twice (shared outlines drawn once)
    doc = ezdxf.readfile(art.file("moldmap_dxf"))
    msp = doc.modelspace()
    (profile,) = msp.query("LWPOLYLINE[layer=='PROFILE']")
    r = np.array(profile.get_points("xy"))[:, 0]
    assert np.allclose(r, SCALE * np.asarray(mold["profile"]["r"]), atol=1e-6)
    (piece,) = mold["pieces"]
    (outline,) = msp.query("LWPOLYLINE[layer=='PIECES']")    # drawn first, closed
    assert outline.closed
    table = " ".join(e.dxf.text for e in msp.query("TEXT[layer=='TABLE']"))
    assert piece["id"] in table
    assert all(p["id"] in table for p in mold["panels"])
    assert "flat panels" in table
    assert {e.dxf.layer for e in msp.query("TEXT")} == {"LABEL", "TABLE"}
    assert doc.layers.get("LABEL").color == 3                # green, readable on white
    # every text of the map, the table's included, readable in its preview: 12 px high or more
    from PIL import Image

    png = Image.open(art.file("moldmap_png"))
    drawn = ezdxf.bbox.extents(msp, fast=False)
    px_per_mm = png.size[0] / (drawn.extmax.x - drawn.extmin.x)
    assert min(e.dxf.height for e in msp.query("TEXT")) * px_per_mm >= 12
    # where the curved panels are pressed: per band of mold rows a label, and its lower and
    # upper edge across the developed sector (s = meridian arc length) drawn once
    curved = [p for p in mold["panels"] if p["piece"] is not None]
    bands = sorted({tuple(p["rows"]) for p in curved})
    labels = [e.dxf.text for e in msp.query("TEXT[layer=='LABEL']")
              if e.dxf.text.startswith("rows")]
    counts = {rows: sum(tuple(p["rows"]) == rows for p in curved) for rows in bands}
    assert labels == [f"rows {a}-{b}: {counts[(a, b)]} panels" for a, b in bands]
    rh = SCALE * np.column_stack([mold["profile"]["r"], mold["profile"]["h"]])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(rh, axis=0), axis=1))])
    lines = [np.array(e.get_points("xy")) for e in msp.query("LWPOLYLINE")
             if e.dxf.layer in ("PIECES", "PANELS", "SECTOR")]
    lines = [np.concatenate([p, p[:1]]) for p in lines]     # closed ones: their last side too
    xs = np.concatenate(lines)[:, 0]
    across = {round(float(seg[0, 1]), 6) for pts in lines
              for seg in np.stack([pts[:-1], pts[1:]], axis=1) if seg[0, 1] == seg[1, 1]}
    for a, b in bands:
        assert round(float(s[a]), 6) in across and round(float(s[b]), 6) in across
    for e in msp.query("LWPOLYLINE[layer=='PANELS']"):
        pts = np.array(e.get_points("xy"))
        assert xs.min() - 1e-6 <= pts[:, 0].min() and pts[:, 0].max() <= xs.max() + 1e-6


def test_deterministic_bytes(sample):
    folder, _, _ = sample
    a, b = read_sheets(folder / "sh"), read_sheets(folder / "again")
    for key in a.data["files"]:
        assert a.file(key).read_bytes() == b.file(key).read_bytes(), key
    assert (folder / "sh.obj").read_bytes() == (folder / "again.obj").read_bytes()
    assert a.data["placements"] == b.data["placements"]


@pytest.mark.parametrize("extra, code, names", [
    (["--sheet", "0x500"], 2, "--sheet"),
    (["--sheet", "300x500"], 1, "S-v00"),                     # parts are 527 mm long
    (["--sheet", "700x500", "--spacing", "-1"], 2, "--spacing"),
    (["--sheet", "700x500", "--rotations", "0,sideways"], 2, "--rotations"),
    (["--sheet", "700x500", "--rotations", "0,360"], 2, "--rotations"),
])
def test_bad_input_writes_nothing(sample, tmp_path, extra, code, names):
    _, flat, _ = sample
    res = dgpc("nest", flat, "--scale", SCALE, *extra, "-o", tmp_path / "bad", expect=code)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert names in res.stderr and err[-1].startswith("Error")
    assert len([line for line in err if line.startswith("Error")]) == 1
    assert list(tmp_path.iterdir()) == []


def test_schema_rejects_edits(sample, tmp_path):
    folder, _, _ = sample
    from dgpc_cli.errors import DgpcError

    for name in ("sh.obj", "sh.parts.csv", "sh.moldmap.dxf", "sh.moldmap.png"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    for f in folder.glob("sh.sheet*"):
        (tmp_path / f.name).write_bytes(f.read_bytes())
    doc = json.loads((folder / "sh.json").read_text())
    (tmp_path / "sh.json").write_text(json.dumps(doc))
    assert read_sheets(tmp_path / "sh").data["sheet_count"] == doc["data"]["sheet_count"]
    for edit, match in [
        (lambda d: d["data"]["utilization"].__setitem__("overall", 1.5), "overall"),
        (lambda d: d["data"].pop("placements"), "placements"),
        (lambda d: d["data"]["placements"][0].__setitem__("sheet", 99), "sheet"),
        (lambda d: d["data"].__setitem__("engine", "magic"), "engine"),
    ]:
        bad = json.loads(json.dumps(doc))
        edit(bad)
        (tmp_path / "sh.json").write_text(json.dumps(bad))
        with pytest.raises(DgpcError, match=match):
            read_sheets(tmp_path / "sh")
    (tmp_path / "sh.json").write_text(json.dumps(doc))
    (tmp_path / "sh.sheet01.dxf").write_text("0\nEOF\n")
    with pytest.raises(DgpcError, match="sha256"):
        read_sheets(tmp_path / "sh")


def test_utilization_against_spyrrow_single_strip(tmp_path):
    """The bench's sample (24 strips, 1650 × 800 mm): our overall utilization is at least 90 %
    of spyrrow's own density on one strip of the sheet's inner height (same parts, run)."""
    flat = _sample(tmp_path, 25)
    dgpc("nest", flat, "--sheet", "1650x800", "--scale", SCALE, "-o", tmp_path / "sh")
    ours = read_sheets(tmp_path / "sh").data["utilization"]["overall"]
    parts = prepare_parts(read_flat(flat).parts, SCALE)
    density, _ = strip_density(parts, 800 - 2 * (10 + CLEARANCE_MM), [0.0, 180.0], 3.0,
                               time_limit=3, seed=0)
    assert ours >= 0.9 * density, (ours, density)


def test_spyrrow_engine_layout_is_checked(sample, tmp_path):
    _, flat, _ = sample
    dgpc("nest", flat, "--sheet", "1250x700", "--engine", "spyrrow",
         "--time-limit", 1, "--scale", SCALE, "-o", tmp_path / "sp")
    art = read_sheets(tmp_path / "sp")
    assert art.data["engine"] == "spyrrow"
    assert sorted(p["part"] for p in art.data["placements"]) == \
        sorted(p["id"] for p in read_flat(flat).parts)


def test_dxf_bytes_do_not_depend_on_the_process(sample, tmp_path):
    """ezdxf orders CLASS records by a set of type names (string hashing differs per process):
    the shared writer sorts them, so two processes with different hash seeds agree."""
    import os
    import subprocess
    import sys

    folder, flat, args = sample
    outs = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        subprocess.run([sys.executable, "-m", "dgpc_cli", "-q", "nest", str(flat), "--mold",
                        str(folder / "mold"), *map(str, args), "-o", str(tmp_path / seed)],
                       check=True, env=env, capture_output=True)
        outs.append(read_sheets(tmp_path / seed))
    for key in ("sheet01_dxf", "moldmap_dxf"):
        assert outs[0].file(key).read_bytes() == outs[1].file(key).read_bytes(), key


def test_near_congruent_parts_share_no_fit_polygons_and_keep_the_spacing(sample, tmp_path):
    """Parts within a quarter of the spacing of each other share a group (one set of no-fit
    polygons), the difference added to their clearance: the layout still keeps the spacing
    between the real outlines (nest's own check and shapely here)."""
    _, flat, _ = sample
    parts = read_flat(flat).parts
    rng = np.random.default_rng(1)
    for p in parts[1:]:                       # perturb every part but the first by ≤ 0.5 mm
        noise = 0.5 / SCALE * rng.uniform(-1, 1, np.shape(p["outline"])) / np.sqrt(2)
        p["outline"] = (np.asarray(p["outline"]) + noise).tolist()
    apart = prepare_parts(parts, SCALE)
    shared = prepare_parts(parts, SCALE, 0.25 * SPACING)
    assert len({p.group for p in apart}) == len(parts)
    assert len({p.group for p in shared}) == 1
    assert 0 < max(p.deviation for p in shared) <= 0.25 * SPACING
    from dgpc_cli.nesting.blf import Sheet
    from dgpc_cli.stages.nest import nest_parts

    result = nest_parts(parts, Sheet(*SHEET, MARGIN, SPACING), [0.0, 180.0], scale=SCALE)
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    sheets = [q.sheet for q in result.placements]
    gaps = [placed[i].distance(placed[j]) for i in range(len(placed))
            for j in range(i + 1, len(placed)) if sheets[i] == sheets[j]]
    assert SPACING - 1e-6 <= min(gaps) <= SPACING + 2 * 0.25 * SPACING


def test_long_outlines_nest_by_a_simplified_outline_and_keep_the_spacing():
    """A strip trimmed along a curved edge of its reference has hundreds of outline vertices:
    its no-fit polygons use a simplified outline (at most MAX_PIECE_VERTICES vertices), the
    simplification added to its spacing, so the true outlines keep the spacing."""
    from dgpc_cli.nesting.blf import Sheet
    from dgpc_cli.nesting.geometry import MAX_PIECE_VERTICES
    from dgpc_cli.stages.nest import nest_parts

    t = np.linspace(0.0, np.pi, 400)[1:-1]
    end = np.column_stack([3.0 + 0.2 * np.sin(t) + 0.01 * np.sin(40 * t),
                           0.25 - 0.25 * np.cos(t)])          # a wavy trimmed end, 398 points
    outline = np.vstack([[0.0, 0.0], [3.0, 0.0], end, [3.0, 0.5], [0.0, 0.5]])
    records = [{"id": f"P{i}", "strip": i, "class": f"C{i}", "outline": outline.tolist(),
                "geodesics": [[[0.0, 0.0], [3.0, 0.0]], [[0.0, 0.5], [3.0, 0.5]]],
                "score": [], "label": [1.5, 0.25]} for i in range(6)]
    parts = prepare_parts(records, SCALE)
    assert all(len(p.pieces) <= MAX_PIECE_VERTICES for p in parts)
    assert all(0 < p.deviation <= 0.01 * 320 for p in parts)     # mm, of a 320 mm part
    result = nest_parts(records, Sheet(*SHEET, MARGIN, SPACING), [0.0, 180.0], scale=SCALE)
    assert len(result.placements) == len(records)
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    sheets = [q.sheet for q in result.placements]
    gaps = [placed[i].distance(placed[j]) for i in range(len(placed))
            for j in range(i + 1, len(placed)) if sheets[i] == sheets[j]]
    assert gaps and min(gaps) >= SPACING - 1e-6


def test_tapered_congruent_parts_pair_by_a_half_turn_and_keep_the_spacing():
    """Congruent tapered strips interlock in pairs, one turned by 180° (a band of nearly
    constant width): the fill places the pairs, and the real outlines keep the spacing."""
    from dgpc_cli.nesting.blf import Sheet
    from dgpc_cli.nesting.pairs import make_units
    from dgpc_cli.stages.nest import nest_parts

    outline = [[0.0, 0.0], [3.0, 0.0], [3.0, 0.2], [0.0, 0.5]]
    records = [{"id": f"P{i}", "strip": i, "class": "C01", "outline": outline,
                "geodesics": [[[0.0, 0.0], [3.0, 0.0]], [[0.0, 0.5], [3.0, 0.2]]],
                "score": [], "label": [1.0, 0.2]} for i in range(4)]
    units = make_units(prepare_parts(records, SCALE), [0.0, 180.0], SPACING)
    assert [len(u.members) for u in units] == [2, 2]
    assert {m.rotation for u in units for m in u.members} == {0.0, 180.0}
    result = nest_parts(records, Sheet(*SHEET, MARGIN, SPACING), [0.0, 180.0], scale=SCALE)
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    assert len(placed) == 4 and {q.sheet for q in result.placements} == {0}
    gaps = [placed[i].distance(placed[j]) for i in range(4) for j in range(i + 1, 4)]
    assert min(gaps) >= SPACING - 1e-6
