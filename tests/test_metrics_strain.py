"""Strain tensor D of paper §6.1 against a reference net."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dgpc_cli.metrics.strain import principal_strains, strain, strain_tensor


def revolution_net(r, h, theta):
    r, h, theta = (np.asarray(x, float) for x in (r, h, theta))
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta),
                     np.broadcast_to(h[:, None], (r.size, theta.size))], axis=-1)


def bottle():
    t = np.linspace(0, 4, 17)
    return revolution_net(1 + 0.3 * np.sin(1.5 * t), t, np.linspace(0, 2 * np.pi, 21))


def planar(m=5, n=6, a=(1.0, 0, 0), b=(0, 1.0, 0)):
    u, v = np.meshgrid(np.arange(m, dtype=float), np.arange(n, dtype=float), indexing="ij")
    return u[..., None] * np.asarray(a) + v[..., None] * np.asarray(b)


def test_identical_and_rigidly_moved_nets_have_zero_strain():
    f0 = bottle()
    amount, summary = strain(f0, f0)
    assert amount.shape == f0.shape[:2]
    assert summary == {"max": 0.0, "mean": 0.0}
    moved = f0 @ Rotation.random(random_state=3).as_matrix().T + [1.0, 2.0, -4.0]
    assert strain(moved, f0)[1]["max"] <= 1e-12


def test_identical_rhombic_nets_have_zero_strain():
    # the paper's printed off-diagonal tan(α_1̄2̄ − α_1̄2) − tan(α_12̄ − α12) would be
    # −2 tan(60°) here; a strain against f0 must vanish
    f0 = planar(a=(1.0, 0, 0), b=(0.5, np.sqrt(0.75), 0))
    D = strain_tensor(f0, f0)
    assert np.abs(D).max() <= 1e-15


@pytest.mark.parametrize("s", [1e-5, 0.01, -0.2])
def test_uniform_scaling_gives_two_s(s):
    f0 = bottle()
    amount, summary = strain((1 + s) * f0, f0)
    assert np.allclose(amount, 2 * abs(s), rtol=1e-9, atol=1e-15)
    assert summary["max"] == pytest.approx(2 * abs(s), rel=1e-9)
    D = strain_tensor((1 + s) * f0, f0)
    assert np.allclose(D[..., 0, 0], s) and np.allclose(D[..., 1, 1], s)
    assert np.abs(D[..., 0, 1]).max() <= 1e-12


def test_simple_shear_of_a_planar_grid():
    k = 0.2
    f0 = planar()
    f = f0.copy()
    f[..., 0] += k * f0[..., 1]                         # x' = x + k y
    D = strain_tensor(f, f0)
    # u-edges (along x) keep their length, v-edges become √(1 + k²) long, and the right angle
    # between them decreases by γ = atan k at every corner → D12 = tan(γ)/2 = k/2
    assert np.allclose(D[..., 0, 0], 0.0, atol=1e-15)
    assert np.allclose(D[..., 1, 1], np.sqrt(1 + k * k) - 1, atol=1e-15)
    assert np.allclose(D[..., 0, 1], k / 2, atol=1e-14)
    assert np.allclose(D[..., 1, 0], k / 2, atol=1e-14)
    a, d, b = 0.0, np.sqrt(1 + k * k) - 1, k / 2
    lam = np.linalg.eigvalsh(np.array([[a, b], [b, d]]))
    amount, summary = strain(f, f0)
    assert np.allclose(amount, np.abs(lam).sum(), atol=1e-14)
    # the sign of γ follows the direction of the shear
    f_neg = f0.copy()
    f_neg[..., 0] -= k * f0[..., 1]
    assert np.allclose(strain_tensor(f_neg, f0)[..., 0, 1], -k / 2, atol=1e-14)


def test_symmetric_pure_shear_amount():
    k = 0.01
    f0 = planar(7, 7)
    x, y = f0[..., 0].copy(), f0[..., 1].copy()
    f = f0.copy()
    f[..., 0], f[..., 1] = x + k / 2 * y, y + k / 2 * x
    amount, summary = strain(f, f0)
    # D11 = D22 = √(1 + k²/4) − 1 ≈ k²/8, D12 = tan(2 atan(k/2))/2 ≈ k/2 → |λ1| + |λ2| ≈ k
    e = np.sqrt(1 + k * k / 4) - 1
    b = np.tan(2 * np.arctan(k / 2)) / 2
    assert np.allclose(amount, abs(e + b) + abs(e - b), atol=1e-14)
    assert summary["max"] == pytest.approx(k, rel=1e-3)


def test_local_stretch_is_localized():
    f0 = planar(6, 6)
    f = f0.copy()
    f[3:, :, 0] += 0.1            # u-edges between rows 2 and 3 are 10 % longer
    amount, _ = strain(f, f0)
    assert np.allclose(amount[[2, 3]], 0.05, atol=1e-14)   # (ε(l1) + ε(l_1̄))/2 = 0.05
    assert np.allclose(amount[[0, 1, 4, 5]], 0.0, atol=1e-15)


def test_principal_strains_closed_form_matches_eigh():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((50, 2, 2))
    A = 0.5 * (A + np.swapaxes(A, 1, 2))
    lam1, lam2, theta = principal_strains(A)
    w = np.linalg.eigvalsh(A)
    assert np.allclose(lam1, w[:, 1]) and np.allclose(lam2, w[:, 0])
    v = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    assert np.allclose(np.einsum("kij,kj->ki", A, v), lam1[:, None] * v)


def test_shape_mismatch_is_rejected():
    with pytest.raises(ValueError, match="differ in shape"):
        strain_tensor(planar(4, 5), planar(5, 4))
