"""Nesting that scales with the facade: no-fit polygons cached by part shape, congruent parts
paired wherever they lie, outputs checked before any nesting, previews optional, and a warning
on an implausible scale."""

import numpy as np
import pytest
from cli_helpers import dgpc
from dxf_checks import check_cam_ready
from shapely.geometry import Polygon

from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.geometry import minkowski_nfp, prepare_parts, rotation_matrix, transform
from dgpc_cli.nesting.nfp import minkowski_sum
from dgpc_cli.stages.nest import nest_parts

SCALE = 100.0
SHEET = Sheet(1400.0, 700.0, 10.0, 3.0)
#: A tapered, slightly curved strip (model units): one template.
_T = np.linspace(0.0, 1.0, 11)
_A = np.column_stack([3.0 * _T, 0.05 * np.sin(np.pi * _T)])
_B = np.column_stack([3.0 * _T, 0.5 - 0.3 * _T + 0.05 * np.sin(np.pi * _T)])
TEMPLATE = np.concatenate([_A, _B[::-1]])


def _records(n, turned=(), moved=True, cls="C01"):
    """``n`` copies of the template, each moved elsewhere (as a flat artifact lays them out),
    those in ``turned`` by a half turn."""
    out = []
    for i in range(n):
        R = rotation_matrix(180.0 if i in turned else 0.0)
        shift = np.array([0.37 * i, 1.1 * i]) if moved else np.zeros(2)

        def f(p, R=R, s=shift):
            return (np.asarray(p) @ R.T + s).tolist()
        out.append({"id": f"P{i:02d}", "strip": i, "class": cls, "outline": f(TEMPLATE),
                    "geodesics": [f(_A), f(_B)], "score": [], "label": f([[1.5, 0.2]])[0]})
    return out


def _gaps_and_margin(result, sheet):
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    on = [q.sheet for q in result.placements]
    gaps = [placed[i].distance(placed[j]) for i in range(len(placed))
            for j in range(i + 1, len(placed)) if on[i] == on[j]]
    lo = min(min(p.bounds[0], p.bounds[1]) for p in placed)
    hi_x = max(p.bounds[2] for p in placed)
    hi_y = max(p.bounds[3] for p in placed)
    assert lo >= sheet.margin - 1e-6
    assert hi_x <= sheet.width - sheet.margin + 1e-6
    assert hi_y <= sheet.height - sheet.margin + 1e-6
    return gaps


def test_a_facade_of_one_template_needs_two_no_fit_polygons():
    """Twelve copies of one template, laid out anywhere and some turned by a half turn: one
    shape, and its no-fit polygons with itself at the two relative rotations (0°, 180°) serve
    every part, pair, sheet and both fill directions."""
    records = _records(12, turned={1, 4, 7})
    parts = prepare_parts(records, SCALE, 0.75)
    assert len({p.group for p in parts}) == 1
    assert sorted({p.shape_rotation for p in parts}) == [0.0, 180.0]
    result = nest_parts(records, SHEET, [0.0, 180.0], scale=SCALE)
    info = result.engine_info
    assert info["shapes"] == 1
    assert info["no_fit_polygons"] <= 2
    assert sorted(q.index for q in result.placements) == list(range(12))
    gaps = _gaps_and_margin(result, SHEET)
    assert gaps and min(gaps) >= SHEET.spacing - 1e-6


def test_distinct_parts_share_no_fit_polygons_across_sheets_and_directions():
    """Parts that differ: one no-fit polygon per ordered pair of shapes and relative
    rotation at most, whatever the number of sheets and fill directions."""
    records = []
    for i in range(6):
        rec = _records(1)[0]
        rec["id"], rec["class"] = f"Q{i}", f"C{i}"
        stretch = 1.0 + 0.1 * i
        for key in ("outline", "label"):
            rec[key] = (np.asarray(rec[key]) * [stretch, 1.0]).tolist()
        rec["geodesics"] = [(np.asarray(g) * [stretch, 1.0]).tolist() for g in rec["geodesics"]]
        records.append(rec)
    result = nest_parts(records, Sheet(800.0, 700.0, 10.0, 3.0), [0.0, 180.0], scale=SCALE)
    assert result.engine_info["shapes"] == 6
    assert result.engine_info["no_fit_polygons"] <= 6 * 5 * 2


def test_congruent_tapered_parts_laid_out_apart_are_paired():
    """Congruent tapered strips as a flat artifact lays them out (each elsewhere, some turned):
    they interlock in pairs (engine_info.pairs > 0), the layout keeps the spacing and margin."""
    records = _records(6, turned={2})
    result = nest_parts(records, SHEET, [0.0, 180.0], scale=SCALE)
    assert result.engine_info["pairs"] == 3
    assert {q.rotation for q in result.placements} <= {0.0, 180.0}
    gaps = _gaps_and_margin(result, SHEET)
    assert min(gaps) >= SHEET.spacing - 1e-6
    assert min(gaps) <= SHEET.spacing + 2 * 0.75 + 1e-6      # interlocked: at the spacing


@pytest.mark.parametrize("rot", [0.0, 90.0, 180.0])
def test_reduced_convolution_is_the_minkowski_sum(rot):
    """The reduced-convolution sum equals the union of every pairwise sum of convex pieces
    (the exact sum) for curved, tapered and non-convex outlines."""
    parts = prepare_parts(_records(2), SCALE)
    notch = SCALE * np.array([[0, 0], [2, 0], [2, 1], [1.2, 1], [1.2, 0.4], [0.8, 0.4],
                              [0.8, 1], [0, 1]], float)
    notched = prepare_parts([{"id": "N", "strip": 0, "class": "C", "outline": notch / SCALE,
                              "geodesics": [[[0, 0], [2, 0]], [[0, 1], [2, 1]]],
                              "score": [], "label": [0.2, 0.2]}], SCALE)[0]
    for a, b in ((parts[0], parts[1]), (parts[0], notched), (notched, notched)):
        exact = minkowski_nfp(a.pieces, 0.0, b.pieces, rot, 0.0)
        ours = minkowski_sum(a.outline, -(b.outline @ rotation_matrix(rot).T))
        assert ours is not None
        filled = Polygon(exact.exterior)
        assert ours.symmetric_difference(filled).area <= 1e-6 * filled.area


@pytest.fixture(scope="module")
def flat(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scale")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 360, "-o", folder / "net")
    dgpc("planarize-strips", folder / "net", "-o", folder / "strips")
    dgpc("unfold", folder / "strips", "-o", folder / "flat")
    return folder / "flat"


def _no_nesting(*args, **kwargs):
    raise AssertionError("nested before checking the output")


@pytest.mark.parametrize("force", [False, True])
def test_a_missing_output_folder_fails_before_nesting(flat, tmp_path, monkeypatch, force):
    monkeypatch.setattr("dgpc_cli.stages.nest_run.nest_parts", _no_nesting)
    res = dgpc("nest", flat, "--sheet", "700x500", "--scale", SCALE,
               "-o", tmp_path / "missing" / "sh", *(["--force"] if force else []), expect=1)
    assert "directory does not exist" in res.stderr and len(res.stderr.strip().splitlines()) == 1


def test_an_existing_sheet_file_fails_before_nesting(flat, tmp_path, monkeypatch):
    """A sheet DXF of an earlier run (whatever the sheet count) is refused without --force,
    before any nesting."""
    (tmp_path / "sh.sheet03.dxf").write_text("0\nEOF\n")
    monkeypatch.setattr("dgpc_cli.stages.nest_run.nest_parts", _no_nesting)
    res = dgpc("nest", flat, "--sheet", "700x500", "--scale", SCALE, "-o", tmp_path / "sh",
               expect=1)
    assert "sh.sheet03.dxf" in res.stderr and "--force" in res.stderr


def test_no_preview_writes_the_cut_files_only(flat, tmp_path):
    dgpc("nest", flat, "--sheet", "700x500", "--scale", SCALE, "--no-preview",
         "-o", tmp_path / "sh")
    art = read_sheets(tmp_path / "sh")
    assert not list(tmp_path.glob("sh.sheet*.svg")) and not list(tmp_path.glob("*.png"))
    dxfs = sorted(tmp_path.glob("sh.sheet*.dxf"))
    assert len(dxfs) == art.data["sheet_count"] >= 1
    for path in dxfs:
        check_cam_ready(path)


def test_implausible_scale_is_one_warning_line(flat, tmp_path):
    """A net in m nested as if in mm (parts of a few mm on a 700 × 500 mm sheet): one stderr
    line naming the smallest part and the likely fix; a plausible scale warns nothing."""
    res = dgpc("nest", flat, "--sheet", "700x500", "--no-preview", "-o", tmp_path / "tiny")
    lines = [ln for ln in res.stderr.splitlines() if "implausible scale" in ln]
    assert len(lines) == 1 and "mm long" in lines[0] and "--units m" in lines[0]
    res = dgpc("nest", flat, "--sheet", "700x500", "--scale", SCALE, "--no-preview",
               "-o", tmp_path / "fine")
    assert "implausible" not in res.stderr


def test_an_almost_empty_sheet_warns():
    from dgpc_cli.stages.nest import scale_warning

    parts = prepare_parts(_records(1), SCALE)
    assert scale_warning(parts, [0.2], "m", SCALE) is None
    assert "0.5 % used" in scale_warning(parts, [0.005], "m", SCALE)


def test_full_sheets_are_skipped_without_no_fit_polygons(monkeypatch):
    """Distinct long strips, two to a sheet: a sheet where a part's probe box (inside it) no
    longer fits is skipped, so fewer no-fit polygons are computed for the same layout."""
    records = []
    for i in range(8):
        rec = _records(1)[0]
        rec["id"], rec["class"] = f"L{i}", f"C{i}"
        k = np.array([3.0, 1.0 + 0.05 * i])
        rec["outline"] = (np.asarray(rec["outline"]) * k).tolist()
        rec["label"] = (np.asarray(rec["label"]) * k).tolist()
        rec["geodesics"] = [(np.asarray(g) * k).tolist() for g in rec["geodesics"]]
        records.append(rec)
    sheet = Sheet(1000.0, 120.0, 5.0, 3.0)                     # two to a sheet
    with_probe = nest_parts(records, sheet, [0.0, 180.0], scale=SCALE)
    monkeypatch.setattr("dgpc_cli.nesting.blf.probe_boxes",
                        lambda units, rotations, sheet: {})
    without = nest_parts(records, sheet, [0.0, 180.0], scale=SCALE)
    assert with_probe.placements == without.placements
    assert with_probe.sheet_count == 4 and with_probe.engine_info["shapes"] == 8
    assert with_probe.engine_info["no_fit_polygons"] <= 16      # on its own sheet only
    assert without.engine_info["no_fit_polygons"] == 48


def test_long_parts_cut_on_one_outline_at_their_own_vertices_share_a_shape():
    """A shared-outline template: 6 m parts whose polylines cut one pair of outline curves at
    their own vertices (0.2 mm apart at most) share their no-fit polygons at the grouping
    tolerance of a 3 mm spacing (0.75 mm); sampled too coarsely (a bound above the tolerance),
    every part would be a shape of its own."""
    def curve(t):
        return np.column_stack([6000.0 * t, 40.0 * np.sin(np.pi * t)])

    records = []
    for i in range(4):
        t = np.sort(np.concatenate([[0.0, 1.0], np.linspace(0.0, 1.0, 21)[1:-1]
                                    + 0.004 * np.sin(3.0 * i + np.arange(19))]))
        a, b = curve(t), curve(t) + [0.0, 300.0]
        outline = np.concatenate([a, b[::-1]])
        records.append({"id": f"P{i}", "strip": i, "class": "C01", "outline": outline.tolist(),
                        "geodesics": [a.tolist(), b.tolist()], "score": [],
                        "label": [3000.0, 150.0]})
    apart = max(Polygon(records[0]["outline"]).hausdorff_distance(Polygon(r["outline"]))
                for r in records[1:])
    assert 0.05 < apart < 0.75
    parts = prepare_parts(records, 1.0, tol=0.75)
    assert len({p.group for p in parts}) == 1
    assert all(p.deviation <= 0.75 for p in parts)
