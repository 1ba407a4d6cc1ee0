"""Issue 14 done-means: every DXF the pipelines write goes to a CAM as it is (re-read by ezdxf and
dxfgrabber: CUT closed, no label over a cut or score line, no duplicate or zero-length segment,
extents set, audit clean), and the Gehry facade declared in metres is drawn in millimetres."""

import json
import re

import ezdxf
import numpy as np
import pytest
from dxf_checks import END_MARK, check_cam_ready, text_boxes
from shapely.geometry import LineString, Point, Polygon

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.mold import read_mold
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.report.mold import profile_figure


@pytest.mark.parametrize("name", ["gehry-facade", "timber-cladding"])
def test_every_dxf_of_the_pipelines_is_cam_ready(pipeline_run, name):
    d = pipeline_run(name)
    sheets = read_sheets(d / "sheets")
    expected = {sheets.file(s["dxf"]).name for s in sheets.data["sheets"]}
    if name == "gehry-facade":
        expected |= {"mold.profile.dxf", "sheets.moldmap.dxf"}
    # one DXF per cutting template, as unfold lists them
    files = json.loads((d / "flat.json").read_text())["data"]["files"]
    expected |= {f["path"] for key, f in files.items() if key.startswith("template_")}
    assert {p.name for p in d.glob("*.dxf")} == expected
    for path in sorted(d.glob("*.dxf")):
        check_cam_ready(path)
    parts = {p["id"]: p for p in read_flat(d / "flat").parts}
    params = json.loads((d / "sheets.json").read_text())["parameters"]
    if name == "timber-cladding":              # timber: a router, ids engraved as strokes
        assert (params["tool"], params["spacing"], params["label_style"]) == \
            ("router", 8.0, "stroke")
    for sheet in sheets.data["sheets"]:
        doc = ezdxf.readfile(sheets.file(sheet["dxf"]))
        cut = [Polygon(e.get_points("xy")) for e in doc.modelspace().query(
            "LWPOLYLINE[layer=='CUT']")]
        assert "SHEET_BORDER" not in doc.layers           # no border: nest --border not given
        if params["label_style"] == "stroke":
            # every part's id engraved inside its own outline, where its label record says
            strokes = [LineString(e.get_points("xy")) for e in doc.modelspace().query(
                "LWPOLYLINE[layer=='ENGRAVE']")]
            for pl in sheets.data["placements"]:
                if pl["sheet"] != sheet["index"] or pl["label"]["leader"]:
                    continue
                (home,) = [poly for poly in cut if poly.contains(Point(pl["label"]["at"]))]
                near = [s for s in strokes if s.distance(Point(pl["label"]["at"]))
                        <= len(pl["part"]) * pl["label"]["height"]]
                assert near and all(home.contains(s) for s in near), pl["part"]
            continue
        labels = [(t, b) for t, b in text_boxes(doc) if not END_MARK.fullmatch(t)]
        marks = [b for t, b in text_boxes(doc) if END_MARK.fullmatch(t)]
        # every part labelled with its full id, inside its own outline, and end-marked
        assert sorted(t for t, _ in labels) == sheet["parts"]
        for text, box in labels:
            assert sum(poly.contains(box) for poly in cut) == 1, text
            assert text in parts
        assert sorted(sum(poly.contains(b) for b in marks) for poly in cut) == [1] * len(cut)


def test_gehry_profile_is_drawn_in_mm(pipeline_run):
    """The facade is declared in m (init --units m): both DXFs draw its profile in mm, as tall as
    the mold (a 5 m facade is some 5,000 mm, not 5); the figures and tables say m."""
    d = pipeline_run("gehry-facade")
    mold = read_mold(d / "mold")
    assert mold.units == "m"
    height_mm = 1000.0 * float(np.ptp(mold.h))
    assert 4000.0 < height_mm < 6000.0
    for path in (d / "mold.profile.dxf", d / "sheets.moldmap.dxf"):
        (profile,) = ezdxf.readfile(path).modelspace().query("LWPOLYLINE[layer=='PROFILE']")
        h = np.array(profile.get_points("xy"))[:, 1]
        assert abs(float(np.ptp(h)) - height_mm) <= 1e-6, path
    fig = profile_figure(mold.r, mold.h, unit=mold.units, title="profile")
    assert (fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()) == ("r [m]", "h [m]")
    html = (d / "report-mold-index.html").read_text()
    overview = (d / "report-index.html").read_text()         # one page: facade to mold
    for name in ("facade-1", "strips", "flat", "sheets", "mold"):
        assert f'href="report-{name}-index.html"' in overview, name
    assert "lengths in <b>m</b>" in html and "(r, h in m)" in html
    assert re.search(r"<tr><td>height</td><td[^>]*>5\.[0-9]+</td><td>m</td></tr>", html)
