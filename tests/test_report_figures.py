"""What the figures of ``dgpc report`` show, checked against the artifacts they come from: the
Clairaut plot's series are the metric's geodesics, the strain glyphs sit at the interior
vertices, the mold pairing shows every panel on both sides in one colour, the camera frames the
whole model, sheet previews keep their layers' colours, lengths carry the artifact's unit."""

import json

import numpy as np
import pytest
from cli_helpers import bent_catenoid_chain, dgpc
from PIL import Image

from dgpc_cli.io.net import read_net
from dgpc_cli.report.camera import box_corners, model_frame, standard_views
from dgpc_cli.report.clairaut import FLOOR
from dgpc_cli.report.render import style
from dgpc_cli.stages.report import PAGES, SHEET_LEGEND, _layer_legend


@pytest.fixture(scope="module")
def arts(tmp_path_factory):
    """A twisted catenoid net (axis recorded, so Clairaut applies), a meridian net, a bent
    catenoid with its mold, and flat parts nested on sheets; the twisted net also in ft."""
    d = tmp_path_factory.mktemp("figures")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 120, "--twist", 0.3, "-o", d / "twisted")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 120, "-o", d / "meridian")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 120, "--twist", 0.3, "--units", "ft", "-o", d / "feet")
    bent_catenoid_chain(d)
    return d


def _figure(path, kind, name):
    """The matplotlib Figure of the report's figure ``name`` of the artifact at ``path``."""
    page = PAGES[kind](path.with_suffix(".json"))
    makes = {n: make for n, _, make in page.figures}
    with style():
        return makes[name]()


def _axes(fig, gid):
    (ax,) = [a for a in fig.axes if a.get_gid() == gid]
    return ax


def _collections(ax, gid):
    return [c for c in ax.collections if c.get_gid() == gid]


def _texts(fig):
    out = [t.get_text() for t in fig.texts]
    for ax in fig.axes:
        out += [t.get_text() for t in ax.texts] + [ax.get_title(), ax.get_xlabel(),
                                                   ax.get_ylabel()]
    return out


# --------------------------------------------------------------------------------------------
# Clairaut (Fig. 11)


def test_clairaut_plots_exactly_the_metrics_geodesics(arts):
    """One series per geodesic of the artifact's metric (the interior u-lines), each r cos α
    minus the recorded mean, whose mean absolute value is the recorded MAD; the means below are
    the recorded means, the title states the recorded max MAD."""
    from dgpc_cli.metrics.clairaut import clairaut_values
    from dgpc_cli.stages.inspect import recorded_axis

    doc = json.loads((arts / "twisted.json").read_text())
    record = doc["metrics"]["clairaut"]
    per = record["per_geodesic"]
    net = read_net(arts / "twisted")
    values = clairaut_values(net.f, recorded_axis(net))
    fig = _figure(arts / "twisted", "net", "clairaut")
    ax = _axes(fig, "clairaut-deviation")
    lines = {ln.get_gid(): ln for ln in ax.lines if (ln.get_gid() or "").startswith("clairaut-v")}
    assert sorted(lines) == sorted(f"clairaut-v{j}" for j in per["v"])
    assert len(lines) == net.shape[1] - 2                   # boundary geodesics left out
    for k, j in enumerate(per["v"]):
        y = np.asarray(lines[f"clairaut-v{j}"].get_ydata(), float)
        np.testing.assert_allclose(y, values[1:-1, j] - per["mean"][k], atol=1e-12)
        assert np.abs(y).mean() == pytest.approx(per["mad"][k], rel=1e-9)
    means = _axes(fig, "clairaut-means")
    (bars,) = [c for c in means.containers if c.lines[0].get_gid() == "clairaut-mean"]
    x, y = bars.lines[0].get_data()
    assert list(x) == per["v"]
    np.testing.assert_allclose(y, per["mean"], rtol=1e-12)
    assert f"max MAD {record['max_mad']:.3g} mm" in fig.texts[0].get_text()
    half = ax.get_ylim()[1]                                  # axis scaled to the data
    biggest = max(np.abs(ln.get_ydata()).max() for ln in lines.values())
    assert biggest <= half <= 1.5 * biggest
    assert ax.get_legend() is not None


def test_clairaut_of_a_meridian_net_is_flat_not_noise(arts):
    """r cos α = 0 up to rounding on a meridian net: the axis spans at least FLOOR × the mean
    radius, so the rounding noise is a flat line."""
    record = json.loads((arts / "meridian.json").read_text())["metrics"]["clairaut"]
    fig = _figure(arts / "meridian", "net", "clairaut")
    ax = _axes(fig, "clairaut-deviation")
    biggest = max(np.abs(ln.get_ydata()).max() for ln in ax.lines
                  if (ln.get_gid() or "").startswith("clairaut-v"))
    assert biggest < 1e-9 * record["mean_radius"]
    assert ax.get_ylim()[1] >= FLOOR * record["mean_radius"]


# --------------------------------------------------------------------------------------------
# strain (Fig. 13)


def test_strain_glyphs_at_every_interior_vertex_as_long_as_their_eigenvalues():
    from dgpc_cli.metrics.strain import principal_strains, strain_tensor
    from dgpc_cli.report.net import strain_figure

    rng = np.random.default_rng(3)
    u, v = np.meshgrid(np.linspace(0, 4, 9), np.linspace(0, 3, 7), indexing="ij")
    f0 = np.stack([u, v, 0.1 * np.sin(u) * np.cos(v)], axis=-1)
    f = f0 * np.array([1.02, 0.99, 1.0]) + 1e-3 * rng.standard_normal(f0.shape)
    with style():          # up y, seen from z: the elevation shows the model's own plane
        fig = strain_figure(f, f0, title="strain", unit="m", up=(0.0, 1.0, 0.0),
                            front=(0.0, 0.0, 1.0))
    m, n = f.shape[:2]
    lam1, lam2, _ = principal_strains(strain_tensor(f, f0))
    for view in ("axonometric", "elevation"):
        ax = _axes(fig, f"view-{view}")
        for k in (1, 2):
            (coll,) = _collections(ax, f"strain-glyphs-{k}")
            segs = np.asarray(coll.get_segments())
            assert len(segs) == (m - 2) * (n - 2)
    # arm lengths in the elevation ∝ |λ|, one scale for both arms, the longest capped
    ax = _axes(fig, "view-elevation")
    lengths = [np.linalg.norm(np.diff(np.asarray(_collections(ax, f"strain-glyphs-{k}")[0]
                                                 .get_segments()), axis=1)[:, 0], axis=-1)
               for k in (1, 2)]
    mags = [np.abs(lam[1:-1, 1:-1]).ravel() for lam in (lam1, lam2)]
    ratio = np.concatenate(lengths) / np.concatenate(mags)
    scale, cap = np.median(ratio), max(x.max() for x in lengths)
    for length, mag in zip(lengths, mags, strict=True):
        np.testing.assert_allclose(length, np.minimum(scale * mag, cap), rtol=0.05,
                                   atol=1e-3 * cap)


def _plane_nets(spike: float = 0.0):
    u, v = np.meshgrid(np.linspace(0, 4, 9), np.linspace(0, 3, 7), indexing="ij")
    f0 = np.stack([u, v, 0.0 * u], axis=-1)
    f = f0 * np.array([1.01, 1.0, 1.0])
    f[4, 3, 0] += spike                                  # one vertex far off: a strain spike
    return f0, f


def test_strain_glyphs_are_readable_beside_a_spike():
    """One spike of strain does not shrink every other glyph to a dot: the typical arm is a
    good part of an edge long, and drawn thick enough to see."""
    from dgpc_cli.report.net import strain_figure

    f0, f = _plane_nets(spike=0.3)
    with style():          # up y, seen from z: the elevation shows the model's own plane
        fig = strain_figure(f, f0, title="strain", unit="m", up=(0.0, 1.0, 0.0),
                            front=(0.0, 0.0, 1.0))
    (coll,) = _collections(_axes(fig, "view-elevation"), "strain-glyphs-1")
    segs = np.asarray(coll.get_segments())
    lengths = np.linalg.norm(segs[:, 1] - segs[:, 0], axis=-1)
    assert np.median(lengths) >= 0.5 * 0.5              # half of an edge (0.5 m) at least
    assert coll.get_linewidths()[0] >= 1.2


def test_strain_figure_marks_the_handles_and_shows_the_start_shape():
    from dgpc_cli.report.net import strain_figure

    f0, f = _plane_nets()
    f[-1, -1] += (0.0, 0.0, 0.8)                           # a handle's drag
    with style():
        fig = strain_figure(f, f0, title="strain", unit="m",
                            handles={"ids": [0, f.shape[0] * f.shape[1] - 1]})
    for view in ("axonometric", "elevation"):
        (marks,) = _collections(_axes(fig, f"view-{view}"), "handles")
        assert len(marks.get_segments()) == 2 * 3           # a three-armed cross each
    start = _axes(fig, "view-second")
    assert start.get_title() == "start shape (input net)"
    (edges,) = _collections(start, "start-net")
    m, n = f.shape[:2]
    assert len(edges.get_segments()) == (m - 1) * n + m * (n - 1)
    (moves,) = _collections(start, "handle-moves")
    lengths = [np.linalg.norm(s[1] - s[0]) for s in moves.get_segments()]
    assert lengths[0] == pytest.approx(0.0, abs=1e-12) and lengths[1] > 0.1
    assert not [a for a in fig.axes if a.get_gid() == "view-plan"]   # no rims over each other
    # the legend says what is drawn (crosses, lines from the start), with the largest move
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    (said,) = [t for t in labels if t.startswith("handles (2)")]
    assert "arrow" not in said and "line from where it started" in said
    assert f"{np.linalg.norm(f[-1, -1] - f0[-1, -1]):.3g} m" in said


# --------------------------------------------------------------------------------------------
# molds (Fig. 16, 17)


def test_mold_pairing_shows_every_panel_on_both_sides_in_one_colour(arts):
    doc = json.loads((arts / "mold.json").read_text())
    ids = {p["id"] for p in doc["data"]["panels"] if p["net"] == 0}
    fig = _figure(arts / "mold", "mold", "pairing-net1")
    colours = {}
    for side in ("mold", "design"):
        ax = _axes(fig, f"view-{side}")
        seen: dict[str, set] = {}
        for coll in _collections(ax, "panels") + _collections(ax, "panels-flat"):
            for pid, rgba in zip(coll.get_urls(), coll.get_facecolors(), strict=True):
                seen.setdefault(pid, set()).add(tuple(np.round(rgba, 6)))
        assert set(seen) == ids, side
        assert all(len(c) == 1 for c in seen.values()), side
        colours[side] = {pid: next(iter(c)) for pid, c in seen.items()}
        labelled = {t.get_gid().split(":", 1)[1] for t in ax.texts
                    if (t.get_gid() or "").startswith(f"label-{side}:")}
        assert labelled and labelled <= ids
    assert colours["mold"] == colours["design"]
    assert len(set(colours["mold"].values())) > 1


def test_mold_pairing_colours_labels_and_no_hidden_panel(arts):
    """Every panel of a net has its own colour; no label covers another or sticks out of its
    view; on the mold side no panel lies behind another (the mold is unrolled)."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    doc = json.loads((arts / "mold.json").read_text())
    ids = {p["id"] for p in doc["data"]["panels"] if p["net"] == 0}
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = _figure(arts / "mold", "mold", "pairing-net1")
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    ax = _axes(fig, "view-mold")
    colours = {}
    polys = []
    for coll in _collections(ax, "panels") + _collections(ax, "panels-flat"):
        for pid, rgba, path in zip(coll.get_urls(), coll.get_facecolors(), coll.get_paths(),
                                   strict=True):
            colours.setdefault(pid, tuple(np.round(rgba, 6)))
            polys.append(Polygon(path.vertices[:4]))
    assert len(set(colours.values())) == len(ids)               # no colour used twice
    areas = sum(p.area for p in polys)
    assert unary_union(polys).area == pytest.approx(areas, rel=1e-6)   # nothing hidden
    for side in ("mold", "design"):
        ax = _axes(fig, f"view-{side}")
        frame = ax.get_window_extent(renderer)
        boxes = [t.get_bbox_patch().get_window_extent(renderer) for t in ax.texts
                 if (t.get_gid() or "").startswith(f"label-{side}:")]
        assert len(boxes) >= (0.5 * len(ids) if side == "mold" else 1), side
        for k, box in enumerate(boxes):
            assert frame.x0 - 1 <= box.x0 and box.x1 <= frame.x1 + 1, side
            assert frame.y0 - 1 <= box.y0 and box.y1 <= frame.y1 + 1, side
            assert not any(box.overlaps(other) for other in boxes[k + 1:]), side


def test_mold_pieces_mark_the_flat_panels(arts):
    doc = json.loads((arts / "mold.json").read_text())
    panels = doc["data"]["panels"]
    fig = _figure(arts / "mold", "mold", "pieces")
    ax = _axes(fig, "view-design-1")
    (coll,) = _collections(ax, "design-1")
    assert set(coll.get_urls()) == {p["id"] for p in panels}
    flat = [p for p in panels if p["flat"]]
    assert bool(_collections(ax, "flat-outlines")) == bool(flat)
    title = fig.texts[0].get_text()
    assert f"{len(panels) - len(flat)} curved panel" in title and f"{len(flat)} flat" in title
    # one scale bar for every view, every view at its scale; the legend only what is drawn
    views = [a for a in fig.axes if (a.get_gid() or "").startswith("view-")]
    bars = [line for a in views for line in a.lines if line.get_gid() == "scale-bar"]
    assert len(bars) == 1 and len(views) >= 2
    per_inch = {round((a.get_xlim()[1] - a.get_xlim()[0])
                      / (a.get_position().width * fig.get_size_inches()[0]), 9) for a in views}
    assert len(per_inch) == 1
    (legend,) = fig.legends
    labels = " ".join(t.get_text() for t in legend.get_texts())
    assert ("flat panel" in labels) == bool(flat)


# --------------------------------------------------------------------------------------------
# camera


@pytest.mark.parametrize("stem", ["twisted", "bent"])
def test_camera_frames_the_whole_model(arts, stem):
    """Every view's frame holds the model's whole bounding box, and the model covers at least
    half of the frame's width or height; the drawn axes span exactly that frame."""
    f = read_net(arts / stem).f.reshape(-1, 3)
    for view in standard_views(f):
        x0, x1, y0, y1 = model_frame(view, f)
        xy = view.project(box_corners(f))
        assert (xy[:, 0] >= x0).all() and (xy[:, 0] <= x1).all()
        assert (xy[:, 1] >= y0).all() and (xy[:, 1] <= y1).all()
        p = view.project(f)
        share = max(np.ptp(p[:, 0]) / (x1 - x0), np.ptp(p[:, 1]) / (y1 - y0))
        assert share >= 0.5, (view.name, share)
    fig = _figure(arts / stem, "net", "width")
    for name in ("axonometric", "plan", "elevation"):
        ax = _axes(fig, f"view-{name}")
        (coll,) = _collections(ax, "net")
        pts = np.concatenate([p.vertices for p in coll.get_paths()])
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        assert pts[:, 0].min() >= x0 and pts[:, 0].max() <= x1
        assert pts[:, 1].min() >= y0 and pts[:, 1].max() <= y1
        assert max(np.ptp(pts[:, 0]) / (x1 - x0), np.ptp(pts[:, 1]) / (y1 - y0)) >= 0.5


# --------------------------------------------------------------------------------------------
# units


def test_lengths_carry_the_artifacts_unit(arts):
    """A net in ft: scale bars, colour bars and Clairaut axes say ft (K in 1/ft²)."""
    width = _figure(arts / "feet", "net", "width")
    texts = _texts(width)
    bars = [t for ax in width.axes for t in ax.texts if t.get_gid() == "scale-bar-label"]
    assert len(bars) == 3 and all(t.get_text().endswith(" ft") for t in bars)
    assert any(ax.get_xlabel() == "strip width [ft]" for ax in width.axes)
    curvature = _figure(arts / "feet", "net", "curvature")
    assert any(ax.get_xlabel() == "K [1/ft²]" for ax in curvature.axes)
    clairaut = _texts(_figure(arts / "feet", "net", "clairaut"))
    assert "arc length along the geodesic [ft]" in clairaut
    assert "r cos α − its mean [ft]" in clairaut
    assert not any("mm" in t for t in texts + clairaut)


# --------------------------------------------------------------------------------------------
# sheets


def test_sheet_previews_show_cut_and_score_colours(arts, tmp_path):
    """The report's sheet figures keep the preview's pixels: the CUT and SCORE colours are
    there, and the legend names every layer in its colour."""
    from dgpc_cli.io.dxf import SHEET_LAYERS

    legend = {name: rgb for name, rgb, _ in _layer_legend(SHEET_LAYERS, SHEET_LEGEND)}
    out = dgpc("report", arts / "sheets", "-o", tmp_path / "r").stdout.split()
    pngs = [p for p in out if p.endswith(".png")]
    assert pngs
    for png in pngs:
        rgb = np.asarray(Image.open(png).convert("RGB"), int)
        for layer in ("CUT", "SCORE"):
            target = np.round(255 * np.asarray(legend[layer])).astype(int)
            hits = (np.abs(rgb - target).max(axis=-1) <= 8).sum()
            assert hits > 50, (png, layer)
    fig = _figure(arts / "sheets", "sheets", "sheet01")
    (leg,) = fig.legends
    names = [t.get_text().split(":")[0] for t in leg.get_texts()]
    assert names == ["CUT", "SCORE", "LABEL"]         # the layers this sheet draws on, only
    for line, name in zip(leg.get_lines(), names, strict=True):
        np.testing.assert_allclose(np.asarray(line.get_color())[:3], legend[name])


# --------------------------------------------------------------------------------------------
# the reference under a net


def test_uncovered_reference_shows_orange_with_the_metrics_share():
    """A net over the left half of a plane: the reference faces it does not cover are drawn
    orange, and the covered share the figure states is the coverage metric's."""
    from dgpc_cli.metrics.coverage import coverage, covered_faces
    from dgpc_cli.report.net import UNCOVERED, Reference, field_figure, width_per_quad

    x, y = np.meshgrid(np.linspace(0, 4, 17), np.linspace(0, 2, 9), indexing="ij")
    rv = np.stack([x, y, np.zeros_like(x)], axis=-1).reshape(-1, 3)
    idx = np.arange(17 * 9).reshape(17, 9)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    rf = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                         np.stack([a, c, d], -1).reshape(-1, 3)])
    u, v = np.meshgrid(np.linspace(0, 2, 9), np.linspace(0, 2, 9), indexing="ij")
    f = np.stack([u, v, np.zeros_like(u)], axis=-1)
    metric = coverage(f, rv, rf)
    ref = Reference(rv, rf, covered_faces(f, rv, rf), metric["area_fraction"])
    assert ref.area_fraction == pytest.approx(metric["area_fraction"], abs=1e-12)
    assert 0.4 < metric["area_fraction"] < 0.6
    with style():
        fig = field_figure([f], [width_per_quad(f)], title="t", label="strip width [m]",
                           unit="m", reference=ref)
    (layer,) = _collections(_axes(fig, "view-plan"), "reference")
    orange = np.all(np.isclose(layer.get_facecolors(), UNCOVERED), axis=1)
    assert orange.sum() == (ref.covered < 0.5).sum() > 0
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    assert f"reference, covered ({100 * metric['area_fraction']:.1f} %)" in labels


# --------------------------------------------------------------------------------------------
# Flat parts


def test_every_overlaid_outline_lies_inside_its_cell():
    """Each congruence class's cell shows its outlines whole: a part as tall as the cell lost
    its top edge to the axes' frame (the timber wall's long, slim strips)."""
    from dgpc_cli.report.flat import overlay_figure

    t = np.linspace(0.0, 1.0, 20)
    A = np.column_stack([6.0 * t, 0.02 * np.sin(np.pi * t)])          # 6 m × 0.35 m strips
    B = A[::-1] + [0.3, 0.35]
    parts = [{"id": f"S{k}", "class": f"C{k}", "outline": np.vstack([A, B]).tolist(),
              "score": [[A[i].tolist(), B[-1 - i].tolist()] for i in range(1, 19)],
              "alignment": {"matrix": np.eye(2).tolist(), "translation": [0.0, 0.0]}}
             for k in range(3)]
    classes = [{"id": f"C{k}", "quantity": 1, "representative": f"S{k}",
                "members": [f"S{k}"], "max_error": 0.0, "max_relative_error": 0.0}
               for k in range(3)]
    fig = overlay_figure(parts, classes, "m")
    cells = [a for a in fig.axes if (a.get_gid() or "").startswith("class-")]
    assert len(cells) == 3
    for ax in cells:
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        for line in ax.lines:
            x, y = line.get_data()
            assert x0 < np.min(x) and np.max(x) < x1 and y0 < np.min(y) and np.max(y) < y1


def test_strips_are_seen_from_the_side_the_net_is_seen_from(arts, tmp_path, monkeypatch):
    """The strips' width figure looks at the strips from where the net's figures look at the
    net (the outside of the wall), not from the other side."""
    from dgpc_cli.report import net as net_figures

    dgpc("planarize-strips", arts / "twisted", "-o", tmp_path / "strips")
    seen = {}
    monkeypatch.setattr(net_figures, "field_figure",
                        lambda *a, **kw: seen.setdefault(kw["title"], kw))
    for path, kind in ((arts / "twisted", "net"), (tmp_path / "strips", "strips")):
        page = PAGES[kind](path.with_suffix(".json"))
        page.figures[0][2]()
    (net_kw,) = [kw for t, kw in seen.items() if t.startswith("strip width")]
    (strips_kw,) = [kw for t, kw in seen.items() if t.endswith("planar-quad strips")]
    assert net_kw["front"] is not None and strips_kw.get("front") is not None
    assert float(np.dot(net_kw["front"], strips_kw["front"])) > 0.95
    assert np.allclose(net_kw["up"], strips_kw["up"])


def test_one_index_covers_net_strips_flat_parts_sheets_and_mold(arts, tmp_path):
    """``dgpc report`` of a project's artifacts: one index showing the figures of every one of
    them (net, strips, flat parts, sheets, mold), each linking its own page of metrics."""
    import re

    stems = [arts / n for n in ("bent", "strips", "flat", "sheets", "mold")]
    out = dgpc("report", *stems, "-o", tmp_path / "all").stdout.split()
    assert out[-1] == str(tmp_path / "all-index.html")
    page = (tmp_path / "all-index.html").read_text()
    for name in ("bent", "strips", "flat", "sheets", "mold"):
        assert f'href="all-{name}-index.html"' in page
        assert (tmp_path / f"all-{name}-index.html").is_file()
        figures = re.findall(rf'src="(all-{name}-[^"]+\.png)"', page)
        assert figures and all((tmp_path / f).is_file() for f in figures), name
    assert 'src="all-sheets-sheet01.png"' in page and 'src="all-flat-strips.png"' in page
