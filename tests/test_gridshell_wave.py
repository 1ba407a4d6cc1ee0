"""Geodesic gridshell on wave.obj (paper §6.2.1, Fig. 14): two transversal fitted nets,
`dgpc laths`, cut list against the OBJ polylines."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc
from data_files import WAVE

from dgpc_cli.geodesics.laths import Lath, find_crossings
from dgpc_cli.io.laths import read_cut_list, read_polylines
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net


@pytest.fixture(scope="module")
def shell(tmp_path_factory):
    d = tmp_path_factory.mktemp("shell")
    for name, direction in (("a", "1,0,0"), ("b", "0,1,0")):
        dgpc("init", WAVE, "--method", "geodesic", "--direction", direction, "--rows", 30,
             "--cols", 20, "--extend", 0, "-o", d / f"{name}0")
        dgpc("optimize", d / f"{name}0", "--mode", "fit", "-o", d / name)
    r = dgpc("laths", d / "a", d / "b", "-o", d / "shell")
    assert r.stdout.strip() == str(d / "shell.json")
    return d


def point_at(poly, s):
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(poly, axis=0), axis=1))])
    return np.array([np.interp(s, cum, poly[:, k]) for k in range(3)])


def test_cut_list_matches_polylines(shell):
    rows = read_cut_list(shell / "shell.csv")
    polys = read_polylines(shell / "shell.obj")
    assert [r["lath_id"] for r in rows] == list(polys)
    assert {r["family"] for r in rows} == {"A", "B"} and len(rows) == 40
    for r in rows:
        length = np.linalg.norm(np.diff(polys[r["lath_id"]], axis=0), axis=1).sum()
        assert abs(length - r["length"]) <= 1e-9
    # the laths are the u-lines of the nets
    a = read_net(shell / "a").f
    assert np.array_equal(polys["A01"], a[:, 0])


def test_crossings_lie_on_both_laths(shell):
    diag = load_mesh(WAVE).bbox_diagonal
    rows = {r["lath_id"]: r for r in read_cut_list(shell / "shell.csv")}
    polys = read_polylines(shell / "shell.obj")
    n = 0
    for lid, r in rows.items():
        if r["family"] != "A":
            continue
        assert r["crossings"] == sorted(r["crossings"])
        for s, other in zip(r["crossings"], r["crossing_laths"], strict=True):
            back = rows[other]
            k = back["crossing_laths"].index(lid)  # the same joint, seen from the other lath
            pa, pb = point_at(polys[lid], s), point_at(polys[other], back["crossings"][k])
            assert np.linalg.norm(pa - pb) <= 1e-3 * diag
            n += 1
    assert n > 200   # most of the 20 x 20 laths cross
    doc = json.loads((shell / "shell.json").read_text())
    assert doc["kind"] == "laths" and doc["metrics"]["crossings"] == n
    assert doc["data"]["cut_list"] == "shell.csv"


def test_refuses_to_overwrite(shell):
    r = dgpc("laths", shell / "a", shell / "b", "-o", shell / "shell", expect=1)
    assert "already exists" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_crossing_of_two_straight_laths():
    t = np.linspace(0, 4, 5)[:, None]
    a = Lath("A01", "A", np.hstack([t, np.full_like(t, 1.5), np.zeros_like(t)]))
    b = Lath("B01", "B", np.hstack([np.full_like(t, 2.5), t, np.full_like(t, 0.01)]))
    c = find_crossings([a], [b], gap=0.1)
    assert c.a.tolist() == [0] and c.b.tolist() == [0]
    assert c.s_a[0] == pytest.approx(2.5) and c.s_b[0] == pytest.approx(1.5)
    assert c.gap[0] == pytest.approx(0.01)
    assert find_crossings([a], [b], gap=0.001).a.size == 0   # too far apart
    # a lath that ends on the other one does not cross it
    short = Lath("B02", "B", np.hstack([np.full_like(t, 2.5), t * 0.375, np.zeros_like(t)]))
    assert find_crossings([a], [short], gap=0.1).a.size == 0


def test_laths_inspect_and_report(shell, tmp_path):
    """`dgpc inspect` and `dgpc report` read the laths artifact (checked against its OBJ and
    cut list): metrics as written, a PNG of the two families and the index."""
    from cli_helpers import metrics

    from dgpc_cli.io.laths import read_laths

    art = read_laths(shell / "shell")
    assert metrics(shell / "shell") == art.metrics
    assert len(art.family("A")) == art.data["laths"]["A"] == 20
    assert art.metrics["crossings"] == art.data["crossings"] > 0
    out = dgpc("report", shell / "shell", "-o", tmp_path / "r").stdout.split()
    assert out == [str(tmp_path / "r-laths.png"), str(tmp_path / "r-index.html")]
    assert (tmp_path / "r-laths.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = (tmp_path / "r-index.html").read_text()
    assert "r-laths.png" in html and "crossing_gap_max" in html


def test_laths_with_an_edited_cut_list_are_refused(shell, tmp_path):
    import shutil

    for suffix in (".json", ".obj", ".csv"):
        shutil.copy(shell / f"shell{suffix}", tmp_path / f"s{suffix}")
    doc = json.loads((tmp_path / "s.json").read_text())
    doc["data"]["cut_list"] = "s.csv"
    doc["data"]["obj"] = "s.obj"
    (tmp_path / "s.json").write_text(json.dumps(doc))
    dgpc("inspect", tmp_path / "s")
    (tmp_path / "s.csv").write_text((tmp_path / "s.csv").read_text().replace("A01", "A99"))
    r = dgpc("inspect", tmp_path / "s", expect=1)
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and "s.csv" in err and "sha256" in err
    r = dgpc("report", tmp_path / "s", "-o", tmp_path / "r", expect=1)
    assert not list(tmp_path.glob("r-*"))
