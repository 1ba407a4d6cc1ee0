"""Trimmed parts that can be made (issue 27: no part narrower than a quarter of the mean width):
a whole strip's part follows its geodesics row by row, the rows where a strip pinches are cut
off and slivers along the outline dropped, with the area they leave bare; boards of the default
stagger are cut where no ruling keeps it, with a warning."""

import logging
from types import SimpleNamespace

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.soundness import require_sound_strips
from dgpc_cli.stages.unfold import part_narrowness
from dgpc_cli.strips.boards import split_run
from dgpc_cli.strips.develop import develop_strip, signed_area
from dgpc_cli.strips.pinch import PINCH, row_widths, unpinched, widest_section
from dgpc_cli.strips.planarize import trim_records
from dgpc_cli.strips.trim import developed_part, part_area, through_rows, trim_strip


def square(x0, x1, y0, y1):
    V = np.array([[x0, y0, 0], [x1, y0, 0], [x1, y1, 0], [x0, y1, 0.0]])
    return ReferenceSurface(V, np.array([[0, 1, 2], [0, 2, 3]]))


def arc_strip(m=9):
    """A plane strip between the arcs of radius 5 and 6 over a quarter turn (8 quads): its
    outline is the polygon of both arcs, of area 11 sin(π/16) · 4 = 8.58; its four corners
    alone span the quadrilateral of area 5.5."""
    a = np.linspace(0.0, np.pi / 2, m)
    u = np.stack([np.cos(a), np.sin(a), np.zeros(m)], 1)
    return 5 * u, 6 * u


def test_a_rectangle_in_the_strip_parameters_runs_through_every_row():
    ring = through_rows(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]]))
    assert ring.tolist() == [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1], [2, 1], [1, 1], [0, 1]]
    tri = through_rows(np.array([[0.5, 0.0], [2.5, 0.5], [0.2, 1.0]]))
    assert tri[:, 0].tolist() == [0.5, 1.0, 2.0, 2.5, 2.0, 1.0, 0.2]
    assert tri[1, 1] == pytest.approx(0.125) and tri[4, 1] == pytest.approx(0.5 + 0.5 * 0.5 / 2.3)


def test_a_whole_strip_part_has_the_strip_area_and_outline():
    """A curved strip wholly over the reference: its one part is the whole developed strip,
    not the quadrilateral of its four corners."""
    A, B = arc_strip()
    reference = square(-1.0, 7.0, -1.0, 7.0)
    (part,) = trim_strip(A, B, reference)
    dev = develop_strip(A, B)
    area = 0.5 * 11 * np.sin(np.pi / 16) * 8
    assert abs(signed_area(dev.outline)) == pytest.approx(area, rel=1e-9)
    assert part_area(dev.A, dev.B, part.outline) == pytest.approx(area, rel=1e-9)
    corners = np.array([[0.0, 0.0], [8.0, 0.0], [8.0, 1.0], [0.0, 1.0]])
    assert part_area(dev.A, dev.B, corners) == pytest.approx(area, rel=1e-9)
    assert abs(signed_area(developed_part(dev.A, dev.B, corners)["outline"])) == \
        pytest.approx(area, rel=1e-9)


def fan(n=4, m=11, length=10.0):
    """``n`` plane strips of a fan: geodesics from the x axis converging to the point
    (length, 0); strip widths at x = 0 of 1, shrinking linearly to 0 at the tip."""
    x = np.linspace(0.0, length, m)
    lines = [np.stack([x, (k - n / 2) * (1 - x / length), np.zeros(m)], 1) for k in range(n + 1)]
    return [SimpleNamespace(id=f"S-v{k:02d}", A=lines[k], B=lines[k + 1]) for k in range(n)]


def test_pinched_ends_are_cut_off_and_their_area_counted():
    """Strips converging to a point: each loses its rows narrower than a quarter of the
    parts' mean width (about 0.5: widths from 1 down to 0), the area cut off is recorded and
    noted; what is kept is nowhere narrower."""
    strips = fan()
    devs = [develop_strip(s.A, s.B) for s in strips]
    mean = sum(abs(signed_area(d.outline)) for d in devs) / sum(d.length for d in devs)
    records, notes = trim_records(strips, square(-1.0, 20.0, -5.0, 5.0))
    for strip, dev, record in zip(strips, devs, records, strict=True):
        (part,) = record["parts"]
        ring = np.asarray(part["outline"], float)
        kept = developed_part(dev.A, dev.B, ring)
        ga, gb = (LineString(g) for g in kept["geodesics"])
        least = min(min(gb.distance(Point(p)) for p in kept["geodesics"][0]),
                    min(ga.distance(Point(p)) for p in kept["geodesics"][1]))
        assert PINCH * mean <= least <= 1.05 * PINCH * mean, strip.id
        (cut,) = record["dropped"]
        assert cut["reason"] == "pinched" and cut["rows"][1] == pytest.approx(10.0)
        whole = abs(signed_area(dev.outline))
        assert cut["area"] == pytest.approx(whole - part_area(dev.A, dev.B, ring), rel=1e-6)
        assert cut["area"] == pytest.approx(whole * (PINCH * mean) ** 2, rel=0.1)
    assert len(notes) == 1 and "S-v00, S-v01, S-v02, S-v03" in notes[0]
    assert "cut off" in notes[0]


def test_a_sliver_along_the_outline_is_dropped():
    """Three strips 1 wide across a plate 2.1 wide: the third keeps a sliver 0.1 wide, less
    than a quarter of the parts' mean width (0.7): dropped, with its area noted."""
    x = np.arange(0.0, 11.0)
    line = [np.stack([x, np.full_like(x, y), np.zeros_like(x)], 1) for y in (0.0, 1.0, 2.0, 3.0)]
    strips = [SimpleNamespace(id=f"S-v{k:02d}", A=line[k], B=line[k + 1]) for k in range(3)]
    records, notes = trim_records(strips, square(-1.0, 11.0, -0.5, 2.1))
    assert [len(r["parts"]) for r in records] == [1, 1, 0]
    (sliver,) = records[2]["dropped"]
    assert sliver["reason"] == "sliver" and sliver["area"] == pytest.approx(1.0, rel=1e-6)
    assert any("S-v02" in n and "narrower everywhere" in n for n in notes)


def test_a_part_as_wide_as_the_least_is_kept_whole():
    widths = np.array([1.0, 1.0, 1.0])
    ring = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    assert unpinched(ring, widths, 0.25)[0] is ring
    assert widest_section(ring, widths) == pytest.approx(1.0)
    strip = fan(n=2, m=3)[0]                  # from (0, -1) to the tip (10, 0), B on y = 0
    assert row_widths(strip.A, strip.B) == pytest.approx(
        [np.cos(np.arctan(0.1)), 0.5 * np.cos(np.arctan(0.1)), 0.0], abs=1e-12)


def test_the_narrowest_part_is_measured_against_the_mean_width():
    parts = [{"id": "a", "length": 10.0, "area": 10.0, "width": [0.9, 1.1]},
             {"id": "b", "length": 10.0, "area": 2.0, "width": [0.1, 0.3]}]
    n = part_narrowness(parts)
    assert n["mean_width_mm"] == pytest.approx(0.6)
    assert n["narrowest"]["part"] == "b" and n["narrowest"]["ratio"] == pytest.approx(0.1 / 0.6)
    assert n["narrowest"]["width_mm"] == pytest.approx(0.1)
    assert part_narrowness(parts, "m")["narrowest"]["width_mm"] == pytest.approx(100.0)
    assert n["pinched"] == ["b"]


def test_the_default_stagger_gives_way_where_no_ruling_keeps_it(caplog):
    """Rulings 2.5 apart, a 6 stock and the neighbour's joints at every ruling: no joint can
    keep 1.5 from them. With the default stagger the boards are cut anyway (each within the
    stock) and a warning names the joints; a stagger asked for is an error."""
    positions = 2.5 * np.arange(9.0)

    def extent(a, b):
        return 2.5 * (b - a)

    args = (extent, 0, 8, list(range(1, 8)), 6.0, positions[1:8], 1.5, positions, "S-v01")
    with pytest.raises(DgpcError, match=r"keeps the stagger \(1.5 mm\)"):
        split_run(*args)
    with caplog.at_level(logging.WARNING):
        joints = split_run(*args, relax=True)
    cuts = [0, *joints, 8]
    assert all(extent(a, b) <= 6.0 for a, b in zip(cuts[:-1], cuts[1:], strict=True))
    assert joints == [2, 4, 6]
    assert "S-v01: 3 joint(s) (rows 2, 4, 6) nearer than the stagger (1.5 mm)" in caplog.text


def test_a_fold_trimmed_away_does_not_stop_unfold():
    """A strip folded in its first quad (A_0 pulled past A_1): refused as a whole strip and
    when a part covers that quad; a part from row 1 on (the fold in the overhang) is cut."""
    x = np.arange(6.0)
    A = np.stack([x, np.zeros(6), np.zeros(6)], 1)
    B = A + [0.0, 1.0, 0.0]
    A[0, 0] = 2.0
    with pytest.raises(DgpcError, match="S-v00 is folded"):
        require_sound_strips([(A, B)], ["S-v00"], "s.json")
    with pytest.raises(DgpcError, match="S-v00 is folded"):
        require_sound_strips([(A, B)], ["S-v00"], "s.json", [[[0, 3], [4, 5]]])
    require_sound_strips([(A, B)], ["S-v00"], "s.json", [[[1, 5]]])
