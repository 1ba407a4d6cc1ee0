"""Lower bounds on the sheet count (dgpc_cli.nesting.bounds): the parts' area, and the sheet's
centre line that every part longer than half the sheet crosses; the fill reaches them on sets
of long boards, overlap-free; spyrrow's sheets take boards nearly as long as the sheet."""

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon

from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.bounds import _least_section, sheet_lower_bounds
from dgpc_cli.nesting.geometry import prepare_parts, transform
from dgpc_cli.stages.nest import nest_parts

ROT = [0.0, 180.0]


def _record(i, outline):
    outline = np.asarray(outline, float)
    n = len(outline) // 2
    return {"id": f"B{i:02d}", "strip": i, "class": f"C{i:02d}", "outline": outline.tolist(),
            "geodesics": [outline[:n].tolist(), outline[n:][::-1].tolist()], "score": [],
            "label": outline.mean(axis=0).tolist()}


def _rectangle(length, width):
    return [[0, 0], [length / 2, 0], [length, 0], [length, width], [length / 2, width],
            [0, width]]


def _overlap_free(result):
    """Every part inside the margin, every two on one sheet at least the spacing apart."""
    sheet = result.sheet
    placed = [Polygon(transform(result.parts[q.index].outline, q.rotation, q.translation))
              for q in result.placements]
    on = [q.sheet for q in result.placements]
    for p in placed:
        x0, y0, x1, y1 = p.bounds
        assert min(x0, y0) >= sheet.margin - 1e-6
        assert x1 <= sheet.width - sheet.margin + 1e-6
        assert y1 <= sheet.height - sheet.margin + 1e-6
    for i in range(len(placed)):
        for j in range(i + 1, len(placed)):
            if on[i] == on[j]:
                assert placed[i].distance(placed[j]) >= sheet.spacing - 1e-6


def test_boards_longer_than_half_the_sheet_need_one_row_each():
    """Nine 600 × 100 mm boards on 1000 × 500 sheets: each crosses the centre line, four fit
    across it (4 × 100 + 3 × 3 ≤ 480, five do not), so 3 sheets, though their area fills 2;
    the fill uses exactly 3."""
    records = [_record(i, _rectangle(600.0, 100.0)) for i in range(9)]
    sheet = Sheet(1000.0, 500.0, 10.0, 3.0)
    bound = sheet_lower_bounds(prepare_parts(records, 1.0), 1000.0, 500.0, 10.0, 3.0, ROT)
    assert bound == {"area": 2, "centre_line": 3, "sheets": 3}
    result = nest_parts(records, sheet, ROT)
    assert result.sheet_count == 3
    _overlap_free(result)


def test_boards_shorter_than_half_the_sheet_need_not_cross_it():
    records = [_record(i, _rectangle(480.0, 100.0)) for i in range(9)]
    bound = sheet_lower_bounds(prepare_parts(records, 1.0), 1000.0, 500.0, 10.0, 3.0, ROT)
    assert bound["centre_line"] == 0 and bound["sheets"] == bound["area"] == 1


def test_a_slanted_end_crossing_the_line_counts_its_narrowest_section():
    """A board 520 mm long with one end slanted (1.2 mm along per mm across) on a sheet 1000
    wide: it crosses the centre line anywhere from 30 mm off its left end (inner half width
    490) to 490 mm; its narrowest section there is 25 mm (at 30 mm), not its width of 100 mm.
    The bound is then loose (17 such sections fit across the line), never wrong."""
    part = prepare_parts([_record(0, [[0, 0], [260, 0], [400, 0], [520, 100], [260, 100],
                                      [120, 100]])], 1.0)[0]
    least = _least_section(part, 0.0, 1000.0, 10.0)
    assert least == pytest.approx(25.0, abs=1e-3)
    # dense sampling of the crossing range never finds a narrower one
    o = part.outline - part.outline.min(axis=0)
    poly = Polygon(o)
    for u in np.linspace(30.0, 490.0, 461):
        assert poly.intersection(LineString([(u, -1), (u, 101)])).length >= least - 1e-6
    records = [_record(i, [[0, 0], [260, 0], [400, 0], [520, 100], [260, 100], [120, 100]])
               for i in range(18)]
    bound = sheet_lower_bounds(prepare_parts(records, 1.0), 1000.0, 500.0, 10.0, 3.0, ROT)
    assert bound["centre_line"] == 2        # ⌈18 / 17⌉


def board_set(seed, n, width=1500.0):
    """``n`` boards as unfold cuts them (a family for the fill): lengths 30-95 % of the sheet's
    inner width, 140-190 mm wide, slightly tapered and bowed, ends slanted."""
    rng = np.random.default_rng(seed)
    records = []
    for i in range(n):
        length = rng.uniform(0.3, 0.95) * (width - 20.0)
        w = rng.uniform(140.0, 190.0)
        taper = rng.uniform(-0.08, 0.08) * w
        s0, s1 = rng.uniform(-0.4, 0.4, 2) * w
        bow = rng.uniform(-0.03, 0.03) * w
        t = np.linspace(0.0, 1.0, 5)
        a = np.column_stack([t * length, bow * np.sin(np.pi * t)])
        b = np.column_stack([t * length + (1 - t) * s0 + t * s1,
                             w + taper * t + bow * np.sin(np.pi * t)])
        shift = max(0.0, -s0, -s1)
        records.append(_record(i, np.concatenate([a, b[::-1]]) + [shift, 0.0]))
    return records


#: Sheets the fill uses for the family (deterministic) and the lower bound: the fill is at the
#: bound or one sheet above it (where the bound is loose or the fill short of it).
FAMILY = {0: (3, 3), 1: (3, 2), 2: (3, 2)}


@pytest.mark.parametrize("seed", sorted(FAMILY))
def test_a_family_of_board_sets_nests_at_or_near_the_bound(seed):
    records = board_set(seed, 14)
    sheet = Sheet(1500.0, 750.0, 10.0, 3.0)
    result = nest_parts(records, sheet, ROT)
    bound = sheet_lower_bounds(result.parts, sheet.width, sheet.height, sheet.margin,
                               sheet.spacing, ROT)
    assert bound["sheets"] <= result.sheet_count <= bound["sheets"] + 1
    assert (result.sheet_count, bound["sheets"]) == FAMILY[seed]
    _overlap_free(result)


def test_spyrrow_sheets_take_boards_nearly_as_long_as_the_sheet():
    """Boards 975 mm long on a sheet 980 mm wide inside its margin, 8 mm apart: spyrrow keeps
    the spacing from the strip's ends too, so its layout starts 8 mm in; the sheets measure
    from its left-most point (it used to find every board too long and stop). 4 a sheet."""
    records = [_record(i, _rectangle(975.0, 100.0)) for i in range(5)]
    result = nest_parts(records, Sheet(1000.0, 500.0, 10.0, 8.0), ROT, engine="spyrrow",
                        time_limit=1)
    assert result.sheet_count == 2
    _overlap_free(result)


def test_sections_that_fill_the_line_add_up_though_their_count_fits():
    """The demo's boards in small: eight 600 × 112 mm boards (four fill the line across a
    1000 × 500 sheet: 4 × 112 + 9 ≤ 480) and two shorter boards whose slanted ends cross it
    with 25 mm. Counted, five sections fit across the line (two ends and three boards), so two
    sheets; added up, the sections and their spacing are 976 mm for 2 × 483 of line, so three
    sheets, and the fill takes exactly three."""
    slanted = [[0, 0], [260, 0], [400, 0], [520, 100], [260, 100], [120, 100]]
    records = ([_record(i, _rectangle(600.0, 112.0)) for i in range(8)]
               + [_record(8 + i, slanted) for i in range(2)])
    parts = prepare_parts(records, 1.0)
    bound = sheet_lower_bounds(parts, 1000.0, 500.0, 10.0, 3.0, ROT)
    assert bound == {"area": 2, "centre_line": 3, "sheets": 3}
    counted = sorted(min(_least_section(p, r, 1000.0, 10.0 + 1e-4) for r in ROT)
                     for p in parts)
    assert counted[:2] == pytest.approx([25.0, 25.0], abs=0.01)
    assert sum(counted[:5]) + 4 * 3.0 <= 500.0 - 2 * 10.0 < sum(counted[:6]) + 5 * 3.0
    result = nest_parts(records, Sheet(1000.0, 500.0, 10.0, 3.0), ROT)
    assert result.sheet_count == 3
    _overlap_free(result)
