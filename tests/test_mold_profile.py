"""The formulas of paper §4.2.2 and Prop. 4.3 behind extract-mold, and the panel helpers."""

import math

import numpy as np
import pytest
from mold_samples import deform, gehry_profile, sector_net, wavy_profile

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.curvature import strip_widths
from dgpc_cli.mold.extract import extract_mold
from dgpc_cli.mold.panels import (
    block_max,
    cut_pieces,
    dimensionless_curvature,
    panel_id,
    quad_isometry_error,
)
from dgpc_cli.mold.profile import (
    admissible_sine,
    check_revolution,
    check_same_surface,
    column_factors,
    meridian,
    mold_grid,
    net_widths,
)
from dgpc_cli.surfaces.minding import minding_bend


def test_meridian_with_lambda_is_the_discrete_minding_bending():
    """The mold with N = λ·(n−1) of a full-ring net is minding_bend(·, λ) of it (one formula)."""
    f = sector_net(wavy_profile(), 11, 25, 360.0)
    wd = net_widths(f)
    for lam in (0.6, 0.9, 1.0):
        mer = meridian(wd.d, wd.l, 24, lam=lam)
        g = minding_bend(f, lam)
        assert mer.segments == pytest.approx(24 * lam)
        assert np.allclose(mer.r, np.hypot(g[:, 0, 0], g[:, 0, 1]), rtol=1e-12)
        assert np.allclose(mer.h, g[:, 0, 2] - g[0, 0, 2], atol=1e-12)


def test_full_ring_is_recovered_exactly():
    prof = gehry_profile()
    f = sector_net(prof, 15, 31, 360.0)
    wd = net_widths(f)
    mer = meridian(wd.d, wd.l, 30)
    r, h, _ = prof.resample(15)
    assert np.allclose(mer.r, r, rtol=1e-12) and np.allclose(mer.h, h - h[0], atol=1e-12)
    assert mer.lam == 1.0 and not mer.lowered


def test_admissible_sine_and_lowering(caplog):
    d = np.array([1.0, 1.5, 1.7])
    ell = np.array([0.5, 0.5])
    s, u = admissible_sine(d, ell)
    assert (s, u) == (0.5, 0)
    mer = meridian(d, ell, 20)                     # sin(π/20) < 0.5: lowered to N = 6
    assert mer.lowered and mer.segments == pytest.approx(6.0) and mer.requested == 20
    assert mer.x[0] == 0.0 and mer.x[1] > 0
    assert "lowered λ to 0.3" in caplog.text
    kept = meridian(d, ell, 20, segments=4)
    assert not kept.lowered and kept.segments == 4
    with pytest.raises(DgpcError, match="--segments"):
        meridian(d, ell, 20, segments=1.5)


def test_check_revolution_names_the_worst_rows():
    f = sector_net(wavy_profile(), 9, 7, 90.0)
    f[5, 3] *= 1.01
    wd = net_widths(f)
    with pytest.raises(DgpcError) as err:
        check_revolution(wd, 1e-6, "bad.json")
    text = str(err.value)
    assert text.startswith("bad.json: not isometric to a surface of revolution")
    assert "rows 4-5" in text and "rows 5-6" in text and "2 of 8 row pairs" in text
    assert "beyond --revolution-tol 1e-06" in text        # the option's name, not its old one
    check_revolution(net_widths(sector_net(wavy_profile(), 9, 7, 90.0)), 1e-12, "ok.json")


def test_check_same_surface():
    f = sector_net(wavy_profile(), 9, 7, 90.0)
    ref = net_widths(f)
    check_same_surface(ref, net_widths(deform(f, 0.7, angle=1.0)), 1e-9, "b", "a")
    check_same_surface(ref, net_widths(sector_net(wavy_profile(), 9, 13, 45.0)), 1e-9, "b", "a")
    with pytest.raises(DgpcError, match="b: has 8 rows"):
        check_same_surface(ref, net_widths(sector_net(wavy_profile(), 8, 7, 90.0)), 1e-9, "b",
                           "a")
    with pytest.raises(DgpcError, match=r"b: .*meridian edges differ by up to 2.00e-02"):
        check_same_surface(ref, net_widths(1.02 * f), 1e-6, "b", "a")


def test_nets_with_other_column_widths_map_onto_the_same_mold():
    """(5) without equal v-edges: column j covers θ_j = 2 arcsin(c_j sin(π/N)) of the mold, and
    each quad is congruent to its mold quad."""
    prof = wavy_profile()
    a = sector_net(prof, 9, 7, 90.0)
    r, h, _ = prof.resample(9)
    theta = np.radians([10.0, 20.0, 15.0, 5.0, 25.0])           # unequal columns
    phi = np.concatenate([[0.0], np.cumsum(theta)])
    b = np.stack([r[:, None] * np.cos(phi), r[:, None] * np.sin(phi),
                  np.broadcast_to(h[:, None], (9, 6))], axis=-1)
    c = column_factors(strip_widths(b), net_widths(a).d)
    mold = extract_mold([("a", a), ("b", b)], segments=24)
    assert np.allclose(mold.nets[1].theta, theta, rtol=1e-12)
    assert np.allclose(c, np.sin(theta / 2) / math.sin(math.pi / 24))
    assert max(float(p.error.max()) for p in mold.nets) <= 1e-12


def test_quad_isometry_error_and_block_max():
    f = sector_net(wavy_profile(), 7, 6, 60.0)
    wd = net_widths(f)
    mer = meridian(wd.d, wd.l, 5, segments=30)
    theta = mer.column_angles(np.ones(5))
    assert np.allclose(theta, 2 * math.pi / 30)
    mold = mold_grid(mer, theta)
    assert quad_isometry_error(f, mold).max() <= 1e-12
    g = f.copy()
    g[3, 2, 2] += 0.01                               # moves one vertex: 4 quads change
    err = quad_isometry_error(g, mold)
    assert set(map(tuple, np.argwhere(err > 1e-6))) == {(2, 1), (2, 2), (3, 1), (3, 2)}
    a = np.arange(30.0).reshape(6, 5)
    assert block_max(a, 4).tolist() == [[18.0, 19.0], [28.0, 29.0]]


def test_dimensionless_curvature_is_minus_delta_uu_w_over_w():
    """On a sphere's meridian net with equal latitude steps (equal u-edges) κ is exactly the
    paper's −δ_uu w / w, ≈ K l² = (l/R)²; on a cylinder it is 0."""
    R, phi, theta = 5.0, np.radians(np.linspace(-40, 50, 19)), np.radians(np.arange(5) * 12.0)
    f = np.stack([R * np.cos(phi)[:, None] * np.cos(theta), R * np.cos(phi)[:, None] *
                  np.sin(theta), np.broadcast_to(R * np.sin(phi)[:, None], (19, 5))], axis=-1)
    w = strip_widths(f)
    kappa = dimensionless_curvature(f)
    assert np.allclose(kappa[1:-1], -(w[2:] - 2 * w[1:-1] + w[:-2]) / w[1:-1], rtol=1e-12)
    ell = np.linalg.norm(f[1, 0] - f[0, 0])
    assert np.allclose(kappa[1:-1], (ell / R) ** 2, rtol=1e-2)
    assert np.all(np.isnan(kappa[[0, -1]]))
    g = sector_net(gehry_profile(), 21, 5, 60.0)              # rows 0..7 on the cylinder
    kg = dimensionless_curvature(g)
    assert np.abs(kg[1:7]).max() <= 1e-12 and np.abs(kg[10]).min() > 1e-3


def test_cut_pieces_greedy_and_ids():
    rows = np.array([[0, 2], [2, 4], [4, 6], [6, 8], [8, 9]])
    needs = np.array([False, True, True, True, True])
    ell = np.full(9, 0.5)
    pieces, of = cut_pieces(rows, needs, ell, 2.0)
    assert [(p.id, p.start, p.stop, p.length) for p in pieces] == \
        [("M01", 2, 6, 2.0), ("M02", 6, 9, 1.5)]
    assert of.tolist() == [-1, 0, 0, 1, 1]
    pieces, of = cut_pieces(rows, np.array([True, False, True, True, False]), ell, None)
    assert [(p.start, p.stop) for p in pieces] == [(0, 2), (4, 8)]
    with pytest.raises(DgpcError, match="--mold-max-length"):
        cut_pieces(rows, needs, ell, 0.9)
    assert panel_id(3, 7, 2) == "P-u03-v07" and panel_id(3, 112, 3, "N2-") == "N2-P-u003-v112"
