"""Fabrication metrics of planar-quad strips (issue 26, item 5): each on a strip built to fail it
(stops short of the edge row, bent off the net, neighbours stepped along the normal or apart
across, a zigzag ruling, a near-triangle quad, a non-planar quad), a good strip passing all of
them, and ``dgpc inspect`` printing them for a strips artifact."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import read_net
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.strips.fabrication import (
    end_gaps,
    measure_strips,
    part_end_gaps,
    ruling_angles,
    side_ratios,
    summary,
)
from dgpc_cli.strips.quality import diagonal_gap, quad_deviation
from dgpc_cli.strips.trim import trim_strip

#: A flat net in the plane z = 0: rows H apart along y (the geodesics), columns W apart along x.
M, N, H, W = 9, 4, 300.0, 350.0


def flat_net():
    u, v = np.meshgrid(np.arange(M), np.arange(N), indexing="ij")
    return np.stack([v * W, u * H, np.zeros((M, N))], axis=-1).astype(float)


def strips_of(f):
    return [(v, f[:, v].copy(), f[:, v + 1].copy()) for v in range(f.shape[1] - 1)]


def measured(f, strips):
    return summary([f"S-v{v:02d}" for v, _, _ in strips], measure_strips(f, strips))


def test_a_strip_on_its_net_passes_every_metric():
    f = flat_net()
    s = measured(f, strips_of(f))
    assert s["max_end_gap_mm"] <= 1e-9
    assert s["max_deviation_mm"] <= 1e-9
    assert s["max_seam_step_mm"] <= 1e-9 and s["max_seam_gap_mm"] <= 1e-9
    assert s["max_ruling_angle_deg"] <= 1e-6
    assert s["max_side_ratio"] == pytest.approx(W / H)
    assert s["max_planarity_mm"] <= 1e-9
    assert s["area_ratio"] == pytest.approx(1.0, abs=1e-12)
    assert s["area_m2"] == pytest.approx((M - 1) * H * (N - 1) * W * 1e-6)   # m² from mm
    assert s["per_strip"]["S-v00"]["seam_step_mm"][0] is None               # no strip v−1


def test_a_strip_stopping_short_of_the_edge_row_has_an_end_gap_and_less_area():
    f = flat_net()
    strips = strips_of(f)
    _, A, B = strips[1]
    A[0] += 0.5 * (A[1] - A[0])                   # half a row short at the start, on P only
    B[-1] += 0.25 * (B[-1] - B[-2])               # a quarter row past the end, on Q
    gaps = end_gaps(f[:, 1], f[:, 2], A, B)
    assert gaps == pytest.approx(np.array([[0.5 * H, 0.0], [0.0, -0.25 * H]]))
    s = measured(f, strips)
    assert s["per_strip"]["S-v01"]["end_gaps_mm"] == pytest.approx([0.5 * H, -0.25 * H])
    assert s["max_end_gap_mm"] == pytest.approx(0.5 * H)
    lost = 0.5 * (0.5 * H) * W - 0.5 * (0.25 * H) * W    # the two triangles
    assert s["per_strip"]["S-v01"]["area_ratio"] == pytest.approx(1 - lost / ((M - 1) * H * W))
    assert s["per_strip"]["S-v00"]["end_gaps_mm"] == pytest.approx([0.0, 0.0])


def test_a_strip_bent_off_the_net_deviates_by_the_bend():
    f = flat_net()
    strips = strips_of(f)
    _, A, B = strips[0]
    A[4, 2] += 7.0
    B[4, 2] += 7.0                                # the ruling at row 4 lifted 7 mm
    dev = quad_deviation(A, B, f[:, 0], f[:, 1])
    assert dev[3] == pytest.approx(7.0) and dev[4] == pytest.approx(7.0)
    assert dev[[0, 1, 2, 5, 6, 7]] == pytest.approx(0.0, abs=1e-9)
    assert measured(f, strips)["max_deviation_mm"] == pytest.approx(7.0)


@pytest.mark.parametrize("shift, step, gap", [((0, 0, 3.0), 3.0, 0.0),      # along the normal
                                              ((2.0, 0, 0), 0.0, 2.0),      # across, in-plane
                                              ((0, 40.0, 0), 0.0, 0.0)])    # along the seam
def test_neighbours_apart_at_their_shared_geodesic_give_seam_step_and_gap(shift, step, gap):
    f = flat_net()
    strips = strips_of(f)
    strips[2][1][:] += np.array(shift)           # strip 2's copy of geodesic 2 moved
    s = measured(f, strips)["per_strip"]
    assert s["S-v01"]["seam_step_mm"][1] == pytest.approx(step, abs=1e-9)
    assert s["S-v01"]["seam_gap_mm"][1] == pytest.approx(gap, abs=1e-9)
    assert s["S-v02"]["seam_step_mm"][0] == s["S-v01"]["seam_step_mm"][1]
    assert s["S-v00"]["seam_step_mm"][1] == pytest.approx(0.0, abs=1e-12)


def test_seam_step_follows_the_net_normal_on_a_curved_net():
    """A cylinder of radius R: strip 1's copy of their shared meridian moved radially by 2 mm
    is a 2 mm step (the normal is radial), moved along the circle a 2 mm gap."""
    R = 3000.0
    theta = np.radians(np.arange(N) * 6.0)
    u = np.arange(M) * H
    T, U = np.meshgrid(theta, u)
    f = np.stack([R * np.cos(T), R * np.sin(T), U], axis=-1)
    for move, step, gap in (("radial", 2.0, 0.0), ("tangent", 0.0, 2.0)):
        strips = strips_of(f)
        radial = np.array([np.cos(theta[2]), np.sin(theta[2]), 0.0])
        tangent = np.array([-np.sin(theta[2]), np.cos(theta[2]), 0.0])
        strips[2][1][:] += 2.0 * (radial if move == "radial" else tangent)
        s = measured(f, strips)["per_strip"]["S-v01"]
        assert s["seam_step_mm"][1] == pytest.approx(step, abs=1e-6), move
        assert s["seam_gap_mm"][1] == pytest.approx(gap, abs=1e-6), move


def test_copies_on_one_curved_geodesic_with_vertices_apart_step_by_the_chord_sag():
    """Both copies of a shared geodesic on the same arc (radius R, the net's normal radial), one
    with its vertices half a row along from the other's: each inner vertex stands off the
    other copy's chord by the sag ``R (1 − cos(φ/2))`` along the normal (φ the row's angle),
    with no gap: the step two differently bent copies of one template leave even on the
    curve."""
    from dgpc_cli.strips.fabrication import seam_offsets

    R, phi = 3000.0, np.radians(6.0)
    k = np.arange(9)

    def arc(a):
        return np.stack([R * np.cos(a), np.zeros_like(a), R * np.sin(a)], axis=-1)

    X, Y = arc(k * phi), arc(np.r_[0.0, (k[:-1] + 0.5) * phi, k[-1] * phi])
    normals = X / R
    step, gap = seam_offsets(X[1:-1], Y, normals[1:-1])
    assert step == pytest.approx(R * (1 - np.cos(phi / 2)), rel=1e-9)
    assert gap == pytest.approx(0.0, abs=1e-9)
    same, _ = seam_offsets(X, X, normals)
    assert same == pytest.approx(0.0, abs=1e-9)


def test_a_zigzag_ruling_turns_by_its_angle():
    f = flat_net()
    _, A, B = strips_of(f)[0]
    assert ruling_angles(A, B) == pytest.approx(0.0, abs=1e-6)
    A[3, 1] += W                                   # ruling 3 slanted 45° (dy = W over dx = W)
    angles = ruling_angles(A, B)
    assert angles[2] == pytest.approx(45.0) and angles[3] == pytest.approx(45.0)
    assert angles[[0, 1, 4]] == pytest.approx(0.0, abs=1e-6)


def test_a_near_triangle_quad_has_a_large_side_ratio():
    f = flat_net()
    _, A, B = strips_of(f)[0]
    A[4] = A[3] + 0.02 * (A[4] - A[3])             # quad 3's side on P 6 mm long
    ratios = side_ratios(A, B)
    assert ratios[3] == pytest.approx(np.hypot(W, 0.98 * H) / (0.02 * H))
    assert ratios[0] == pytest.approx(W / H)


def test_a_non_planar_quad_has_its_diagonals_apart():
    f = flat_net()
    _, A, B = strips_of(f)[0]
    assert diagonal_gap(A, B) == pytest.approx(0.0, abs=1e-12)
    A[2, 2] += 4.0                                 # one corner lifted: quads 1 and 2 twisted
    gap = diagonal_gap(A, B)
    assert gap[1] > 1.0 and gap[2] > 1.0
    assert gap[[0, 3, 4]] == pytest.approx(0.0, abs=1e-12)
    # quad 1's diagonals A1 -> B2 and B1 -> A2 (lifted): the distance of their lines
    d1 = B[2] - A[1]
    d2 = A[2] - B[1]
    c = np.cross(d1, d2)
    assert gap[1] == pytest.approx(abs(np.dot(B[1] - A[1], c)) / np.linalg.norm(c))


def test_a_trimmed_part_that_ends_on_the_outline_has_no_end_gap_and_a_short_one_has():
    """The reference covers rows 2 to 6 of the flat net: the part trimmed from the whole strip
    ends on the outline (gap ≈ 0); the strip cut short inside it (it ends at row 5.5) leaves
    half a row."""
    f = flat_net()
    y0, y1 = 2 * H, 6 * H
    V = np.array([[-10.0, y0, 0], [N * W, y0, 0], [N * W, y1, 0], [-10.0, y1, 0]])
    reference = ReferenceSurface(V, np.array([[0, 1, 2], [0, 2, 3]]))
    A, B = f[:, 1].copy(), f[:, 2].copy()
    (part,) = trim_strip(A, B, reference)
    assert (np.abs(part_end_gaps(A, B, part.outline, reference)) <= 1e-6).all()
    A, B = A[:7].copy(), B[:7].copy()
    A[-1] -= 0.5 * (A[-1] - A[-2])
    B[-1] -= 0.5 * (B[-1] - B[-2])                 # the strip ends at row 5.5
    (part,) = trim_strip(A, B, reference)
    gaps = part_end_gaps(A, B, part.outline, reference)
    assert (np.abs(gaps[0]) <= 1e-6).all()
    assert gaps[1] == pytest.approx([0.5 * H, 0.5 * H], abs=1e-6)


@pytest.fixture(scope="module")
def bent_strips(tmp_path_factory):
    from cli_helpers import bent_catenoid_chain

    d = tmp_path_factory.mktemp("fabrication")
    bent_catenoid_chain(d)
    return d


def test_inspect_prints_the_fabrication_metrics_in_mm_and_degrees(bent_strips):
    stem = bent_strips / "strips"
    out = json.loads(dgpc("inspect", stem).stdout)
    fab = out["fabrication"]
    art = read_strips(stem)
    ids = [r["id"] for r in art.records]
    assert list(fab["per_strip"]) == ids
    for key in ("end_gaps_mm", "deviation_mm", "seam_step_mm", "seam_gap_mm",
                "ruling_angle_deg", "side_ratio", "planarity_mm", "width_mm", "area_m2",
                "area_ratio"):
        assert all(key in fab["per_strip"][i] for i in ids)
    # the recorded width is in the artifact's unit; the metrics' in mm
    assert fab["mean_width_mm"] == pytest.approx(np.mean([r["width"] for r in art.records]))
    assert fab["max_deviation_mm"] == pytest.approx(
        max(r["deviation"] * r["width"] for r in art.records), rel=1e-9)
    assert fab == art.metrics["fabrication"]          # recomputed: the recorded values
    # a closed ring: every strip has two neighbours, last and first included only if both
    # are in the artifact (strip v and v+1)
    assert fab["max_seam_step_mm"] is not None and fab["max_seam_step_mm"] > 0


def _figures(stem):
    from dgpc_cli.report.render import style
    from dgpc_cli.stages.report import PAGES

    page = PAGES["strips"](stem.with_suffix(".json"))
    with style():
        return {name: make() for name, _, make in page.figures}


def test_report_overlays_every_developed_strip_on_the_template(bent_strips):
    stem = bent_strips / "strips"
    art = read_strips(stem)
    figs = _figures(stem)
    (ax,) = [a for a in figs["template"].axes if a.get_gid() == "overlay"]
    outlines = [ln for ln in ax.lines if (ln.get_gid() or "").startswith("outline:")]
    assert [ln.get_gid() for ln in outlines] == [f"outline:{r['id']}" for r in art.records]
    # every outline closed, as many vertices as the strip's A and B, and congruent to its
    # strip's development (the same perimeter, mm)
    from dgpc_cli.io.units import to_mm
    from dgpc_cli.strips.develop import develop_strip

    for ln, (A, B) in zip(outlines, art.geometry, strict=True):
        x, y = ln.get_data()
        assert len(x) == 2 * len(A) + 1 and (x[0], y[0]) == (x[-1], y[-1])
        dev = develop_strip(to_mm(A, art.units), to_mm(B, art.units))
        ring = np.concatenate([dev.A, dev.B[::-1], dev.A[:1]])
        perimeter = np.linalg.norm(np.diff(ring, axis=0), axis=1).sum()
        assert np.hypot(np.diff(x), np.diff(y)).sum() == pytest.approx(perimeter, rel=1e-9)
    texts = [t.get_text() for a in figs["template"].axes for t in a.texts]
    assert any(t.endswith(" mm") for t in texts)                     # a scale bar in mm


def test_report_colours_the_deviation_in_mm_and_marks_the_stepped_seams(bent_strips):
    from dgpc_cli.io.atomic import write_files
    from dgpc_cli.io.strips import strips_files
    from dgpc_cli.metrics.frames import tangent_frames
    from dgpc_cli.stages.report import SEAM_STEP_MARK

    art = read_strips(bent_strips / "strips")
    f = read_net(bent_strips / "bent").f
    A, B = art.geometry[1]                # strip 1 lifted 5 % of its width along its normal
    lift = 0.05 * art.records[1]["width"] * tangent_frames(f, one_sided=True)[2][len(A) // 2, 1]
    art.geometry[1] = (A + lift, B + lift)
    art.metrics = {}
    stem = bent_strips / "stepped"
    write_files(strips_files(stem, art), force=True)
    fab = json.loads(dgpc("inspect", stem).stdout)["fabrication"]
    fig = figs = _figures(stem)["deviation"]
    bar = [a for a in figs.axes if a.get_xlabel() == "deviation from the net strip [mm]"]
    assert len(bar) == 1 and bar[0].get_xlim()[1] == pytest.approx(fab["max_deviation_mm"])
    view = [a for a in fig.axes if a.get_gid() == "view-axonometric"][0]
    stepped = [c for c in view.collections if c.get_gid() == "seams-stepped"][0]
    calm = [c for c in view.collections if c.get_gid() == "seams"][0]
    mark = SEAM_STEP_MARK * fab["mean_width_mm"]
    assert fab["max_seam_step_mm"] > mark               # this ring's strips do step
    assert len(stepped.get_segments()) > 0 and len(calm.get_segments()) > 0
    rows = read_strips(stem).records[0]["rows"]
    seams = sum(1 for r in fab["per_strip"].values() if r["seam_step_mm"][1] is not None)
    assert len(stepped.get_segments()) + len(calm.get_segments()) == seams * (rows - 1)


def test_report_without_the_net_draws_the_strips_only(tmp_path, bent_strips):
    import shutil

    for name in ("strips.json", "strips.obj"):
        shutil.copy(bent_strips / name, tmp_path / name)
    assert set(_figures(tmp_path / "strips")) == {"width"}
    out = json.loads(dgpc("inspect", tmp_path / "strips").stdout)
    assert out["fabrication"] == read_strips(bent_strips / "strips").metrics["fabrication"]


def test_planarize_records_strips_that_build_the_design_and_warns_when_they_do_not(tmp_path):
    """A cylinder's strips are its net strips: no end gap, the parts add up to the net's area
    (the done-means check, within 0.1 %; here to round-off) and no warning. A coarse twisted
    catenoid's planar strips end on its edge rows but bulge past its net strips by more than
    0.1 % of the area: a warning names it."""
    dgpc("init", "--surface", "revolution", "--profile", "cylinder", "--rows", 9, "--cols", 5,
         "--span", 90, "--units", "m", "-o", tmp_path / "cyl")
    run = dgpc("planarize-strips", tmp_path / "cyl", "-o", tmp_path / "s")
    fab = read_strips(tmp_path / "s").metrics["fabrication"]
    assert fab["max_end_gap_mm"] <= 1e-9 and abs(fab["area_ratio"] - 1) <= 1e-12
    assert fab["mean_width_mm"] > 100                    # mm, from a net in m
    assert "warning" not in run.stderr
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 120, "--twist", 0.3, "-o", tmp_path / "tw")
    run = dgpc("planarize-strips", tmp_path / "tw", "-o", tmp_path / "t")
    fab = read_strips(tmp_path / "t").metrics["fabrication"]
    assert fab["max_end_gap_mm"] <= 1e-9 and abs(fab["area_ratio"] - 1) > 1e-3
    assert f"the strips' area is {100 * fab['area_ratio']:.2f} % of the net's" in run.stderr


def test_report_tables_label_the_fabrication_metrics_in_mm_degrees_and_m2():
    from dgpc_cli.report.tables import metric_unit

    units = {"fabrication.max_end_gap_mm": "mm", "fabrication.per_strip.seam_step_mm": "mm",
             "fabrication.max_ruling_angle_deg": "°", "fabrication.area_m2": "m²",
             "fabrication.max_side_ratio": "", "fabrication.area_ratio": "",
             "fabrication.max_deviation_relative": "× width",
             "max_deviation_relative": "× width", "per_strip.deviation_relative": "× width",
             "max_planarity_diagonal_relative": "× diagonal",
             "per_strip.planarity_diagonal_relative": "× diagonal",
             "per_part.deviation_mm": "mm", "per_strip.width_mm": "mm",
             "per_part.length_mm": "mm", "total_area_m2": "m²",
             "max_straightness_relative": "× length", "max_congruence_error": ""}
    assert {k: metric_unit(k, "m") for k in units} == units


def _metric_keys(doc, prefix=""):
    """Every dotted key of an ``inspect`` document, per-item records' ids replaced by ``*``."""
    out = set()
    for key, value in doc.items():
        name = f"{prefix}{key}"
        if key in ("per_strip", "per_part", "classes") and isinstance(value, dict):
            for record in value.values():
                out |= _metric_keys(record, f"{name}.*.")
        elif isinstance(value, dict):
            out |= _metric_keys(value, f"{name}.")
        else:
            out.add(name)
    return out


#: Keys of ``inspect`` on strips and flat parts that are no length, angle or area (counts,
#: ratios, ids, states); every other key names its unit.
UNITLESS = {"n_strips", "polished", "flat_rows", "limited_rows", "side_ratio", "max_side_ratio",
            "area_ratio", "area_reference", "n_parts", "n_classes", "max_strain", "strain",
            "quantity", "representative", "members", "score_lines", "class", "part", "ratio",
            "pinched", "max_congruence_error", "relative_error", "max_relative_error"}
UNIT_ENDINGS = ("_mm", "_deg", "_m2", "_relative")


def unit_clashes(*docs) -> list[str]:
    """The keys of ``inspect`` documents ``docs`` whose unit their name does not say, and the
    names (last part) that say different units in different places."""
    from dgpc_cli.report.tables import metric_unit

    bare, units = [], {}
    for doc in docs:
        for key in _metric_keys(doc):
            last = key.rsplit(".", 1)[-1]
            if last not in UNITLESS and not last.endswith(UNIT_ENDINGS):
                bare.append(key)
            units.setdefault(last, set()).add(metric_unit(key.replace("*", "x"), "m"))
    return bare + [f"{last}: {sorted(u)}" for last, u in units.items() if len(u) > 1]


def test_unit_clashes_finds_a_key_with_a_mixed_unit():
    """Built to fail: a relative ``max_deviation`` beside a ``fabrication.max_deviation`` in
    mm (the keys before they named their units), a bare length."""
    doc = {"max_deviation": 0.01, "fabrication": {"max_deviation": 3.5},
           "per_part": {"S-v00": {"length": 4.2}}}
    assert sorted(unit_clashes(doc)) == ["fabrication.max_deviation", "max_deviation",
                                         "per_part.*.length"]
    assert unit_clashes({"max_deviation_relative": 0.01,
                         "fabrication": {"max_deviation_relative": 0.01}}) == []
    assert unit_clashes({"a": {"width_mm": 1.0}, "b": {"x": {"width_mm": 2.0}}}) == []


def test_inspect_names_the_unit_of_every_strips_and_flat_metric(bent_strips):
    """``inspect`` of strips (their own metrics and ``fabrication``) and of flat parts: every
    length, angle and area names its unit, and no name means two units."""
    strips = json.loads(dgpc("inspect", bent_strips / "strips").stdout)
    flat = json.loads(dgpc("inspect", bent_strips / "flat").stdout)
    assert unit_clashes(strips, flat) == []
    assert "fabrication.max_deviation_mm" in _metric_keys(strips)
    assert "max_deviation_relative" in _metric_keys(strips)
    # the flat parts' lengths in mm whatever the artifact's unit
    part = read_flat(bent_strips / "flat").parts[0]
    assert flat["per_part"][part["id"]]["length_mm"] == pytest.approx(
        part["length"] * mm_per_unit(read_flat(bent_strips / "flat").units))


def _end_short(strips):
    strips[1][1][0] += np.array([0.0, 2.0, 0.0])            # A of strip 1 starts 2 mm short


def _lifted(strips):
    strips[1][1][4, 2] += 7.0
    strips[1][2][4, 2] += 7.0                               # ruling 4 of strip 1 lifted 7 mm


def _stepped(strips):
    strips[2][1][:, 2] += 4.0                               # strip 2's copy of geodesic 2


def _apart(strips):
    strips[2][1][:, 0] += 2.0                               # ... moved 2 mm across


def _zigzag(strips):
    strips[1][1][3, 1] += 0.5 * W                           # ruling 3 slanted by 26.6°


def _pinched(strips):
    _, A, _ = strips[1]
    A[4] = A[3] + 0.05 * (A[4] - A[3])                      # quad 3's side on P 15 mm


def _twisted(strips):
    strips[1][1][2, 2] += 1e-3                              # one corner 1 µm off its plane


#: metric -> (the change that fails it, the figure's key in the summary, its per-strip key,
#: the bound it must exceed: the issue's, in mm or degrees, on strips 350 mm wide)
FAILS = {
    "end gap": (_end_short, "max_end_gap_mm", "end_gaps_mm", 1.0),
    "deviation": (_lifted, "max_deviation_mm", "deviation_mm", 0.015 * W),
    "seam step": (_stepped, "max_seam_step_mm", "seam_step_mm", 0.01 * W),
    "seam gap": (_apart, "max_seam_gap_mm", "seam_gap_mm", 1.0),
    "ruling angle": (_zigzag, "max_ruling_angle_deg", "ruling_angle_deg", 20.0),
    "side ratio": (_pinched, "max_side_ratio", "side_ratio", 10.0),
    "planarity": (_twisted, "max_planarity_mm", "planarity_mm", 1e-9 * W),
}


def _worst(value):
    if isinstance(value, list):
        return max((abs(x) for x in value if x is not None), default=0.0)
    return abs(value)


@pytest.mark.parametrize("metric", list(FAILS))
def test_each_metric_flags_the_strip_built_to_fail_it(metric):
    """On the flat net every figure is within the issue's bounds; each change fails its own
    figure, beyond the bound, at the strip it was made on (and at its neighbour for a seam)
    and nowhere else."""
    change, key, per_key, bound = FAILS[metric]
    f = flat_net()
    good = measured(f, strips_of(f))
    assert good[key] <= bound
    strips = strips_of(f)
    change(strips)
    s = measured(f, strips)
    assert s[key] > bound, (metric, s[key])
    flagged = {sid for sid, r in s["per_strip"].items() if _worst(r[per_key]) > bound}
    seam = per_key.startswith("seam")
    assert flagged == ({"S-v01", "S-v02"} if seam else {"S-v01"}), (metric, flagged)
    assert max(_worst(r[per_key]) for r in s["per_strip"].values()) == pytest.approx(s[key])


def test_planarize_warns_of_an_end_gap_above_a_millimetre_only():
    from dgpc_cli.stages.strip_fabrication import fabrication_warnings

    f = flat_net()
    assert fabrication_warnings(measured(f, strips_of(f))) == []
    strips = strips_of(f)
    strips[1][1][0] += np.array([0.0, 0.9, 0.0])            # 0.9 mm short: no warning
    assert fabrication_warnings(measured(f, strips)) == []
    strips[1][1][0] += np.array([0.0, 0.2, 0.0])            # 1.1 mm short
    (line,) = [w for w in fabrication_warnings(measured(f, strips)) if "edge rows" in w]
    assert "up to 1.1 mm" in line and "(S-v01)" in line
