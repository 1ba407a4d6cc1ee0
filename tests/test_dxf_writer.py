"""Issue 14 item 3: the one DXF writer (dgpc_cli.io.dxf) and where labels go on a sheet.

Re-read with ezdxf and dxfgrabber (tests/dxf_checks.py): no zero-length or repeated segment,
CUT closed only, extents, audit; labels fitted inside their part, a short id with a leader when
the part is too small."""

import ezdxf
import numpy as np
import pytest
from cli_helpers import dgpc
from dxf_checks import check_cam_ready, grabber_polylines, segment_faults
from ezdxf import bbox
from shapely.geometry import LineString, Polygon

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.dxf import SHEET_LAYERS, Drawing, Layer, text_box
from dgpc_cli.nesting.labels import MAX_TEXT_MM, MIN_TEXT_MM, place_labels


def test_zero_length_and_repeated_segments_are_drawn_once(tmp_path):
    d = Drawing({"A": Layer(1), "B": Layer(5)})
    square = [(0, 0), (10, 0), (10, 10), (0, 10)]
    d.polyline("A", square, closed=True)
    d.polyline("B", [(10, 0), (10, 10), (20, 10), (20, 10), (20, 0)])   # a shared side, a dot
    d.polyline("B", [(0, 0), (10, 0)])                                  # all drawn before
    d.polyline("B", [(5, 5), (5, 5)])                                   # zero length only
    path = tmp_path / "a.dxf"
    path.write_bytes(d.to_bytes())
    lines = grabber_polylines(path)
    assert segment_faults(lines) == (0, 0)
    assert [(layer, len(p), closed) for layer, p, closed in lines] == [
        ("A", 4, True), ("B", 3, False)]                        # (10,10)-(20,10)-(20,0)
    assert segment_faults([("x", np.array(square, float), True)] * 2) == (4, 0)  # the check


def test_a_cut_outline_is_never_split():
    d = Drawing(SHEET_LAYERS)
    d.polyline("CUT", [(0, 0), (10, 0), (10, 10)], closed=True)
    d.polyline("CUT", [(10, 0), (0, 0), (0, -10)], closed=True)          # shares a side
    with pytest.raises(DgpcError, match="cut outline repeats a line"):
        d.to_bytes("x")
    with pytest.raises(ValueError, match="closed outlines only"):
        d.polyline("CUT", [(0, 0), (1, 1)])


def test_header_extents_hold_lines_and_text(tmp_path):
    d = Drawing(SHEET_LAYERS)
    d.polyline("CUT", [(0, 0), (100, 0), (100, 20)], closed=True)
    d.text("LABEL", "S-v01", (50, 40), 10.0)
    path = tmp_path / "t.dxf"
    path.write_bytes(d.to_bytes())
    doc = ezdxf.readfile(path)
    lo, hi = np.array(doc.header["$EXTMIN"][:2]), np.array(doc.header["$EXTMAX"][:2])
    (text,) = doc.modelspace().query("TEXT")
    drawn = bbox.extents([text], fast=False)           # the text as its font draws it
    assert np.allclose(lo, [0, 0]) and np.allclose(hi, [100, drawn.extmax.y])
    # not dgpc's wider estimate of the text's box (the mold map's extents were half again
    # as wide as its drawing)
    assert hi[1] < text_box("S-v01", 10.0, (50, 40))[:, 1].max() - 0.5
    check_cam_ready(path)


def test_an_audit_error_is_exit_1_and_nothing_is_written(tmp_path, monkeypatch):
    """ezdxf's audit runs when a DXF is made: an error there stops the command."""
    from ezdxf.document import Drawing as Document

    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 7, "--cols", 5,
         "-o", tmp_path / "n")
    dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s")
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    before = sorted(p.name for p in tmp_path.iterdir())
    audit = Document.audit

    def failing_audit(self):
        auditor = audit(self)
        auditor.add_error(999, "a planted error")
        return auditor

    monkeypatch.setattr(Document, "audit", failing_audit)
    res = dgpc("nest", tmp_path / "f", "--sheet", "3000x2000", "-o", tmp_path / "sh",
               expect=1)
    (line,) = [x for x in res.stderr.splitlines() if x.startswith("Error")]   # one line
    assert line.startswith("Error: sheet SH01: the DXF does not pass ezdxf's audit")
    assert "a planted error" in line and "nothing written" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def _strip(length, width, cells, at=(0.0, 0.0)):
    """A straight strip ``length × width`` of ``cells`` equal cells, as a placed part."""
    x = np.linspace(0.0, length, cells + 1) + at[0]
    A = np.column_stack([x, np.full_like(x, at[1])])
    B = np.column_stack([x, np.full_like(x, at[1] + width)])
    return {"geodesics": [A, B], "outline": np.concatenate([A, B[::-1]]),
            "score": [np.array([A[u], B[u]]) for u in range(1, cells)],
            "label": 0.5 * (A[cells // 2] + B[cells // 2])}


def _crossings(label, parts):
    box = Polygon(label.box())
    lines = [LineString(np.concatenate([p["outline"], p["outline"][:1]])) for p in parts]
    lines += [LineString(s) for p in parts for s in p["score"]]
    return sum(box.intersects(line) for line in lines)


def test_labels_are_fitted_inside_a_cell():
    parts = [{"id": f"S-v0{k}", **_strip(1200.0, w, 6, (0.0, 100.0 * k))}
             for k, w in enumerate((20.0, 40.0, 80.0))]
    labels = place_labels(parts, 1300.0, 400.0)
    heights = [lb.height for lb in labels]
    assert [lb.text for lb in labels] == ["S-v00", "S-v01", "S-v02"]
    assert MIN_TEXT_MM <= heights[0] < heights[1] < heights[2] <= MAX_TEXT_MM
    for lb, p in zip(labels, parts, strict=True):
        assert lb.leader is None and _crossings(lb, parts) == 0
        assert Polygon(p["outline"]).contains(Polygon(lb.box()))


def test_a_small_part_gets_its_short_id_and_then_a_leader():
    narrow = {"id": "S-v07.2", **_strip(20.0, 6.0, 1, (100.0, 100.0))}   # "07.2" fits
    tiny = {"id": "S-v08.1", **_strip(8.0, 4.0, 2, (200.0, 100.0))}      # nothing fits
    big = {"id": "S-v09.1", **_strip(400.0, 150.0, 4, (250.0, 40.0))}
    parts = [narrow, tiny, big]
    labels = place_labels(parts, 700.0, 300.0)
    assert labels[0].text == "07.2" and labels[0].leader is None
    assert labels[0].height >= MIN_TEXT_MM
    assert Polygon(narrow["outline"]).contains(Polygon(labels[0].box()))
    lb = labels[1]
    assert lb.text == "08.1" and lb.height == MIN_TEXT_MM and lb.leader is not None
    box = Polygon(lb.box())
    assert _crossings(lb, parts) == 0                      # beside every part, on the sheet
    assert all(box.distance(Polygon(p["outline"])) > 0 for p in parts)
    assert not any(box.intersects(Polygon(other.box())) for other in (labels[0], labels[2]))
    assert Polygon([(0, 0), (700, 0), (700, 300), (0, 300)]).contains(box)
    start, end = lb.leader
    assert Polygon(tiny["outline"]).contains(LineString([start, start]).centroid)
    assert box.exterior.distance(LineString([end, end]).centroid) < 1e-9
    assert labels[2].text == "S-v09.1" and labels[2].leader is None
