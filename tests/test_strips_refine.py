"""planarize-strips --refine K: strips with K rulings per net row, their ends on cubics through
the net's geodesics (dgpc_cli.strips.refine); the refined geodesics pass through the net's
vertices and stay on the surface, and unfold names the parts' rows in net rows."""

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.strips import read_strips
from dgpc_cli.stages.unfold import in_net_rows
from dgpc_cli.strips.refine import net_rows, refine_rows
from dgpc_cli.surfaces.minding import minding_bend

#: A refined point's distance from the surface, relative to its radius, on nets of 21 rows
#: over a quarter turn (the chords there sag 7.7e-4 of the radius: a linear refinement would
#: miss by that much).
ON_SURFACE = 1e-5


def _helix_net(m=21, n=5, R=1.0):
    """A cylinder of radius R (axis z) whose columns are helices (geodesics) over a quarter
    turn: ``f (m, n, 3)``."""
    u = np.linspace(0.0, 0.5 * np.pi, m)[:, None]
    v = np.linspace(0.0, 0.6, n)[None, :]
    theta, z = u + v, 0.8 * u + 0.3 * v
    return np.stack([R * np.cos(theta), R * np.sin(theta), z + 0 * theta], axis=-1)


def _cone_net(m=21, n=5):
    """A cone (apex at the origin, half-angle 30°, axis z) whose columns are its parallels
    over a quarter turn: ``f (m, n, 3)``."""
    theta = np.linspace(0.0, 0.5 * np.pi, m)[:, None]
    z = np.linspace(1.0, 1.5, n)[None, :]
    r = np.tan(np.radians(30.0)) * z
    return np.stack([r * np.cos(theta), r * np.sin(theta), z + 0 * theta], axis=-1)


@pytest.mark.parametrize("K", [1, 2, 3])
def test_refined_geodesics_pass_through_the_net_vertices(K):
    f = _helix_net()
    g = refine_rows(f, K)
    assert g.shape == ((f.shape[0] - 1) * K + 1, f.shape[1], 3)
    assert np.array_equal(g[::K], f)
    assert np.allclose(net_rows(np.arange(g.shape[0])[::K], K), np.arange(f.shape[0]))


def test_refined_rows_stay_on_a_cylinder_and_a_cone():
    """The new rows lie on the surface within ON_SURFACE of its radius, far closer than the
    chords' midpoints (a linear refinement), and at equal arc length between the net's rows."""
    K = 2
    f = _helix_net()
    g = refine_rows(f, K)
    off = np.abs(np.linalg.norm(g[..., :2], axis=-1) - 1.0)
    chord_mid = 0.5 * (f[1:] + f[:-1])
    sag = np.abs(np.linalg.norm(chord_mid[..., :2], axis=-1) - 1.0)
    assert off.max() <= ON_SURFACE
    assert sag.min() > 50 * ON_SURFACE
    steps = np.linalg.norm(np.diff(g, axis=0), axis=-1)
    assert np.allclose(steps[::2], steps[1::2], rtol=1e-4)

    c = _cone_net()
    h = refine_rows(c, K)
    r = np.linalg.norm(h[..., :2], axis=-1)
    assert np.abs(r - np.tan(np.radians(30.0)) * h[..., 2]).max() <= ON_SURFACE * r.max()
    assert np.abs(h[..., 2] - c[:1, :, 2]).max() <= 1e-12           # on its parallel


def test_unfold_records_net_rows():
    """in_net_rows: whole strips span the net's rows; an end on a ruling between two net rows
    is a fractional net row; a joint there too; rows a trimmed part reaches into stay whole."""
    parts = [{"rows": [0, 40]}, {"rows": [0, 17]}, {"rows": [17, 40]},
             {"rows": [3, 9], "trimmed": True}, {"rows": [5, 10], "row_span": [5.5, 10.0]}]
    joints = [{"row": 17}, {"row": 5.5}]
    in_net_rows(parts, joints, 2)
    assert parts[0] == {"rows": [0, 20]}
    assert parts[1] == {"rows": [0, 9], "row_span": [0.0, 8.5]}
    assert parts[2] == {"rows": [8, 20], "row_span": [8.5, 20.0]}
    assert parts[3] == {"rows": [1, 5], "trimmed": True}
    assert parts[4] == {"rows": [2, 5], "row_span": [2.75, 5.0]}
    assert [j["row"] for j in joints] == [8.5, 2.75]


def test_planarize_refine_cli(tmp_path):
    """--refine 2 on a bent catenoid net: strips of 2m − 1 rows, one template, the refinement
    recorded, measured against the refined net (and the net's own quads); unfold's parts span
    the net's rows 0 … m − 1."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 5,
         "--span", 90, "-o", tmp_path / "cat")
    net = read_net(tmp_path / "cat")
    write_net(tmp_path / "bent", NetArtifact(f=minding_bend(net.f, 0.8)))
    m = net.shape[0]
    dgpc("planarize-strips", tmp_path / "bent", "--refine", 2, "-o", tmp_path / "s")
    art = read_strips(tmp_path / "s")
    assert art.parameters["refine"] == 2
    assert art.parameters["method"] == "template"
    assert all(r["rows"] == 2 * m - 1 for r in art.records)
    fab = art.metrics["fabrication"]
    assert fab["refine"] == 2
    assert fab["max_end_gap_mm"] <= 1e-6
    assert fab["max_deviation_relative"] <= 0.05
    assert 0 < fab["net_quads_max_deviation_relative"] <= 0.05
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "flat")
    flat = read_flat(tmp_path / "flat")
    assert {tuple(p["rows"]) for p in flat.parts} == {(0, m - 1)}
    assert len(flat.classes) == 1

    result = dgpc("planarize-strips", tmp_path / "bent", "--refine", 0, "-o", tmp_path / "s0",
                  expect=2)                                   # K: a whole number ≥ 1
    assert "--refine" in result.stderr
