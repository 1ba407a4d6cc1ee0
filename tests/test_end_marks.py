"""End marks: every part on a cut sheet and in its template carries a chevron pointing at its
first-row end and that row's number, inside the part, clear of its score lines."""

import ezdxf
import numpy as np
import pytest
from cli_helpers import dgpc, revolution_strips
from dxf_checks import END_MARK
from shapely.geometry import LineString, Point, Polygon

from dgpc_cli.io.flat import first_row, read_flat
from dgpc_cli.io.sheets import read_sheets, transform
from dgpc_cli.nesting.end_mark import row_text

SCALE = 10.0            # the net in cm, ten times: 1 net unit = 100 mm
MM = 10.0 * SCALE


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    folder = tmp_path_factory.mktemp("endmark")
    revolution_strips(folder, "catenoid", 13, 5, 120, "cm", net="cat")
    dgpc("unfold", folder / "s", "-o", folder / "flat")
    dgpc("nest", folder / "flat", "--sheet", "1200x800", "--rotations", "0,90,180,270",
         "--scale", SCALE, "-o", folder / "sh")
    # boards, all placed turned end-for-end
    dgpc("unfold", folder / "s", "--stock-length", 2, "-o", folder / "boards")
    dgpc("nest", folder / "boards", "--sheet", "1200x800", "--rotations", "180",
         "--scale", SCALE, "-o", folder / "bsh")
    return folder


def _marks(msp, layer="LABEL"):
    chevrons = [np.array(e.get_points("xy")) for e in msp.query(f"LWPOLYLINE[layer=='{layer}']")
                if len(e) == 3]
    rows = [(e.dxf.text, np.array(e.dxf.align_point if e.dxf.halign or e.dxf.valign
                                    else e.dxf.insert)[:2])
            for e in msp.query(f"TEXT[layer=='{layer}']") if END_MARK.fullmatch(e.dxf.text)]
    return chevrons, rows


@pytest.mark.parametrize("flat_stem, sheets", [("flat", "sh"), ("boards", "bsh")])
def test_every_sheet_part_has_its_end_mark_at_its_first_row(sample, flat_stem, sheets):
    art = read_sheets(sample / sheets)
    flat = {p["id"]: p for p in read_flat(sample / flat_stem).parts}
    checked = 0
    for s, rec in enumerate(art.data["sheets"]):
        msp = ezdxf.readfile(art.file(rec["dxf"])).modelspace()
        chevrons, rows = _marks(msp)
        score = [LineString(np.array(e.get_points("xy")))
                 for e in msp.query("LWPOLYLINE[layer=='SCORE']")]
        for pl in (p for p in art.data["placements"] if p["sheet"] == s):
            part = flat[pl["part"]]

            def place(x, pl=pl):
                return transform(MM * np.asarray(x, float), pl["rotation"], pl["translation"])

            outline = Polygon(place(part["outline"]))
            A, B = (place(g) for g in part["geodesics"])
            first, last = LineString([A[0], B[0]]), LineString([A[-1], B[-1]])
            mine = [c for c in chevrons if outline.contains(LineString(c))]
            assert len(mine) == 1, pl["part"]
            c = mine[0]
            apex = Point(c[1])
            assert apex.distance(first) < apex.distance(last)
            # the chevron points at the first-row end: its apex nearer that end than its arms
            assert apex.distance(first) < min(Point(c[0]).distance(first),
                                              Point(c[2]).distance(first))
            assert not any(LineString(c).intersects(line) for line in score)
            texts = [t for t, at in rows if outline.contains(Point(at))]
            assert texts == [row_text(first_row(part))]
            checked += 1
    assert checked == len(flat) > 0


def test_template_has_its_end_mark(sample):
    folder = sample
    dxfs = sorted(folder.glob("flat.C*.dxf"))
    assert dxfs
    for path in dxfs:
        msp = ezdxf.readfile(path).modelspace()
        chevrons, rows = _marks(msp)
        (cut,) = [Polygon(np.array(e.get_points("xy")))
                  for e in msp.query("LWPOLYLINE[layer=='CUT']")]
        assert len(chevrons) == 1 and len(rows) == 1
        assert cut.contains(LineString(chevrons[0]))
        assert cut.contains(Point(rows[0][1]))


def test_a_board_cut_inside_a_quad_is_marked_with_its_fractional_row():
    """A board whose first end is a joint inside quad 3 at 0.5512 of its sides starts at row
    3.5512: its mark reads R3.55, not R3 (the ruling it does not reach)."""

    record = {"rows": [3, 7], "row_span": [3.5512, 7.0]}
    assert first_row(record) == 3.5512
    assert row_text(first_row(record)) == "R3.55"
    assert row_text(first_row({"rows": [4, 9]})) == "R4"
    assert row_text(0.999999) == "R1"
