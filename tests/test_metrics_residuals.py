"""Geometric residuals of SPEC §7 on analytic nets (paper Prop. 2.7, Lemma 2.5, (2), (5), (7))."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dgpc_cli.metrics.residuals import (
    arclength_spread,
    edge_length_stats,
    finite_max,
    gpc_angle_defect,
    gpc_angle_defect_max,
    jacobi_residual,
    orthogonality,
    ratio_spread,
    strip_width_spread,
)


def revolution_net(r, h, theta):
    """Meridian net f(u, v) = (r(u) cos θ_v, r(u) sin θ_v, h(u)), shape (m, n, 3)."""
    r, h, theta = (np.asarray(x, float) for x in (r, h, theta))
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta),
                     np.broadcast_to(h[:, None], (r.size, theta.size))], axis=-1)


def sphere_net(R=2.0, m=21, n=15, phi=(0.3, 2.8), theta=(0.0, 2.0)):
    p = np.linspace(*phi, m)
    return revolution_net(R * np.sin(p), R * np.cos(p), np.linspace(*theta, n))


def rigid(f, seed=0):
    rot = Rotation.random(random_state=seed).as_matrix()
    return f @ rot.T + np.array([3.0, -1.0, 7.5])


PROFILES = {
    "sphere": sphere_net(),
    "cylinder": revolution_net(np.full(17, 1.5), np.linspace(0, 4, 17), np.linspace(0, 3, 12)),
    "cone": revolution_net(np.linspace(0.5, 2.0, 17), np.linspace(0, 3, 17),
                           np.linspace(0, 2 * np.pi, 25)),
    "bowling_pin": revolution_net(1 + 0.4 * np.sin(np.linspace(0, 6, 31)),
                                  np.linspace(0, 5, 31), np.linspace(0, 2.5, 9)),
}


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_meridian_nets_are_discrete_gpc(name):
    f = rigid(PROFILES[name])
    d = gpc_angle_defect(f)
    m, n, _ = f.shape
    assert d.shape == (m, n)
    assert np.isnan(d[:, 0]).all() and np.isnan(d[:, -1]).all()
    assert np.isfinite(d[:, 1:-1]).all()            # includes the boundary rows u = 0, m-1
    assert gpc_angle_defect_max(f) <= 1e-12
    o = orthogonality(f)
    assert np.isfinite(o[1:-1, 1:-1]).all()
    assert np.isnan(o[0]).all() and np.isnan(o[:, -1]).all()
    assert finite_max(o) <= 1e-12


def test_uneven_meridians_are_not_discrete_gpc():
    # equal angular steps are needed: at f = (r, 0, h), cos α12 = −δr sin(Δθ₊/2)/l and
    # cos α_12̄ = −δr sin(Δθ₋/2)/l
    p = np.linspace(0.3, 2.8, 9)
    f = revolution_net(np.sin(p), np.cos(p), np.array([0.0, 0.2, 0.5, 0.6, 1.1]))
    assert gpc_angle_defect_max(f) > 1e-2
    # and T^v = unit(e2 − e4) gets a radial component, so orthogonality fails as well
    assert finite_max(orthogonality(f)) > 1e-3


def test_sheared_lattice_has_the_exact_defect():
    k = 0.3
    u, v = np.meshgrid(np.arange(5.0), np.arange(6.0), indexing="ij")
    f = np.stack([u + k * v, v, 0 * u], axis=-1)
    # alpha12 = π/2 − atan k, alpha_12̄ = π/2 + atan k: defect 2 atan k, same for the other pair
    d = gpc_angle_defect(f)
    assert np.allclose(d[:, 1:-1], 2 * np.arctan(k), atol=1e-14)
    assert np.allclose(orthogonality(f)[1:-1, 1:-1], k / np.hypot(1, k), atol=1e-14)


def test_noisy_net_has_clearly_nonzero_residuals():
    rng = np.random.default_rng(7)
    f = sphere_net() + 1e-2 * rng.standard_normal((21, 15, 3))
    assert gpc_angle_defect_max(f) > 1e-2
    assert finite_max(orthogonality(f)) > 1e-3


def test_boundary_rows_use_only_the_existing_pair():
    f = sphere_net(m=5, n=5)
    f = f.copy()
    theta2 = np.arctan2(f[0, 2, 1], f[0, 2, 0])
    f[0, 2] += 0.05 * np.array([-np.sin(theta2), np.cos(theta2), 0.0])   # along the parallel
    d = gpc_angle_defect(f)
    assert d[0, 2] > 1e-3
    # vertex (0, 1) sees the moved vertex as its e2 neighbour: alpha12 changes, not alpha_12̄
    assert d[0, 1] > 1e-3
    assert d[-1, 1:-1].max() <= 1e-12


def test_arclength_spread():
    f = sphere_net(m=11, n=6)
    s = arclength_spread(f)
    assert s.shape == (6,) and s.max() <= 1e-12
    g = f.copy()
    g[5, 3] = f[4, 3] + 0.6 * (f[6, 3] - f[4, 3])   # on the chord: lengths 0.6c, 0.4c
    lu = np.linalg.norm(g[1:, 3] - g[:-1, 3], axis=-1)
    expected = (lu.max() - lu.min()) / lu.mean()
    s = arclength_spread(g)
    assert s[3] == pytest.approx(expected, rel=1e-12)
    assert s[3] > 0.1 and np.delete(s, 3).max() <= 1e-12


def test_strip_width_and_ratio_spread_distinguish_5_from_7():
    theta = np.array([0.0, 0.2, 0.5, 0.6, 1.1, 1.3])          # uneven columns
    p = np.linspace(0.4, 2.6, 9)
    f = revolution_net(2 * np.sin(p), 2 * np.cos(p), theta)
    sw = strip_width_spread(f)
    chords = 2 * np.sin(np.diff(theta) / 2)
    assert sw.shape == (9,)
    assert np.allclose(sw, (chords.max() - chords.min()) / chords.mean(), rtol=1e-12)
    rs = ratio_spread(f)                                        # still a surface of revolution
    assert rs.shape == (8,) and rs.max() <= 1e-12
    # equal columns: (7) holds as well
    f_eq = revolution_net(2 * np.sin(p), 2 * np.cos(p), np.linspace(0, 1.3, 6))
    assert strip_width_spread(f_eq).max() <= 1e-12
    # a generic surface (paraboloid graph) is not isometric to a surface of revolution by (5)
    x, y = np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 6), indexing="ij")
    g = np.stack([x, y, x ** 2 + 2 * y ** 2 + 0.3 * x * y], axis=-1)
    assert ratio_spread(g).max() > 1e-2


def test_jacobi_residual():
    # cone meridians in arc length: strip width linear in u → developable, (2) = 0
    s = np.linspace(0, 3, 13)
    f = revolution_net(0.5 + 0.6 * s, 0.8 * s, np.linspace(0, 2, 7))
    j = jacobi_residual(f)
    assert j.shape == (13, 6) and np.isnan(j[[0, -1]]).all()
    assert np.nanmax(np.abs(j)) <= 1e-12
    # sphere: w(u±1) = w(u)·(cos Δφ ± ...) → δ_uu w = −4 sin²(Δφ/2) w
    p = np.linspace(0.3, 2.8, 21)
    f = sphere_net(R=2.0, m=21, n=7)
    lv = np.linalg.norm(f[:, 1:] - f[:, :-1], axis=-1)
    dphi = p[1] - p[0]
    expected = -4 * np.sin(dphi / 2) ** 2 * lv[1:-1] / lv.mean()
    assert np.allclose(jacobi_residual(f)[1:-1], expected, atol=1e-14)
    assert finite_max(jacobi_residual(f), absolute=True) > 1e-3


def test_edge_length_stats_and_fold_check():
    u, v = np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij")
    f = np.stack([u, v, 0 * u], axis=-1)
    st = edge_length_stats(f)
    assert st == {"min": 1.0, "mean": 1.0, "max": 1.0, "min_ratio": 1.0, "folded": False}
    g = f.copy()
    g[:, 1, 1] = g[:, 0, 1] + 0.05                # v-edges (u, 0)->(u, 1) of length 0.05
    st = edge_length_stats(g)
    assert st["min"] == pytest.approx(0.05)
    assert st["min_ratio"] < 0.1 and st["folded"] is True


def test_finite_max():
    assert finite_max(np.array([np.nan, -3.0, 2.0])) == 2.0
    assert finite_max(np.array([np.nan, -3.0, 2.0]), absolute=True) == 3.0
    assert finite_max(np.full(3, np.nan)) is None
