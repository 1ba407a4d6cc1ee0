"""Edge vectors, corner angles and the frame T^u, T^v, N of paper §2.2.1."""

import numpy as np
import pytest

from dgpc_cli.metrics.frames import (
    angle,
    as_grid,
    corner_angles,
    edge_lengths,
    edge_vectors,
    net_frames,
    tangent_frames,
    unit_edge_vectors,
)


def lattice(m, n, a, b):
    """Planar net f(u, v) = u·a + v·b, shape (m, n, 3)."""
    u, v = np.meshgrid(np.arange(m, dtype=float), np.arange(n, dtype=float), indexing="ij")
    return u[..., None] * np.asarray(a, float) + v[..., None] * np.asarray(b, float)


def test_square_grid_frame_and_masks():
    f = lattice(4, 5, [2.0, 0, 0], [0, 3.0, 0])
    e1, e2, e3, e4 = unit_edge_vectors(f)
    assert np.allclose(e1[:-1], [1, 0, 0]) and np.isnan(e1[-1]).all()
    assert np.allclose(e3[1:], [-1, 0, 0]) and np.isnan(e3[0]).all()
    assert np.allclose(e2[:, :-1], [0, 1, 0]) and np.isnan(e2[:, -1]).all()
    assert np.allclose(e4[:, 1:], [0, -1, 0]) and np.isnan(e4[:, 0]).all()

    fr = net_frames(f)
    interior = np.zeros((4, 5), bool)
    interior[1:-1, 1:-1] = True
    assert np.array_equal(fr.has_Tu, np.broadcast_to(np.arange(4)[:, None] % 3 != 0, (4, 5)))
    assert np.array_equal(fr.has_Tv, np.broadcast_to(np.arange(5)[None, :] % 4 != 0, (4, 5)))
    assert np.array_equal(fr.has_N, interior)
    assert np.allclose(fr.Tu[fr.has_Tu], [1, 0, 0])
    assert np.allclose(fr.Tv[fr.has_Tv], [0, 1, 0])
    assert np.allclose(fr.N[interior], [0, 0, 1])
    for a in (fr.angles.a12, fr.angles.a1b2, fr.angles.a1b2b, fr.angles.a12b):
        assert np.allclose(a[np.isfinite(a)], np.pi / 2, atol=1e-15)


def test_one_sided_frames_exist_everywhere():
    f = lattice(3, 4, [1.0, 0, 0], [0, 1.0, 0])
    Tu, Tv, N = tangent_frames(f, one_sided=True)
    assert np.isfinite(Tu).all() and np.isfinite(Tv).all() and np.isfinite(N).all()
    assert np.allclose(Tu, [1, 0, 0]) and np.allclose(Tv, [0, 1, 0]) and np.allclose(N, [0, 0, 1])


def test_rhombic_corner_angles_follow_paper_notation():
    # a and b at 60°: alpha12 = ∠(e1, e2) = 60°, alpha_1̄2 = ∠(e3, e2) = 120°, ...
    f = lattice(3, 3, [1.0, 0, 0], [np.cos(np.pi / 3), np.sin(np.pi / 3), 0])
    a = corner_angles(f)
    assert a.a12[1, 1] == pytest.approx(np.pi / 3, abs=1e-15)
    assert a.a1b2[1, 1] == pytest.approx(2 * np.pi / 3, abs=1e-15)
    assert a.a1b2b[1, 1] == pytest.approx(np.pi / 3, abs=1e-15)
    assert a.a12b[1, 1] == pytest.approx(2 * np.pi / 3, abs=1e-15)
    # corner (0, 0) has only alpha12
    assert np.isfinite(a.a12[0, 0])
    assert np.isnan([a.a1b2[0, 0], a.a1b2b[0, 0], a.a12b[0, 0]]).all()
    # the tangents of a non-orthogonal lattice are not orthogonal: <Tu, Tv> = cos 60°
    Tu, Tv, N = tangent_frames(f)
    assert np.dot(Tu[1, 1], Tv[1, 1]) == pytest.approx(0.5, abs=1e-15)
    assert np.allclose(N[1, 1], [0, 0, 1])


def test_angle_is_accurate_near_zero_and_pi():
    t = 1e-9
    a = np.array([1.0, 0, 0])
    b = np.array([np.cos(t), np.sin(t), 0])
    assert angle(a, b) == pytest.approx(t, rel=1e-12)
    assert angle(a, -b) == pytest.approx(np.pi - t, rel=1e-15)
    assert angle(3 * a, 0.5 * b) == pytest.approx(t, rel=1e-12)   # scale invariant


def test_edge_vectors_and_lengths_match_differences():
    rng = np.random.default_rng(1)
    f = rng.standard_normal((5, 4, 3))
    E1, E2, E3, E4 = edge_vectors(f)
    assert np.allclose(E1[2, 1], f[3, 1] - f[2, 1])
    assert np.allclose(E3[2, 1], f[1, 1] - f[2, 1])
    assert np.allclose(E2[2, 1], f[2, 2] - f[2, 1])
    assert np.allclose(E4[2, 1], f[2, 0] - f[2, 1])
    lu, lv = edge_lengths(f)
    assert lu.shape == (4, 4) and lv.shape == (5, 3)
    assert lv[3, 2] == pytest.approx(np.linalg.norm(f[3, 3] - f[3, 2]))


def test_degenerate_edge_gives_nan_not_garbage():
    f = lattice(3, 3, [1.0, 0, 0], [0, 1.0, 0])
    f[1, 2] = f[1, 1]                         # zero-length v-edge
    e1, e2, e3, e4 = unit_edge_vectors(f)
    assert np.isnan(e2[1, 1]).all()
    assert np.isnan(corner_angles(f).a12[1, 1])


@pytest.mark.parametrize("bad, reason", [
    (np.zeros((3, 3)), "(m, n, 3)"),
    (np.zeros((1, 4, 3)), "at least 2×2"),
    (np.full((2, 2, 3), np.nan), "non-finite"),
])
def test_as_grid_rejects(bad, reason):
    with pytest.raises(ValueError, match=reason.replace("(", r"\(").replace(")", r"\)")):
        as_grid(bad)
