"""Every constraint term's Jacobian against central finite differences (SPEC §4)."""

import numpy as np
import pytest
from jacobian_check import FrozenReference, assert_jacobian_matches_finite_differences

from dgpc_cli.core.constraints import TERMS
from dgpc_cli.core.constraints.isometry import boundary_angle_pairs
from dgpc_cli.core.layout import NetLayout


def _random_state(layout, rng):
    """A generic point in variable space: positions, non-unit e and w off the edge lengths."""
    u, v = np.meshgrid(np.linspace(0, 1, layout.m), np.linspace(0, 1.3, layout.n), indexing="ij")
    f = np.stack([u, v, 0.3 * np.sin(2 * u + v)], axis=-1) + 0.05 * rng.standard_normal(
        (layout.m, layout.n, 3))
    x = layout.pack(f)
    return x + 0.05 * rng.standard_normal(x.size)


def _bound(name, layout, rng):
    if name == "isometry":
        w0 = rng.uniform(0.5, 1.5, layout.n_edges)
        cos0 = rng.uniform(-0.3, 0.3, len(boundary_angle_pairs(layout)))
        return lambda x: TERMS[name](x, layout, w0=w0, cos0=cos0)
    if name in ("displacement_fairness", "displacement_smoothness", "closeness"):
        f0 = rng.standard_normal((layout.n_vertices, 3))
        return lambda x: TERMS[name](x, layout, f0)
    if name == "crease_guard":
        # a start net with small third differences and a small margin: some runs of the
        # random state pass it (active rows), some do not
        f0 = 0.02 * rng.standard_normal((layout.n_vertices, 3))
        return lambda x: TERMS[name](x, layout, f0, margin=0.2)
    if name == "handles":
        ids, targets = np.array([0, 7, layout.n_vertices - 1]), rng.standard_normal((3, 3))
        return lambda x: TERMS[name](x, layout, ids, targets)
    if name == "approximation":
        # closest points frozen (as the term's Jacobian assumes): half of them normal offsets
        # (point-to-plane rows), half with a tangential part (point-to-point rows)
        frozen = FrozenReference(layout.n_vertices, rng)
        return lambda x: TERMS[name](x, layout, frozen)
    if name == "boundary":
        frozen = FrozenReference(layout.n_vertices, rng)
        rim = np.array([0, 1, 2, layout.n - 1, layout.n_vertices - 1])
        return lambda x: TERMS[name](x, layout, frozen, rim)
    if name == "rim":
        # start vertices and directions such that some rim rows are drawn in, some not
        ids = np.array([0, 1, 2, layout.n - 1, layout.n_vertices - 1])
        start = rng.standard_normal((len(ids), 3))
        outward = rng.standard_normal((len(ids), 3))
        outward /= np.linalg.norm(outward, axis=1, keepdims=True)
        slack = np.array([0.0, 0.1, 0.0, 2.0, 0.0])
        return lambda x: TERMS[name](x, layout, ids, start, outward, slack)
    return lambda x: TERMS[name](x, layout)


@pytest.mark.parametrize("name", sorted(TERMS))
def test_jacobian_matches_finite_differences(name):
    rng = np.random.default_rng(7)
    layout = NetLayout(5, 4)
    term = _bound(name, layout, rng)
    x = _random_state(layout, rng)
    assert_jacobian_matches_finite_differences(term, x, layout.size)


@pytest.mark.parametrize("name", sorted(TERMS))
def test_jacobian_pattern_does_not_depend_on_values(name):
    rng = np.random.default_rng(3)
    layout = NetLayout(4, 5)
    term = _bound(name, layout, rng)
    _, J1 = term(_random_state(layout, rng))
    _, J2 = term(np.zeros(layout.size) + 1e-3)
    assert np.array_equal(J1.row, J2.row) and np.array_equal(J1.col, J2.col)


def test_equation_counts_follow_the_paper():
    m, n = 7, 6
    layout = NetLayout(m, n)
    x = layout.pack(np.random.default_rng(0).standard_normal((m, n, 3)))
    E = layout.n_edges
    counts = {name: TERMS[name](x, layout)[0].size for name in
              ("net", "gpc", "arclength", "equal_strip_width", "developable", "fairness",
               "ratio_revolution", "equal_u_edges")}
    assert counts["net"] == 4 * E                          # 8|E| in the paper's doubled layout
    assert counts["gpc"] == 2 * (m * n - n - 2 * m + 2)    # paper's table
    assert counts["arclength"] == n * (m - 2)              # 2n(m-2) with w_ij, w_ji
    assert counts["equal_strip_width"] == m * (n - 2)      # 2m(n-2) with w_ij, w_ji
    assert counts["developable"] == (n - 1) * (m - 2)
    assert counts["ratio_revolution"] == (m - 1) * (n - 2)
    assert counts["fairness"] == 3 * ((m - 2) * n + m * (n - 2))
    assert counts["equal_u_edges"] == (m - 1) * (n - 1)
    assert NetLayout(21, 21).paper_size == 8043


def test_approximation_is_point_to_plane_inside_and_point_to_point_off_the_boundary():
    """A vertex above a face slides freely along it; one beyond the boundary is pulled back."""
    layout = NetLayout(3, 3)
    f = np.zeros((3, 3, 3))
    f[..., 0], f[..., 1] = np.meshgrid(np.arange(3.0), np.arange(3.0), indexing="ij")
    f[0, 0] = (0.0, 0.0, 0.5)          # above the half plane x ≥ 0: normal offset
    f[2, 2] = (-1.0, 2.0, 0.0)         # beyond its boundary x = 0, in its plane

    class HalfPlane:
        def closest(self, q):
            p = q.copy()
            p[:, 0] = np.maximum(p[:, 0], 0.0)
            p[:, 2] = 0.0
            return p, np.tile([0.0, 0.0, 1.0], (len(q), 1))

    f = f.reshape(-1, 3)
    phi, _ = TERMS["approximation"](layout.pack(f), layout, HalfPlane())
    phi = phi.reshape(-1, 3)
    assert np.allclose(phi[0], [0, 0, 0.5])        # point-to-plane: only the normal part
    assert np.allclose(phi[8], [-1.0, 0, 0])       # off the boundary: the whole offset
    assert np.abs(np.delete(phi, [0, 8], axis=0)).max() == 0
