"""Issue 14 item 2: strips of a 30 m roof cut into boards of 6 m stock (`unfold --stock-length`),
joints staggered between neighbouring strips, recorded in the cut list; the boards nest on
6.1 × 2.5 m sheets."""

import csv
from collections import defaultdict

import numpy as np
import pytest
from cli_helpers import dgpc
from shapely.geometry import Polygon

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.io.strips import read_strips
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


@pytest.mark.parametrize("args, code, names", [
    (["--stock-length", 0], 2, "--stock-length"),
    (["--stock-length", -6], 2, "--stock-length"),
    (["--stock-length", 0.3], 1, "--stock-length"),            # shorter than one quad
    (["--stagger", 1], 2, "--stagger"),                          # needs --stock-length
    (["--stock-length", 6, "--stagger", 4], 1, "--stagger"),    # no joint can keep 4 m apart
])
def test_bad_stock_writes_nothing(roof, tmp_path, args, code, names):
    res = dgpc("unfold", roof / "strips", *args, "-o", tmp_path / "bad", expect=code)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert names in err[-1] and err[-1].startswith("Error")
    assert len([line for line in err if line.startswith("Error")]) == 1
    assert list(tmp_path.iterdir()) == []
