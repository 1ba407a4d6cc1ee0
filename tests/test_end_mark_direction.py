"""End marks on the part's axis, read back from the DXF files (ezdxf): on every part of the demo
(its two cut sheets and its twelve copy templates) and of every gallery shape's templates, the
chevron opens along the part and points at its first-row end, its row number reads along the
part, and it is as large as the part's width allows (before, on 7 of the demo's 12 parts the
`R0` mark stood turned 90° and small)."""

import ezdxf
import numpy as np
import pytest
from end_mark_checks import along_the_part, read_mark

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.sheets import read_sheets, transform
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.nesting.end_mark import WIDTH_FRACTION
from dgpc_cli.nesting.labels import MAX_TEXT_MM

#: The gallery's shapes (pipelines/gallery.mk).
GALLERY = ("sphere-zone", "cylinder", "catenoid", "sphere", "bowling-pin", "wall")


def _template_frame(part: dict, rep: dict, k: float, per_copy: bool):
    """The map of a part's coordinates (artifact unit) into its template DXF: the copy carried
    onto its representative by its alignment (a per-copy file), then the representative's
    bounding box's lower-left corner at the origin (``nesting.template``)."""
    low = k * np.asarray(rep["outline"], float).min(axis=0)
    R = np.asarray(part["alignment"]["matrix"], float) if per_copy else np.eye(2)
    t = k * np.asarray(part["alignment"]["translation"], float) if per_copy else np.zeros(2)

    def move(x):
        return (k * np.asarray(x, float)) @ R.T + t - low
    return move


def template_readings(flat_stem):
    """``(file name, part id, MarkReading, width at the first end in mm)`` of every template
    DXF of the flat artifact ``flat_stem``."""
    flat = read_flat(flat_stem)
    k = mm_per_unit(flat.units)
    by_id = {p["id"]: p for p in flat.parts}
    out = []
    for cls in flat.classes:
        rep = by_id[cls["representative"]]
        per_copy = cls.get("score_lines") == "per copy"
        for member in (cls["members"] if per_copy else [rep["id"]]):
            name = f"{flat_stem.name}.{cls['id']}" + (f".{member}" if per_copy else "") + ".dxf"
            msp = ezdxf.readfile(flat_stem.parent / name).modelspace()
            layer = "ENGRAVE" if len(msp.query("*[layer=='ENGRAVE']")) else "LABEL"
            part = by_id[member]
            move = _template_frame(part, rep, k, per_copy)
            cut = np.array(msp.query("LWPOLYLINE[layer=='CUT']")[0].get_points("xy"))
            outline = move(part["outline"])
            assert np.abs(outline.min(axis=0) - cut.min(axis=0)).max() < 1e-6   # the frame
            A, B = (move(g) for g in part["geodesics"])
            out.append((name, member, read_mark(msp, layer, cut, A, B),
                        float(np.linalg.norm(B[0] - A[0]))))
    return out


def sheet_readings(sheets_stem, flat_stem):
    """``(sheet, part id, MarkReading, width at the first end in mm)`` of every placed part."""
    art = read_sheets(sheets_stem)
    flat = read_flat(flat_stem)
    k = art.parameters.get("scale", 1.0) * mm_per_unit(flat.units)
    by_id = {p["id"]: p for p in flat.parts}
    out = []
    for s, rec in enumerate(art.data["sheets"]):
        msp = ezdxf.readfile(art.file(rec["dxf"])).modelspace()
        layer = "ENGRAVE" if len(msp.query("*[layer=='ENGRAVE']")) else "LABEL"
        for pl in (p for p in art.data["placements"] if p["sheet"] == s):
            part = by_id[pl["part"]]

            def place(x, pl=pl):
                return transform(k * np.asarray(x, float), pl["rotation"], pl["translation"])

            A, B = (place(g) for g in part["geodesics"])
            out.append((rec["dxf"], pl["part"], read_mark(msp, layer, place(part["outline"]),
                                                           A, B),
                        float(np.linalg.norm(B[0] - A[0]))))
    return out


def _as_large_as_allowed(reading, width, share=0.5):
    """At least ``share`` of the largest mark the part's width allows."""
    return reading.height >= share * min(WIDTH_FRACTION * width, MAX_TEXT_MM)


def test_every_demo_part_on_the_cut_sheets_is_marked_along_its_axis(demo_run):
    readings = sheet_readings(demo_run / "sheets", demo_run / "flat")
    assert len(readings) == 12
    for sheet, part, reading, width in readings:
        assert along_the_part(reading), (sheet, part, reading)
        assert _as_large_as_allowed(reading, width), (sheet, part, reading, width)


def test_every_demo_template_is_marked_along_its_axis(demo_run):
    readings = template_readings(demo_run / "flat")
    assert len(readings) == 12                     # one template, a file per copy
    for name, part, reading, width in readings:
        assert along_the_part(reading), (name, part, reading)
        assert _as_large_as_allowed(reading, width), (name, part, reading, width)


@pytest.mark.parametrize("shape", GALLERY)
def test_every_gallery_template_is_marked_along_its_axis(pipeline_run, shape):
    readings = template_readings(pipeline_run("gallery") / f"{shape}-flat")
    assert readings
    for name, part, reading, _ in readings:
        assert along_the_part(reading), (name, part, reading)
        assert reading.text == "R0"


def test_the_checker_sees_a_mark_turned_across_the_part(tmp_path):
    """The reading is not blind: a chevron turned 90° (pointing at a long edge) and a number
    reading across the part fail it."""
    from dgpc_cli.io.dxf import Drawing
    from dgpc_cli.nesting.drawing import sheet_layers

    A = np.array([[0.0, 0.0], [200.0, 0.0], [400.0, 0.0]])
    B = A + [0.0, 300.0]
    outline = np.concatenate([A, B[::-1]])
    d = Drawing(sheet_layers(False, "text"))
    d.polyline("CUT", outline, closed=True)
    h = 30.0
    apex = np.array([50.0, 100.0])                  # opening across the part: +y
    d.polyline("LABEL", np.array([apex + [0.5 * h, 0.6 * h], apex, apex + [-0.5 * h, 0.6 * h]]))
    d.text("LABEL", "R0", (50.0, 160.0), h, rotation=90.0)
    path = tmp_path / "turned.dxf"
    path.write_bytes(d.to_bytes("turned"))
    reading = read_mark(ezdxf.readfile(path).modelspace(), "LABEL", outline, A, B)
    assert reading.chevron_deg == pytest.approx(90.0) and reading.reading_deg == \
        pytest.approx(90.0)
    assert not along_the_part(reading)
