"""Clairaut's relation (9): r cos α constant along the geodesics of a surface of revolution."""

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dgpc_cli.metrics.clairaut import as_axis, clairaut, clairaut_values, parse_axis

Z_AXIS = (np.zeros(3), np.array([0.0, 0.0, 1.0]))


def revolution_net(r, h, theta):
    r, h, theta = (np.asarray(x, float) for x in (r, h, theta))
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta),
                     np.broadcast_to(h[:, None], (r.size, theta.size))], axis=-1)


def helix_net(R=2.0, omega=0.7, k=0.5, m=41, n=9, ds=0.05):
    """u-lines: helices θ = θ_v + ω s, z = k s (geodesics of the cylinder of radius R)."""
    s = ds * np.arange(m)
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)[None, :] + omega * s[:, None]
    return np.stack([R * np.cos(theta), R * np.sin(theta),
                     np.broadcast_to(k * s[:, None], theta.shape)], axis=-1)


def test_parse_axis():
    a, d = parse_axis("1, 2, 3, 0, 0, 2")
    assert np.array_equal(a, [1.0, 2.0, 3.0]) and np.array_equal(d, [0.0, 0.0, 1.0])
    a, d = parse_axis("0,0,0,1,1,0")
    assert np.allclose(d, [np.sqrt(0.5), np.sqrt(0.5), 0])


@pytest.mark.parametrize("text, reason", [
    ("1,2,3,4,5", "6 comma-separated numbers"),
    ("1,2,3,4,5,6,7", "6 comma-separated numbers"),
    ("1,2,3,a,5,6", "6 comma-separated numbers"),
    ("1,2,,4,5,6", "6 comma-separated numbers"),
    ("1,2,3,nan,0,1", "non-finite"),
    ("1,2,3,0,inf,1", "non-finite"),
    ("1,2,3,0,0,0", "zero vector"),
])
def test_parse_axis_rejects(text, reason):
    with pytest.raises(ValueError, match=reason) as err:
        parse_axis(text)
    assert "\n" not in str(err.value)


def test_as_axis_accepts_pairs_and_text():
    a, d = as_axis(([0, 0, 1], [0, 3, 0]))
    assert np.array_equal(d, [0, 1, 0])
    assert np.array_equal(as_axis("0,0,1,0,3,0")[1], d)
    with pytest.raises(ValueError):
        as_axis(5)


def test_meridian_net_has_zero_clairaut_constant():
    t = np.linspace(0, 5, 31)
    f = revolution_net(1 + 0.4 * np.sin(t), t, np.linspace(0, 2 * np.pi, 17))
    c = clairaut_values(f, Z_AXIS)
    assert np.isnan(c[[0, -1]]).all() and np.isfinite(c[1:-1]).all()
    assert np.abs(c[1:-1]).max() <= 1e-12
    res = clairaut(f, Z_AXIS)
    assert res["max_mad_over_radius"] <= 1e-12
    assert res["mean_abs"] <= 1e-12
    assert res["max_relative_mad"] is None         # r cos α = 0: relative MAD undefined


def test_cylinder_helices_satisfy_clairaut_exactly():
    R, omega, k, ds = 2.0, 0.7, 0.5, 0.05
    f = helix_net(R, omega, k, ds=ds)
    res = clairaut(f, Z_AXIS)
    per = res["per_geodesic"]
    assert len(per["mean"]) == f.shape[1] - 2 and per["v"] == list(range(1, f.shape[1] - 1))
    assert max(per["mad"]) <= 1e-12
    assert res["max_relative_mad"] <= 1e-12
    # discrete: T^u ∥ f(u+1) − f(u−1) = (2R sin δ (−sin φ, cos φ), 2 k ds), δ = ω ds
    delta = omega * ds
    discrete = R * R * np.sin(delta) / np.hypot(R * np.sin(delta), k * ds)
    assert np.allclose(per["mean"], discrete, rtol=1e-13)
    # smooth: r cos α with cos α = Rω / √(R²ω² + k²); the discrete value is O(δ²) close
    smooth = R * R * omega / np.hypot(R * omega, k)
    assert np.allclose(per["mean"], smooth, rtol=1e-4)
    assert res["mean_abs"] == pytest.approx(discrete, rel=1e-13)
    assert res["mean_radius"] == pytest.approx(R, rel=1e-14)


def test_invariant_under_rigid_motion_with_moved_axis():
    f = helix_net()
    rot = Rotation.random(random_state=11).as_matrix()
    shift = np.array([5.0, -2.0, 1.0])
    g = f @ rot.T + shift
    axis = (rot @ Z_AXIS[0] + shift, rot @ Z_AXIS[1])
    a, b = clairaut(f, Z_AXIS), clairaut(g, axis)
    assert np.allclose(a["per_geodesic"]["mean"], b["per_geodesic"]["mean"], rtol=1e-12)
    assert b["max_relative_mad"] <= 1e-12
    # a wrong axis breaks the relation
    assert clairaut(g, Z_AXIS)["max_relative_mad"] > 1e-2


def test_non_geodesics_violate_clairaut():
    # loxodrome-like curves on a sphere: φ = φ0 + s, θ = θ_v + 0.8 s (not geodesics)
    s = np.linspace(0, 1.5, 31)[:, None]
    phi = 0.5 + s
    theta = np.linspace(0, 2, 7)[None, :] + 0.8 * s
    f = np.stack([np.sin(phi) * np.cos(theta), np.sin(phi) * np.sin(theta),
                  np.broadcast_to(np.cos(phi), theta.shape)], axis=-1)
    assert clairaut(f, Z_AXIS)["max_relative_mad"] > 5e-2


def test_two_row_net_is_json_safe():
    f = helix_net(m=2)
    res = clairaut(f, Z_AXIS)
    assert res["max_relative_mad"] is None and res["per_geodesic"]["mad"] == [None] * 7
    json.dumps(res, allow_nan=False)


def test_boundary_u_lines_are_not_counted_as_geodesics():
    """The angle condition says nothing about the two boundary u-lines: a bent boundary
    column must not change the Clairaut summary of the interior geodesics."""
    f = helix_net(2.0, 0.7, 0.5, ds=0.05)
    bent = f.copy()
    bent[:, 0, 2] += 0.3 * np.sin(np.linspace(0, 3, f.shape[0]))
    assert clairaut(bent, Z_AXIS)["max_mad"] == clairaut(f, Z_AXIS)["max_mad"]
