"""``dgpc report`` on a flat artifact: the overlay and side-by-side PNGs (paper Fig. 18)."""

import numpy as np
from cli_helpers import dgpc
from PIL import Image


def _flat(tmp_path, twist="0"):
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 6,
         "--span", 90, "--twist", twist, "-o", tmp_path / "n")
    dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s")
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    return tmp_path / "f"


def test_report_writes_two_deterministic_pngs(tmp_path):
    flat = _flat(tmp_path)
    out = dgpc("report", flat, "-o", tmp_path / "a").stdout.split()
    assert out == [str(tmp_path / "a-overlay.png"), str(tmp_path / "a-strips.png"),
                   str(tmp_path / "a-index.html")]
    dgpc("report", flat, "-o", tmp_path / "b")
    for name in ("overlay", "strips"):
        a = (tmp_path / f"a-{name}.png").read_bytes()
        assert a == (tmp_path / f"b-{name}.png").read_bytes()
        img = np.asarray(Image.open(tmp_path / f"a-{name}.png").convert("L"))
        assert img.shape[0] > 100 and img.shape[1] > 100
        assert (img < 128).mean() > 1e-3                      # something was drawn


def test_report_refuses_existing_files(tmp_path):
    flat = _flat(tmp_path)
    dgpc("report", flat, "-o", tmp_path / "r")
    result = dgpc("report", flat, "-o", tmp_path / "r", expect=1)
    assert "already exists" in result.stderr
    dgpc("report", flat, "-o", tmp_path / "r", "--force")


def _signed_area(points) -> float:
    x, y = np.asarray(points, float).T
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_laid_out_parts_face_the_way_the_dxf_cuts_them(tmp_path):
    """The layout figure shows each part as the flat artifact and the cut sheet have it (its
    outline's orientation on the page, in display coordinates, is the DXF's), not mirrored by
    an inverted y axis."""
    import ezdxf

    from dgpc_cli.io.flat import read_flat
    from dgpc_cli.report.flat import layout_figure
    from dgpc_cli.report.render import style

    flat = read_flat(_flat(tmp_path))
    with style():
        fig = layout_figure(flat.parts, flat.units)
    ax = next(a for a in fig.axes if a.get_gid() == "layout")
    shown = {}
    for patch in ax.patches:
        if (patch.get_gid() or "").startswith("part:"):
            xy = patch.get_transform().transform(patch.get_path().vertices)
            shown[patch.get_gid()[5:]] = _signed_area(xy)
    assert set(shown) == {p["id"] for p in flat.parts}
    for p in flat.parts:
        assert np.sign(shown[p["id"]]) == np.sign(_signed_area(p["outline"])), p["id"]
    dgpc("nest", tmp_path / "f", "--sheet", "2000x1500", "--scale", 100, "-o",
         tmp_path / "sh")
    dxf_signs = sorted(np.sign(_signed_area(e.get_points("xy")))
                       for path in sorted(tmp_path.glob("sh.sheet*.dxf"))
                       for e in ezdxf.readfile(path).modelspace().query(
                           "LWPOLYLINE[layer=='CUT']"))
    assert dxf_signs == sorted(np.sign(v) for v in shown.values())


def test_overlay_has_a_scale_bar_and_errors_with_a_unit(tmp_path):
    """The overlay's cells share one scale, shown by a bar; each class's error is a length."""
    from dgpc_cli.io.flat import read_flat
    from dgpc_cli.report.flat import overlay_figure
    from dgpc_cli.report.render import style

    flat = read_flat(_flat(tmp_path, twist="0.4"))
    with style():
        fig = overlay_figure(flat.parts, flat.classes, flat.units)
    bars = [line for ax in fig.axes for line in ax.lines if line.get_gid() == "scale-bar"]
    assert len(bars) == 1
    cells = [a for a in fig.axes if (a.get_gid() or "").startswith("class-")]
    spans = {round(np.diff(a.get_xlim())[0], 12) for a in cells}
    assert len(spans) == 1                                # one scale for every cell
    for ax in cells:
        assert ax.get_title().rstrip().endswith(" mm"), ax.get_title()


def test_overlay_of_many_long_classes_draws_those_that_fit_and_says_so():
    """133 classes of 6 m × 0.1 m boards (an arched roof's trimmed boards come so) do not fit
    one page legibly: the overlay draws the classes of the largest quantity in cells at least
    MIN_CELL wide and says how many are left out (it used to fail on cells of negative height)."""
    from dgpc_cli.report.flat import MIN_CELL, overlay_figure

    parts, classes = [], []
    for k in range(133):
        parts.append({"id": f"P{k}", "outline": [[0, 0], [6000, 0], [6000, 100 + k % 7],
                                                  [0, 100 + k % 7]], "score": [],
                      "alignment": {"matrix": [[1, 0], [0, 1]], "translation": [0, 0]}})
        classes.append({"id": f"C{k:03d}", "representative": f"P{k}", "members": [f"P{k}"],
                        "quantity": 1 + (k % 3 == 0), "max_error": 0.0})
    fig = overlay_figure(parts, classes, "mm")
    cells = [ax for ax in fig.axes if (ax.get_gid() or "").startswith("class-")]
    shown = {ax.get_gid()[len("class-"):] for ax in cells}
    assert 1 < len(shown) < len(classes)
    assert f"{len(shown)} of the largest quantity shown, {len(classes) - len(shown)} more" \
        in fig._suptitle.get_text()
    # the classes of quantity 2 come first
    assert {c["id"] for c in classes if c["quantity"] == 2} <= shown
    width, _ = fig.get_size_inches()
    for ax in cells:
        box = ax.get_position()
        assert box.width * width >= MIN_CELL - 0.1 - 1e-9 and box.height > 0


def test_overlay_draws_the_score_lines_of_the_representative_once():
    """Twelve copies of one template scored each for its own bending: the cell overlays the
    twelve outlines and draws one set of score lines, the representative's (not twelve sets
    on top of each other), and its title says the copies are scored each for its own."""
    from dgpc_cli.report.flat import CUT, SCORE, overlay_figure

    t = np.linspace(0.0, 1.0, 12)
    A = np.column_stack([6.0 * t, np.zeros_like(t)])
    B = A[::-1] + [0.0, 0.3]
    parts = [{"id": f"S{k}", "class": "C01", "outline": np.vstack([A, B]).tolist(),
              "score": [[A[i].tolist(), (B[-1 - i] + [0.01 * k, 0.0]).tolist()]
                        for i in range(1, 11)],
              "alignment": {"matrix": np.eye(2).tolist(), "translation": [0.0, 0.0]}}
             for k in range(12)]
    classes = [{"id": "C01", "quantity": 12, "representative": "S3",
                "members": [p["id"] for p in parts], "max_error": 0.0,
                "score_lines": "per copy"}]
    fig = overlay_figure(parts, classes, "m")
    (cell,) = [a for a in fig.axes if (a.get_gid() or "").startswith("class-")]
    colours = [tuple(np.round(line.get_color(), 3)) for line in cell.lines]
    assert colours.count(tuple(np.round(CUT, 3))) == 12
    scores = [line for line in cell.lines if tuple(np.round(line.get_color(), 3))
              == tuple(np.round(SCORE, 3))]
    assert len(scores) == 10
    # the representative's own lines: S3's lean 0.03 across the strip
    leans = [abs(float(np.diff(line.get_data()[0])[0])) for line in scores]
    assert np.allclose(leans, 0.03), leans
    assert "S3's shown" in cell.get_title()
