"""Discrete Gaussian curvature from the Jacobi equation (1) on analytic meridian nets."""

import numpy as np
import pytest

from dgpc_cli.metrics.curvature import gaussian_curvature, strip_widths


def revolution_net(r, h, theta):
    """Meridian net f(u, v) = (r(u) cos θ_v, r(u) sin θ_v, h(u)), shape (m, n, 3)."""
    r, h, theta = (np.asarray(x, float) for x in (r, h, theta))
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta),
                     np.broadcast_to(h[:, None], (r.size, theta.size))], axis=-1)


def test_sphere_gives_one_over_R_squared():
    R = 2.5
    p = np.linspace(0.2, 2.9, 41)
    f = revolution_net(R * np.sin(p), R * np.cos(p), np.linspace(0, 2 * np.pi, 33))
    K = gaussian_curvature(f)
    assert K.shape == (41, 32)
    assert np.isnan(K[[0, -1]]).all() and np.isfinite(K[1:-1]).all()
    # exact for equal latitude steps: δ_uu w = −4 sin²(Δφ/2) w and l = 2R sin(Δφ/2)
    assert np.allclose(K[1:-1], 1 / R ** 2, rtol=1e-9)


def test_coarse_sphere_is_still_exact_and_scales_with_one_over_lambda_squared():
    p = np.linspace(0.5, 2.5, 7)
    f = revolution_net(np.sin(p), np.cos(p), np.linspace(0, 1, 4))
    assert np.allclose(gaussian_curvature(f)[1:-1], 1.0, rtol=1e-12)
    assert np.allclose(gaussian_curvature(3 * f)[1:-1], 1 / 9, rtol=1e-12)


def test_cylinder_and_cone_are_flat():
    f = revolution_net(np.full(21, 1.7), np.linspace(-1, 2, 21), np.linspace(0, 4, 13))
    assert np.nanmax(np.abs(gaussian_curvature(f))) <= 1e-12
    s = np.linspace(0, 2, 21)
    cone = revolution_net(0.3 + 0.5 * s, np.sqrt(0.75) * s, np.linspace(0, 4, 13))
    assert np.nanmax(np.abs(gaussian_curvature(cone))) <= 1e-12


@pytest.mark.parametrize("arclength", [True, False])
def test_catenoid_is_negative_and_close_to_analytic(arclength):
    c = 1.3
    if arclength:          # meridian in arc length: s = c sinh t
        t = np.arcsinh(np.linspace(-2.0, 2.0, 81) / c)
    else:                  # uniform in t: unequal u-edges, the non-uniform difference is needed
        t = np.linspace(-1.2, 1.2, 81)
    f = revolution_net(c * np.cosh(t), c * t, np.linspace(0, 2 * np.pi, 41))
    K = gaussian_curvature(f)[1:-1]
    exact = -1 / (c ** 2 * np.cosh(t[1:-1]) ** 4)
    assert (K < 0).all()
    assert np.allclose(K, exact[:, None], rtol=2e-3)


def test_wrong_spacing_formula_would_fail_the_catenoid():
    # guard against the uniform-spacing formula K = −δ_uu w /(w l²) on unequal u-edges: at
    # uniform t it is off by far more than the 0.2 % accepted above
    c, t = 1.3, np.linspace(-1.2, 1.2, 81)
    f = revolution_net(c * np.cosh(t), c * t, np.linspace(0, 2 * np.pi, 41))
    w = strip_widths(f)[:, 0]
    lu = np.linalg.norm(f[1:, 0] - f[:-1, 0], axis=-1)
    l_mean = 0.5 * (lu[1:] + lu[:-1])
    naive = -(w[2:] - 2 * w[1:-1] + w[:-2]) / (w[1:-1] * l_mean ** 2)
    exact = -1 / (c ** 2 * np.cosh(t[1:-1]) ** 4)
    assert np.max(np.abs(naive / exact - 1)) > 0.1
    assert np.max(np.abs(gaussian_curvature(f)[1:-1, 0] / exact - 1)) < 2e-3


def test_strip_widths_shape_and_values():
    f = revolution_net(np.array([1.0, 2.0]), np.array([0.0, 1.0]), np.array([0.0, np.pi / 2]))
    w = strip_widths(f)
    assert w.shape == (2, 1)
    assert np.allclose(w[:, 0], [np.sqrt(2), 2 * np.sqrt(2)])
    assert np.isnan(gaussian_curvature(f)).all()            # no interior row


def test_curvature_is_symmetric_in_the_two_boundary_geodesics_of_a_strip():
    # a generic (non-GPC) net whose u-edges differ between neighbouring u-lines: reversing the
    # order of the u-lines, or the direction of u, must just reverse K
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 7), indexing="ij")
    f = np.stack([u * (1 + 0.8 * v), v + 0.2 * u * u, 0.3 * np.sin(2 * u + 3 * v)], axis=-1)
    K = gaussian_curvature(f)
    assert np.nanmax(np.abs(K)) > 1e-2
    assert np.allclose(gaussian_curvature(f[:, ::-1]), K[:, ::-1], equal_nan=True, rtol=1e-12)
    assert np.allclose(gaussian_curvature(f[::-1]), K[::-1], equal_nan=True, rtol=1e-12)
