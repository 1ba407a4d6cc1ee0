"""``dgpc report`` on every artifact kind: each kind's figures (PNG at their sizes, not blank,
byte-deterministic) and an index.html that shows them with the metrics grouped and their units."""

import json
import re

import numpy as np
import pytest
from cli_helpers import bent_catenoid_chain, dgpc
from PIL import Image

from dgpc_cli.io.net import read_net
from dgpc_cli.report.clairaut import CLAIRAUT_SIZE
from dgpc_cli.report.convergence import CONVERGENCE_SIZE
from dgpc_cli.report.mold import PAIRING_SIZE, PIECES_SIZE, PROFILE_SIZE
from dgpc_cli.report.render import DPI
from dgpc_cli.report.strips import TEMPLATE_SIZE
from dgpc_cli.report.tables import ITEMS
from dgpc_cli.report.views import VIEWS_SIZE
from dgpc_cli.surfaces.minding import minding_bend

#: Figure sizes in inches, as rendered; the 3-D figures (width, curvature, strain) are
#: VIEWS_SIZE, the flat parts' pages fit their content.
SIZES = {"clairaut": CLAIRAUT_SIZE, "convergence": CONVERGENCE_SIZE, "profile": PROFILE_SIZE,
         "pairing-net1": PAIRING_SIZE, "pieces": PIECES_SIZE, "template": TEMPLATE_SIZE}


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    """One artifact of each kind, small: a twisted catenoid net (with an axis), an isometric
    optimization of a half sphere, strips, flat parts, a mold and sheets."""
    d = tmp_path_factory.mktemp("report")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 120, "--twist", 0.3, "-o", d / "net")
    dgpc("init", "--surface", "revolution", "--profile", "sphere", "--rows", 9, "--cols", 9,
         "--span", 90, "-o", d / "hs0")
    f = read_net(d / "hs0").f
    g = minding_bend(f, 0.9)
    idx = [(0, 0), (0, 8), (8, 4)]
    (d / "handles.json").write_text(json.dumps(
        {"handles": [{"index": list(i), "target": g[i].tolist()} for i in idx]}))
    dgpc("optimize", d / "hs0", "--mode", "isometric", "--handles", d / "handles.json",
         "--steps", 2, "-o", d / "iso")
    bent_catenoid_chain(d)
    return d


def _check_png(path, size):
    img = Image.open(path)
    assert img.size == (round(size[0] * DPI), round(size[1] * DPI))
    grey = np.asarray(img.convert("L"), float)
    assert grey.std() > 5.0                                   # not blank
    return np.asarray(img.convert("RGB"), int)


def _check_index(path, pngs, metrics):
    text = path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "<script" not in text
    for png in pngs:
        assert f'src="{png}"' in text
    for name in metrics:                 # every metric: rows of its own or a table per item
        assert f"<td>{name}" in text or f"<summary>{ITEMS.get(name)} (" in text, name
    assert "<td>steps[" not in text and "history" not in text     # no solver history rows
    return text


def _report(sample, stem, prefix):
    return [p for p in dgpc("report", sample / stem, "-o", sample / prefix).stdout.split()]


@pytest.mark.parametrize("stem, names", [
    ("net", ["width", "curvature", "clairaut"]),
    ("iso", ["width", "curvature", "strain", "convergence"]),   # deformed: off the surface
    ("strips", ["width", "template", "deviation"]),
    ("flat", ["overlay", "strips"]),
    ("mold", ["profile", "pairing-net1", "pieces"]),
])
def test_report_figures_and_index(sample, stem, names):
    out = _report(sample, stem, f"{stem}-a")
    pngs = [f"{stem}-a-{n}.png" for n in names]
    assert out == [str(sample / p) for p in pngs] + [str(sample / f"{stem}-a-index.html")]
    for n in names:
        if stem != "flat":
            _check_png(sample / f"{stem}-a-{n}.png", SIZES.get(n, VIEWS_SIZE))
    doc = json.loads((sample / f"{stem}.json").read_text())
    assert doc["metrics"]
    _check_index(sample / f"{stem}-a-index.html", pngs, doc["metrics"])
    # byte-deterministic
    _report(sample, stem, f"{stem}-b")
    for n in names:
        assert (sample / f"{stem}-a-{n}.png").read_bytes() == \
               (sample / f"{stem}-b-{n}.png").read_bytes()
    a = (sample / f"{stem}-a-index.html").read_text().replace(f"{stem}-a-", "")
    assert a == (sample / f"{stem}-b-index.html").read_text().replace(f"{stem}-b-", "")


def test_curvature_is_red_blue_white(sample):
    """A catenoid has K < 0 everywhere: its quads are blue, none red (Fig. 17 colours)."""
    _report(sample, "net", "colours")
    rgb = _check_png(sample / "colours-curvature.png", VIEWS_SIZE)
    plot = rgb[: int(0.85 * rgb.shape[0])]                    # above the colour bar
    r, g, b = plot[..., 0], plot[..., 1], plot[..., 2]
    blue = (b > 150) & (r < 120) & (g < 120)
    red = (r > 150) & (b < 120) & (g < 120)
    assert blue.sum() > 200 and red.sum() == 0


def test_sheets_report_shows_every_preview(sample):
    """One figure per sheet (the preview nest wrote, pixel for pixel, with a legend), linked
    from the index with a relative path; the header states the sheet size in its unit."""
    out = _report(sample, "sheets", "sh")
    doc = json.loads((sample / "sheets.json").read_text())
    count = doc["data"]["sheet_count"]
    assert count >= 1
    assert out == [str(sample / f"sh-sheet{i + 1:02d}.png") for i in range(count)] + \
        [str(sample / "sh-index.html")]
    text = (sample / "sh-index.html").read_text()
    hrefs = re.findall(r'<img src="([^"]+)"', text)
    assert hrefs == [f"sh-sheet{i + 1:02d}.png" for i in range(count)]
    for i, sheet in enumerate(doc["data"]["sheets"]):
        figure = Image.open(sample / hrefs[i])
        preview = Image.open(sample / doc["data"]["files"][sheet["png"]]["path"])
        assert figure.size[0] > preview.size[0] and figure.size[1] > preview.size[1]
    sheet = doc["data"]["sheet"]
    assert f"{sheet['width']:g} × {sheet['height']:g} {doc['data']['units']}" in text
    for name in doc["metrics"]:
        assert f"<td>{name}" in text


def test_strain_figure_needs_the_input_net(sample, tmp_path):
    """Without its recorded input net an isometric net still reports, without strain."""
    for ext in (".json", ".obj"):
        (tmp_path / f"iso{ext}").write_bytes((sample / f"iso{ext}").read_bytes())
    out = dgpc("report", tmp_path / "iso", "-o", tmp_path / "r").stdout.split()
    assert [p.rsplit("-", 1)[1] for p in out] == ["width.png", "curvature.png",
                                                  "convergence.png", "index.html"]


def test_existing_files_need_force(sample):
    _report(sample, "mold", "again")
    result = dgpc("report", sample / "mold", "-o", sample / "again", expect=1)
    assert "already exists" in result.stderr
    dgpc("report", sample / "mold", "-o", sample / "again", "--force")


def test_metrics_table_flattens_and_summarises():
    from dgpc_cli.report.tables import LIST_MAX, flatten

    rows = dict(flatten({"b": {"x": 1.0, "y": None}, "a": [1, 2],
                         "long": list(range(LIST_MAX + 1)),
                         "hist": [{"R": float(i)} for i in range(LIST_MAX + 1)],
                         "flag": True}))
    assert list(rows) == ["a", "b.x", "b.y", "flag", "hist", f"hist[{LIST_MAX}].R", "long"]
    assert rows["a"] == "[1, 2]" and rows["b.y"] == "null" and rows["flag"] == "true"
    assert rows["long"] == f"{LIST_MAX + 1} values, min 0, max {LIST_MAX}"
    assert rows[f"hist[{LIST_MAX}].R"] == str(LIST_MAX)


def test_lengths_are_labelled_with_the_unit(tmp_path):
    """A net in ft: its figures' axes and the index's table name the unit of every length."""
    from dgpc_cli.report.tables import metric_unit

    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 7, "--cols", 5,
         "--span", 120, "--units", "ft", "-o", tmp_path / "net")
    dgpc("report", tmp_path / "net", "-o", tmp_path / "r")
    text = (tmp_path / "r-index.html").read_text()
    assert "lengths in <b>ft</b>" in text
    assert re.search(r"<tr><td>edges\.max</td><td class=.v.>[0-9.e-]+</td><td>ft</td></tr>",
                     text)
    assert re.search(r"<tr><td>gaussian_curvature\.max</td><td class=.v.>[0-9.e-]+</td>"
                     r"<td>1/ft²</td></tr>", text)
    assert re.search(r"<tr><td>R</td><td class=.v.>[0-9.e-]+</td><td></td></tr>", text)
    assert [metric_unit(k, "m") for k in ("per_part.S-v01.length_mm", "total_area_m2",
                                          "hausdorff.relative", "hausdorff.max",
                                          "strain.max", "clairaut.max_relative_mad",
                                          "covered_area")] == \
        ["mm", "m²", "", "m", "", "", "m²"]
