"""Issue 'core' done-means: init + optimize + inspect on surfaces of revolution (paper §6.1)."""

import json

import numpy as np
import pytest
from cli_helpers import add_noise, dgpc, metrics

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.io.net import read_net
from dgpc_cli.surfaces.minding import minding_bend


def bbox_diagonal(f):
    f = f.reshape(-1, 3)
    return float(np.linalg.norm(f.max(0) - f.min(0)))


def test_meridian_net_is_gpc_and_revolution_mode_leaves_it_in_place(tmp_path):
    s0, s1 = tmp_path / "sphere", tmp_path / "sphere-rev"
    dgpc("init", "--surface", "revolution", "--profile", "sphere", "--rows", 21, "--cols", 21,
         "-o", s0)
    m0 = metrics(s0)
    assert m0["gpc_angle_defect_max"] <= 1e-12
    assert m0["orthogonality_max"] <= 1e-12
    dgpc("optimize", s0, "--mode", "revolution", "-o", s1)
    a, b = read_net(s0).f, read_net(s1).f
    assert np.abs(a - b).max() <= 1e-9 * bbox_diagonal(a)
    assert metrics(s1)["strip_width_spread_max"] <= 1e-12


def test_clairaut_on_a_twisted_bowling_pin(tmp_path):
    """Paper Fig. 11: geodesics that are not meridians satisfy r cos α = const (9)."""
    s0, s1, ref = tmp_path / "pin0", tmp_path / "pin", tmp_path / "pin-ref.obj"
    dgpc("init", "--surface", "revolution", "--profile", "bowling-pin", "--rows", 41,
         "--cols", 21, "--twist", 3.0, "--reference-out", ref, "-o", s0)
    dgpc("optimize", s0, "--mode", "fit", "--reference", ref, "-o", s1)
    m = metrics(s1)
    c = m["clairaut"]
    assert c["mean_abs"] >= 0.2 * c["mean_radius"]           # really not meridians
    assert m["gpc_angle_defect_max"] <= 1e-6
    assert c["max_relative_mad"] <= 0.002                      # SPEC §8: ≤ 0.2 % at 41 rows
    assert m["edges"]["min_ratio"] >= 0.1                      # not folded
    assert m["orthogonality_max"] <= 1e-6
    assert m["residuals"]["approximation"] <= 1e-8          # vertices on the reference
    assert m["hausdorff"]["net_to_reference_max"] <= 1e-3 * m["hausdorff"]["diagonal"]
    # the initial, twisted net is far from geodesic: the test can fail
    assert metrics(s0)["clairaut"]["max_relative_mad"] > 0.01


def test_isometric_deformation_of_a_half_sphere(tmp_path):
    """Paper Fig. 10, 13: three boundary handles moved by ≈ 20 % of the radius, reached in 5
    steps; the targets come from an exact isometric (Minding) bending of the half sphere, so
    the deformation exists."""
    s0, s1 = tmp_path / "hs0", tmp_path / "hs"
    dgpc("init", "--surface", "revolution", "--profile", "sphere", "--rows", 21, "--cols", 21,
         "--span", 90, "-o", s0)
    f = read_net(s0).f
    g = minding_bend(f, 0.85)
    idx = [(0, 0), (0, 20), (20, 10)]
    moves = [np.linalg.norm(g[i] - f[i]) / 5.0 for i in idx]
    assert min(moves) >= 0.16 and max(moves) >= 0.19
    handles = tmp_path / "handles.json"
    handles.write_text(json.dumps({"handles": [{"index": list(i), "target": g[i].tolist()}
                                               for i in idx]}))
    dgpc("optimize", s0, "--mode", "isometric", "--handles", handles, "--steps", 5, "-o", s1)
    m = metrics(s1, "--against", s0)
    out = read_net(s1).f
    assert max(np.linalg.norm(out[i] - g[i]) for i in idx) <= 1e-6
    assert m["strain"]["max"] <= 1e-5
    assert m["R"] <= 1e-8


def test_revolution_mode_on_a_noisy_twisted_net(tmp_path):
    s0 = tmp_path / "tw0"
    dgpc("init", "--surface", "revolution", "--profile", "bowling-pin", "--rows", 21,
         "--cols", 21, "--twist", 0.5, "-o", s0)
    noisy = add_noise(s0, tmp_path / "tw-noisy", 0.01)
    assert metrics(noisy)["strip_width_spread_max"] > 0.01
    res = dgpc("-q", "optimize", noisy, "--mode", "revolution", "-o", tmp_path / "tw", expect=3)
    m = metrics(tmp_path / "tw")
    assert m["strip_width_spread_max"] <= 1e-6
    assert m["gpc_angle_defect_max"] <= 1e-6
    # isometric to a surface of revolution, exactly; but the noise left its strips unequal
    # (u-edges of a row): its quads are further than --max-strain from that surface's, so it
    # is not converged for a mold, and the message names the rows
    assert m["mold_panel_error"]["max"] > 3e-4
    assert "off the surface of revolution" in res.stderr and "rows " in res.stderr
    dgpc("optimize", noisy, "--mode", "revolution", "--max-strain", 0.01, "-o", tmp_path / "tw2")


def test_developable_mode_on_a_noisy_cone(tmp_path):
    s0 = tmp_path / "cone0"
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 21, "--cols", 21,
         "-o", s0)
    assert abs(metrics(s0)["jacobi_residual_max"]) <= 1e-12
    noisy = add_noise(s0, tmp_path / "cone-noisy", 0.01)
    assert metrics(noisy)["jacobi_residual_max"] > 1e-3
    dgpc("optimize", noisy, "--mode", "developable", "-o", tmp_path / "cone")
    assert metrics(tmp_path / "cone")["jacobi_residual_max"] <= 1e-8


def test_optimize_is_byte_deterministic(tmp_path):
    s0 = tmp_path / "c0"
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 11, "--cols", 9,
         "--twist", 0.3, "-o", s0)
    for name in ("a", "b"):
        dgpc("optimize", s0, "--mode", "revolution", "-o", tmp_path / name)
    for ext in (".json", ".obj"):
        assert (tmp_path / f"a{ext}").read_bytes().replace(b'"a.obj"', b"") == \
               (tmp_path / f"b{ext}").read_bytes().replace(b'"b.obj"', b"")


@pytest.mark.parametrize("shape", [(3, 3), (5, 4)])
def test_smallest_nets_work(tmp_path, shape):
    m, n = shape
    dgpc("init", "--surface", "revolution", "--profile", "cylinder", "--rows", m, "--cols", n,
         "-o", tmp_path / "s")
    assert NetLayout(m, n).n_vertices == read_net(tmp_path / "s").f.shape[0] * n
