"""Issue 27, done means: the default command chain on real roofs — `init MESH` (no method, no
option but the unit), `optimize --mode fit`, `planarize-strips --trim`, `unfold --stock-length
6`, `nest --sheet 6100x2500` — exits 0 on the clipped dome and on the roof with a curved edge;
its trimmed parts cover at least 97 % of the reference's area, none is narrower than a quarter
of the mean width (the dome's geodesics converge round a pole), every board is at most 6 m and
every board is placed on a sheet."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc, metrics
from outline_meshes import clipped_dome, roof, write
from shapely.geometry import LineString, Point, Polygon

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net
from dgpc_cli.io.sheets import read_sheets

STOCK = 6.0                                               # m


def mesh_area(path) -> float:
    mesh = load_mesh(path)
    tri = mesh.vertices[mesh.faces]
    return float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                      axis=1).sum())


@pytest.fixture(scope="module", params=["dome", "roof"])
def chain(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(request.param)
    mesh = write(d / "roof.obj", {"dome": clipped_dome, "roof": roof}[request.param]())
    dgpc("init", mesh, "--units", "m", "-o", d / "n0")
    dgpc("optimize", d / "n0", "--mode", "fit", "-o", d / "n1")
    dgpc("planarize-strips", d / "n1", "--trim", "-o", d / "strips")
    unfold = dgpc("unfold", d / "strips", "--stock-length", STOCK, "-o", d / "boards")
    dgpc("nest", d / "boards", "--sheet", "6100x2500", "-o", d / "sheets")
    return request.param, d, mesh, unfold.stderr


def test_the_fitted_net_is_sound(chain):
    _, d, _, _ = chain
    assert read_net(d / "n1").status["state"] == "converged"
    assert not metrics(d / "n1")["edges"]["folded"]


def test_the_trimmed_boards_cover_the_roof(chain):
    _, d, mesh, _ = chain
    parts = read_flat(d / "boards").parts
    area = sum(Polygon(p["outline"]).area for p in parts)
    assert area >= 0.97 * mesh_area(mesh)
    assert area <= 1.001 * mesh_area(mesh)


def test_no_board_is_pinched(chain):
    """The least distance between a board's developed geodesics, measured here, is at least a
    quarter of the boards' mean width (their area over their length); unfold warns of none."""
    _, d, _, stderr = chain
    parts = read_flat(d / "boards").parts
    mean = sum(Polygon(p["outline"]).area for p in parts) / sum(p["length"] for p in parts)
    for p in parts:
        ga, gb = (np.asarray(g, float) for g in p["geodesics"])
        least = min(min(LineString(gb).distance(Point(x)) for x in ga),
                    min(LineString(ga).distance(Point(x)) for x in gb))
        assert least >= 0.25 * mean, p["id"]
    flat = json.loads((d / "boards.json").read_text())
    assert flat["metrics"]["narrowest"]["ratio"] >= 0.25 and not flat["metrics"]["pinched"]
    assert "narrower than" not in stderr


def test_every_board_fits_the_stock_and_a_sheet(chain):
    _, d, _, _ = chain
    parts = read_flat(d / "boards").parts
    assert len({p["id"].split(".")[0] for p in parts}) < len(parts)      # strips were cut
    for p in parts:
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9, p["id"]
    sheets = read_sheets(d / "sheets")
    assert sorted(q["part"] for q in sheets.data["placements"]) == sorted(p["id"] for p in parts)
