"""Issue 14 item 2: strips of a 30 m roof cut into boards of 6 m stock (`unfold --stock-length`),
joints staggered between neighbouring strips, recorded in the cut list; the boards nest on
6.1 × 2.5 m sheets."""

import csv
from collections import defaultdict

import numpy as np
import pytest
from cli_helpers import dgpc
from shapely.geometry import Polygon

from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.io.strips import read_strips, strips_files
from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.bounds import sheet_lower_bounds
from dgpc_cli.nesting.geometry import transform
from dgpc_cli.stages.nest import nest_parts
from dgpc_cli.strips.boards import board_extent, split_boards
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.trim import strip_points
from dgpc_cli.surfaces.minding import minding_bend

STOCK, STAGGER = 6.0, 1.5            # m: the default stagger is a quarter of the stock


def _along(X):
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=1))])


@pytest.fixture(scope="module")
def roof(tmp_path_factory):
    """A 30 m tall surface of revolution in m (r from 12 m down to 10, waving), its 61×7
    meridian net bent isometrically (Minding, λ = 0.8), the planar strips, then the flat parts
    whole and as boards of 6 m stock."""
    d = tmp_path_factory.mktemp("roof")
    h = np.linspace(0.0, 30.0, 301)
    r = 12.0 - h / 15.0 + 0.3 * np.sin(h / 5.0)
    (d / "roof.csv").write_text("r,h\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(
        r.tolist(), h.tolist(), strict=True)))
    dgpc("init", "--surface", "revolution", "--profile", d / "roof.csv", "--units", "m",
         "--rows", 61, "--cols", 7, "--span", 24, "-o", d / "base")
    write_net(d / "bent", NetArtifact(f=minding_bend(read_net(d / "base").f, 0.8), units="m"))
    dgpc("planarize-strips", d / "bent", "-o", d / "strips")
    dgpc("unfold", d / "strips", "-o", d / "whole")
    dgpc("unfold", d / "strips", "--stock-length", STOCK, "-o", d / "boards")
    return d


def test_boards_fit_the_stock_and_conserve_the_length(roof):
    whole = {p["id"]: p for p in read_flat(roof / "whole").parts}
    assert min(p["length"] for p in whole.values()) > 29.0       # strips of some 30 m
    boards = read_flat(roof / "boards")
    by_strip = defaultdict(list)
    for p in boards.parts:
        sid, number = p["id"].split(".")
        assert int(number) == p["board"]
        by_strip[sid].append(p)
        # the stock a board needs: its outline's extent along its own length (its chord lies
        # along x as unfold lays it out), no more than 6 m
        outline = np.asarray(p["outline"])
        assert np.ptp(outline[:, 0]) <= STOCK + 1e-9, p["id"]
        assert Polygon(outline).is_valid and p["area"] > 0
    assert sorted(by_strip) == sorted(whole)
    for sid, parts in by_strip.items():
        parts.sort(key=lambda p: p["board"])
        assert [p["board"] for p in parts] == list(range(1, len(parts) + 1))
        assert len(parts) >= 5                                     # 30 m / 6 m
        total = sum(p["length"] for p in parts)
        assert abs(total - whole[sid]["length"]) <= 1e-9 * whole[sid]["length"], sid
        rows = [p["rows"] for p in parts]                           # consecutive, all rows
        assert rows[0][0] == 0 and rows[-1][1] == whole[sid]["rows"][1]
        assert all(a[1] == b[0] for a, b in zip(rows[:-1], rows[1:], strict=True))


def test_joints_of_neighbouring_strips_are_staggered(roof):
    """Measured independently on the 3-D strips: arc length along the geodesic two strips
    share (side B of strip v, side A of strip v+1) from the first row."""
    strips = read_strips(roof / "strips")
    flat = read_flat(roof / "boards")
    geometry = {r["v"]: (A, B) for r, (A, B) in zip(strips.records, strips.geometry,
                                                     strict=True)}
    joints = defaultdict(list)
    for j in flat.joints:
        v = int(j["strip"][3:])
        joints[v].append(j["row"])
        A, B = geometry[v]
        assert j["position"] == pytest.approx(0.5 * (_along(A) + _along(B))[j["row"]],
                                              abs=1e-12)
    assert len(joints) == len(geometry) and all(len(v) >= 4 for v in joints.values())
    closest = np.inf
    for v in sorted(geometry)[:-1]:
        on_b = _along(geometry[v][1])[joints[v]]
        on_a = _along(geometry[v + 1][0])[joints[v + 1]]
        closest = min(closest, float(np.abs(on_b[:, None] - on_a[None, :]).min()))
    assert closest >= STAGGER - 1e-9, closest
    assert flat.parameters["stagger"] == STAGGER


def test_assembly_list_records_the_joints(roof):
    flat = read_flat(roof / "boards")
    rows = list(csv.DictReader((roof / "boards.assembly.csv").open()))
    assert [r["id"] for r in rows] == [p["id"] for p in flat.parts]
    by_id = {r["id"]: r for r in rows}
    for j in flat.joints:
        left, right = (by_id[i] for i in j["parts"])
        assert int(left["row_stop"]) == int(right["row_start"]) == j["row"]
        assert float(left["stop_mm"]) == float(right["start_mm"]) == \
            pytest.approx(1000.0 * j["position"], abs=1e-3)
    for r, p in zip(rows, flat.parts, strict=True):
        assert float(r["length_mm"]) == pytest.approx(1000.0 * p["length"], abs=1e-3)
        assert float(r["stop_mm"]) - float(r["start_mm"]) == pytest.approx(
            float(r["length_mm"]), abs=1e-2)


def test_congruent_strips_cut_alike_keep_one_class_per_board(roof):
    whole = {p["id"]: p["class"] for p in read_flat(roof / "whole").parts}
    assert len(set(whole.values())) == 1                          # an isometric net: one class
    boards = read_flat(roof / "boards")
    cut = defaultdict(list)
    for p in boards.parts:
        cut[p["id"].split(".")[0]].append(p["rows"][1])
    groups = defaultdict(set)
    for p in boards.parts:
        sid = p["id"].split(".")[0]
        groups[(whole[sid], tuple(cut[sid]), p["board"])].add(p["class"])
    assert all(len(classes) == 1 for classes in groups.values()), groups
    assert len({tuple(v) for v in cut.values()}) == 2              # staggered: two patterns
    for c in boards.classes:
        assert c["max_relative_error"] <= 1e-3


def test_boards_nest_on_6100_by_2500_sheets(roof, tmp_path):
    dgpc("nest", roof / "boards", "--sheet", "6100x2500", "-o", tmp_path / "sheets")
    sheets = read_sheets(tmp_path / "sheets")
    flat = read_flat(roof / "boards")
    assert sorted(p["part"] for p in sheets.data["placements"]) == \
        sorted(p["id"] for p in flat.parts)
    # whole 30 m strips cannot be nested on these sheets
    res = dgpc("nest", roof / "whole", "--sheet", "6100x2500", "-o", tmp_path / "no", expect=1)
    assert "does not fit" in res.stderr



def test_boards_of_templates_share_their_shapes_and_nest_at_the_bound(roof):
    """The roof's 36 boards are copies of 12 templates: the nester takes them as 12 shapes
    (one no-fit polygon per pair of shapes and relative rotation, never one per pair of
    boards), and fills 7000 × 1250 mm sheets up to the lower bound: every board longer than
    half the sheet crosses its centre line, one a sheet."""
    flat = read_flat(roof / "boards")
    sheet = Sheet(7000.0, 1250.0, 10.0, 3.0)
    result = nest_parts(flat.parts, sheet, [0.0, 180.0], units=flat.units)
    info = result.engine_info
    assert len(flat.parts) == 36 and len(flat.classes) == 12
    assert info["shapes"] == 12
    assert info["no_fit_polygons"] <= 2 * 12 * 12
    by_class = defaultdict(set)
    for p in result.parts:
        by_class[p.cls].add(p.group)
    assert all(len(groups) == 1 for groups in by_class.values())
    bound = sheet_lower_bounds(result.parts, sheet.width, sheet.height, sheet.margin,
                               sheet.spacing, [0.0, 180.0])
    assert result.sheet_count == bound["sheets"] > bound["area"]
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    on = [q.sheet for q in result.placements]
    for i in range(len(placed)):
        for j in range(i + 1, len(placed)):
            if on[i] == on[j]:
                assert placed[i].distance(placed[j]) >= sheet.spacing - 1e-6

@pytest.mark.parametrize("args, code, names", [
    (["--stock-length", 0], 2, "--stock-length"),
    (["--stock-length", -6], 2, "--stock-length"),
    (["--stock-length", 0.3], 2, "--stock-length"),            # both readings refused
    (["--stock-length", "0.3m"], 1, "--stock-length"),         # shorter than one quad
    (["--stock-length", "2.5mm"], 1, "--stock-length"),        # a unit slip: narrower than wide
    (["--stagger", 1], 2, "--stagger"),                          # needs --stock-length
    (["--stock-length", 6, "--stagger", 4], 1, "--stagger"),    # no joint can keep 4 m apart
])
def test_bad_stock_writes_nothing(roof, tmp_path, args, code, names):
    res = dgpc("unfold", roof / "strips", *args, "-o", tmp_path / "bad", expect=code)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert names in err[-1] and err[-1].startswith("Error")
    assert len([line for line in err if line.startswith("Error")]) == 1
    assert list(tmp_path.iterdir()) == []


def _slightly_different_strips(n=8, m=61, width=0.3):
    """Flat strips of 60 quads about 0.5 m long (waving by 5 %), each 0.3 % shorter than the
    one before: near-templates whose greedy joints drift from strip to strip."""
    geometry = []
    for v in range(n):
        ds = 0.5 * (1 - 0.003 * v) * (1 + 0.05 * np.sin(0.7 * np.arange(m - 1)))
        A = np.column_stack([np.concatenate([[0.0], np.cumsum(ds)]), np.zeros(m), np.zeros(m)])
        geometry.append((A, A + [0.0, width, 0.0]))
    return geometry


def test_strips_alternate_between_two_joint_patterns_where_they_can():
    """A strip takes the joints of the strip two columns before it where they fit: two joint
    patterns, alternating, where cutting each strip greedily gave six."""
    geometry = _slightly_different_strips()
    devs = [develop_strip(A, B) for A, B in geometry]
    columns = list(range(len(geometry)))
    boards = split_boards(devs, geometry, columns, [f"S-v{v:02d}" for v in columns], 5.0, 1.2)
    patterns = [tuple(b.stop for b in strip[:-1]) for strip in boards]
    assert len(set(patterns)) == 2
    assert all(patterns[v] == patterns[v - 2] for v in range(2, len(patterns)))
    assert patterns[0] != patterns[1]
    for strip, dev in zip(boards, devs, strict=True):
        assert all(board_extent(dev, b.start, b.stop) <= 5.0 for b in strip)
    along = [_along(A) for A, _ in geometry]
    for v in range(len(geometry) - 1):                     # staggered by 1.2 m
        a = along[v][list(patterns[v])]
        b = along[v + 1][list(patterns[v + 1])]
        assert np.abs(a[:, None] - b[None, :]).min() >= 1.2


def test_boards_of_a_template_are_few_templates(roof):
    """Six congruent strips cut alternately: the boards are the boards of two patterns, each a
    template with three copies, and the cut list says so."""
    boards = read_flat(roof / "boards")
    patterns = defaultdict(list)
    for p in boards.parts:
        patterns[p["strip"]].append(p["rows"][1])
    by_column = [tuple(patterns[v]) for v in sorted(patterns)]
    assert all(by_column[v] == by_column[v - 2] for v in range(2, len(by_column)))
    assert len(boards.classes) == len(by_column[0]) + len(by_column[1])
    rows = list(csv.DictReader((roof / "boards.parts.csv").open()))
    assert [int(r["quantity"]) for r in rows] == [len(by_column) // 2] * len(rows)
    assert sum(int(r["quantity"]) for r in rows) == len(boards.parts)


@pytest.mark.parametrize("stagger", ["2m", "900mm"])
def test_boards_with_a_stagger_are_templates_of_two_alternating_patterns(roof, tmp_path,
                                                                          stagger):
    """``--stagger``: the joints of neighbouring strips at least that far apart, at most two
    joint patterns, alternating, so the boards of the six congruent strips are templates: the
    cut list names each once, with its quantity and its copies' ids, every copy a board of the
    same place in its pattern."""
    gap = {"2m": 2.0, "900mm": 0.9}[stagger]
    dgpc("unfold", roof / "strips", "--stock-length", STOCK, "--stagger", stagger,
         "-o", tmp_path / "b")
    flat = read_flat(tmp_path / "b")
    assert flat.parameters["stagger"] == pytest.approx(gap)
    joints = defaultdict(list)
    for j in flat.joints:
        joints[int(j["strip"][3:])].append(j["row"])
    by_column = [tuple(joints[v]) for v in sorted(joints)]
    assert len(by_column) == 6 and len(set(by_column)) <= 2
    assert all(by_column[v] == by_column[v - 2] for v in range(2, len(by_column)))
    strips = read_strips(roof / "strips")
    for v in range(len(by_column) - 1):
        on_b = _along(strips.geometry[v][1])[list(by_column[v])]
        on_a = _along(strips.geometry[v + 1][0])[list(by_column[v + 1])]
        assert np.abs(on_b[:, None] - on_a[None, :]).min() >= gap - 1e-9
    rows = list(csv.DictReader((tmp_path / "b.parts.csv").open()))
    assert len(rows) == len(flat.classes) == len(by_column[0]) + len(by_column[1]) + 2
    parts = {p["id"]: p for p in flat.parts}
    for r, c in zip(rows, flat.classes, strict=True):
        copies = r["parts"].split()
        assert copies == c["members"] and int(r["quantity"]) == len(copies) == 3
        # the copies: the same board (rows) of the strips of one pattern
        assert len({tuple(parts[i]["rows"]) for i in copies}) == 1
        assert len({parts[i]["strip"] % 2 for i in copies}) == 1
    assert sorted(i for r in rows for i in r["parts"].split()) == sorted(parts)


def _trimmed(roof):
    """The roof's strips with trim records (as `planarize-strips --trim` writes them): slanted
    end cuts, and strip 2 cut in two by a hole; rings sampled every 1/8 quad, as the trim's."""
    strips = read_strips(roof / "strips")
    m = len(strips.geometry[0][0])
    for v, (rec, (A, B)) in enumerate(zip(strips.records, strips.geometry, strict=True)):
        if v == 2:
            rings = {rec["id"] + "a": [[0.3, 0], [25.5, 0], [24.2, 1], [0, 1]],
                     rec["id"] + "b": [[30.6, 0], [m - 1, 0], [m - 1.7, 1], [31.2, 1]]}
        else:
            rings = {rec["id"]: [[0.2 + 0.1 * v, 0], [m - 1, 0], [m - 1 - 0.3 * v, 1], [0, 1]]}
        parts = []
        for pid, ring in rings.items():
            ring = np.asarray(Polygon(ring).segmentize(0.125).exterior.coords)[:-1]
            parts.append({"id": pid, "outline": ring, "outline_3d": strip_points(A, B, ring),
                          "rows": [int(np.floor(ring[:, 0].min())),
                                   int(np.ceil(ring[:, 0].max()))]})
        rec["trim"] = {"parts": parts, "dropped": []}
    write_files(strips_files(roof / "trimmed", strips), force=True)
    return roof / "trimmed"


def test_trimmed_strips_are_cut_into_boards_at_rulings(roof, tmp_path):
    """Issue 27 item 5: trimmed parts into boards no longer than the stock, end cuts along the
    outline on the end boards, joints staggered, the same area as the trimmed parts."""
    stem = _trimmed(roof)
    dgpc("unfold", stem, "-o", tmp_path / "parts")
    dgpc("unfold", stem, "--stock-length", "6m", "-o", tmp_path / "boards")
    parts = {p["id"]: p for p in read_flat(tmp_path / "parts").parts}
    flat = read_flat(tmp_path / "boards")
    by_part = defaultdict(list)
    for p in flat.parts:
        by_part[p["id"].split(".")[0]].append(p)
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9, p["id"]
        assert Polygon(p["outline"]).is_valid
    assert sorted(by_part) == sorted(parts) and "S-v02b" in by_part
    for pid, boards in by_part.items():
        assert len(boards) >= 3                          # 13 m and more
        area = sum(b["area"] for b in boards)
        assert area == pytest.approx(parts[pid]["area"], rel=1e-6), pid
        # the outline's end cuts stay on the end boards; the boards between are whole
        assert boards[0].get("trimmed") and not any(b.get("trimmed") for b in boards[1:-1])
        assert [b["board"] for b in boards] == list(range(1, len(boards) + 1))
    for c in flat.classes:                                # whole boards share templates
        assert c["max_deviation_mm"] <= 0.5
    assert any(c["quantity"] > 1 for c in flat.classes)
    strips = read_strips(stem)
    geometry = {r["v"]: (A, B) for r, (A, B) in zip(strips.records, strips.geometry,
                                                     strict=True)}
    rows = defaultdict(list)
    for j in flat.joints:
        rows[int(j["strip"][3:])].append(j["row"])
    for v in sorted(geometry)[:-1]:
        on_b = _along(geometry[v][1])[rows[v]]
        on_a = _along(geometry[v + 1][0])[rows[v + 1]]
        assert np.abs(on_b[:, None] - on_a[None, :]).min() >= STAGGER - 1e-9
