"""Terms of the one-template fit of planarize-strips (template isometry, gauge, ruling
fairness, seam) and the shared planarity/lateral/closeness terms on its layout: Jacobians
against finite differences, fixed patterns, and what their residuals measure."""

import numpy as np
import pytest
from jacobian_check import FrozenReference, assert_jacobian_matches_finite_differences

from dgpc_cli.core.constraints.planarity import lateral, planarity, surface_closeness
from dgpc_cli.core.constraints.template import (
    StripSetLayout,
    plane_offsets,
    ruling_fairness,
    ruling_turn,
    seam,
    strip_quad_samples,
    template_gauge,
    template_isometry,
    template_order,
    template_outline,
)

NAMES = ["template_isometry", "template_gauge", "template_order", "ruling_fairness", "seam",
         "plane_offsets", "planarity", "lateral", "surface_closeness", "ruling_turn"]
#: Terms on the shared-outline layout (one development per strip, outline coefficients).
OUTLINE_NAMES = ["template_isometry", "template_order", "template_outline", "ruling_fairness",
                 "ruling_turn"]


def _state(layout, rng):
    m, S = layout.m, layout.S
    u = np.broadcast_to(np.linspace(0.0, 1.0, m)[None, :, None], (S, m, 1))
    A = np.concatenate([u, np.zeros_like(u) + np.arange(S)[:, None, None] * 0.4,
                        0.2 * np.sin(3 * u)], axis=-1)
    B = A + np.array([0.35, 0.05, 0.1])
    T = np.stack([np.c_[np.zeros(m), np.linspace(0, 1, m)],
                  np.c_[np.full(m, 0.4), np.linspace(0, 1, m)]], axis=1)
    if layout.outline_degree > 0:
        T = np.broadcast_to(T, (S, m, 2, 2))
        x = layout.pack(A + 0.03 * rng.standard_normal(A.shape), B, T,
                        rng.standard_normal((2, layout.outline_degree + 1)))
    else:
        x = layout.pack(A + 0.03 * rng.standard_normal(A.shape), B, T)
    return x + 0.05 * rng.standard_normal(x.size)


def _terms(layout, rng):
    k = layout.m * (layout.S - 1)
    d = rng.standard_normal((k, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    feet = rng.integers(0, layout.n_vertices - 1, k)
    steps = (rng.integers(0, layout.n_vertices, k), np.stack([feet, feet + 1], -1),
             rng.random(k), d)
    points = rng.standard_normal((layout.n_vertices, 3))
    t = rng.standard_normal((layout.n_vertices, 3))
    samples = strip_quad_samples(layout)
    frozen = FrozenReference(len(samples[0]), rng)
    return {"template_isometry": lambda x: template_isometry(x, layout),
            "template_gauge": lambda x: template_gauge(x, layout),
            "template_order": lambda x: template_order(x, layout, [0.6, 0.8], -1.0, 0.1, 0.2),
            "template_outline": lambda x: template_outline(x, layout, 0.4, 0.7),
            "ruling_turn": lambda x: ruling_turn(x, layout, 0.36),
            "ruling_fairness": lambda x: ruling_fairness(x, layout),
            "seam": lambda x: seam(x, layout, *steps),
            "plane_offsets": lambda x: plane_offsets(x, layout, samples, frozen.p, frozen.n),
            "planarity": lambda x: planarity(x, layout),
            "lateral": lambda x: lateral(x, layout, points, t),
            "surface_closeness": lambda x: surface_closeness(x, layout, frozen, samples)}


@pytest.mark.parametrize("name", NAMES)
def test_jacobian_matches_finite_differences(name):
    rng = np.random.default_rng(3)
    layout = StripSetLayout(4, 3)
    x = _state(layout, rng)
    assert_jacobian_matches_finite_differences(_terms(layout, rng)[name], x, layout.size)


@pytest.mark.parametrize("name", OUTLINE_NAMES)
def test_jacobian_matches_finite_differences_shared_outline(name):
    rng = np.random.default_rng(4)
    layout = StripSetLayout(5, 3, outline_degree=4)
    x = _state(layout, rng)
    assert_jacobian_matches_finite_differences(_terms(layout, rng)[name], x, layout.size)


@pytest.mark.parametrize("name", NAMES)
def test_jacobian_pattern_does_not_depend_on_values(name):
    rng = np.random.default_rng(5)
    layout = StripSetLayout(4, 2)
    term = _terms(layout, rng)[name]
    _, J1 = term(_state(layout, rng))
    _, J2 = term(_state(layout, rng))
    assert np.array_equal(J1.row, J2.row) and np.array_equal(J1.col, J2.col)


def test_template_isometry_vanishes_on_congruent_strips_only():
    """Two strips that are rigid motions of the template quads (one of them bent about a
    ruling) have zero residuals; a stretched quad does not."""
    layout = StripSetLayout(3, 2)
    T = np.array([[[0.0, 0.0], [1.0, 0.0]], [[0.1, 2.0], [1.1, 2.1]], [[0.0, 4.0], [1.2, 4.0]]])
    flat = np.concatenate([T, np.zeros((3, 2, 1))], axis=-1)
    A0, B0 = flat[:, 0], flat[:, 1]
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    A1, B1 = A0 @ R.T + [5.0, 1.0, 2.0], B0 @ R.T + [5.0, 1.0, 2.0]
    phi, _ = template_isometry(layout.pack(np.stack([A0, A1]), np.stack([B0, B1]), T), layout)
    assert np.abs(phi).max() <= 1e-12
    B1[2] += [0.0, 0.3, 0.0]
    phi, _ = template_isometry(layout.pack(np.stack([A0, A1]), np.stack([B0, B1]), T), layout)
    assert np.abs(phi).max() > 0.1


def test_template_outline_vanishes_on_developments_on_the_outline_only():
    """Developments whose boundary vertices lie on the outline curves and share the end
    vertices have zero residuals; a vertex moved off its curve, or a strip whose end differs,
    does not."""
    from numpy.polynomial import chebyshev

    m, S, d = 5, 3, 3
    layout = StripSetLayout(m, S, outline_degree=d)
    c = np.array([[0.0, 0.1, 0.02, 0.0], [1.0, -0.05, 0.0, 0.01]])
    y0, h = -2.0, 2.5
    rng = np.random.default_rng(0)
    T = np.empty((S, m, 2, 2))
    for s_ in range(S):
        y = np.linspace(0.0, -4.0, m)
        y[1:-1] += rng.uniform(-0.3, 0.3, m - 2)        # each strip its own rulings
        for j in (0, 1):
            T[s_, :, j, 1] = y
            T[s_, :, j, 0] = chebyshev.chebval((y - y0) / h, c[j])
    A = np.zeros((S, m, 3))
    x = layout.pack(A, A, T, c)
    phi, _ = template_outline(x, layout, y0, h)
    assert np.abs(phi).max() <= 1e-12
    T2 = T.copy()
    T2[1, 2, 0, 0] += 0.01
    assert np.abs(template_outline(layout.pack(A, A, T2, c), layout, y0, h)[0]).max() > 0.009
    T3 = T.copy()
    T3[2, -1, 1, 1] -= 0.1                                # end vertex slides along its curve
    T3[2, -1, 1, 0] = chebyshev.chebval((T3[2, -1, 1, 1] - y0) / h, c[1])
    phi3 = template_outline(layout.pack(A, A, T3, c), layout, y0, h)[0]
    assert np.abs(phi3[: S * m * 2]).max() <= 1e-12 and np.abs(phi3).max() > 0.09


def test_ruling_turn_holds_for_rulings_within_the_angle_only():
    """With the slack σ² taken by the residual's value, the term vanishes for rulings that turn
    by less than θ and not for a pair turning by more (whatever the sense) or reversing."""
    layout = StripSetLayout(3, 1)
    tan_max = np.tan(np.radians(20.0))

    def worst(angles):
        r = np.stack([np.cos(np.radians(angles)), np.sin(np.radians(angles))], -1)
        T = np.stack([np.zeros((3, 2)), r], axis=1)
        x = layout.pack(np.zeros((1, 3, 3)), np.zeros((1, 3, 3)), T)
        g, _ = ruling_turn(x, layout, tan_max)
        x[layout.turn_offset:] = np.sqrt(np.maximum(g, 0.0))
        return np.abs(ruling_turn(x, layout, tan_max)[0]).max()

    assert worst([0.0, 19.0, 0.0]) <= 1e-12
    assert worst([0.0, 21.0, 42.0]) > 1e-3
    assert worst([0.0, -25.0, -20.0]) > 1e-3
    assert worst([0.0, 180.0, 180.0]) > 1e-3


def test_seam_residuals_are_the_seam_steps_at_their_feet():
    """Two strips whose shared geodesic's copies lie apart (B of strip 0 lifted along z, its
    vertices slid half a row): the residuals at the feet of each copy on the other, along the
    normal, are the seam steps that the fabrication metrics measure; zero for copies that
    coincide."""
    from dgpc_cli.strips.fabrication import seam_offsets
    from dgpc_cli.strips.template import closest_on_polylines

    m = 6
    u = np.linspace(0.0, 1.0, m)
    g = np.c_[u, np.zeros(m), 0.3 * u ** 2]                      # the shared geodesic, curved
    layout = StripSetLayout(m, 2)
    A = np.stack([g - [0.0, 0.4, 0.0], g])
    B = np.stack([g, g + [0.0, 0.4, 0.0]])
    x0 = layout.pack(A, B, np.zeros((m, 2, 2)))
    lifted = B.copy()
    lifted[0, 1:-1] = 0.5 * (g[1:-1] + g[2:]) + [0.0, 0.0, 0.02]  # slid and lifted
    x1 = layout.pack(A, lifted, np.zeros((m, 2, 2)))
    normal = np.array([0.0, 0.0, 1.0])
    for x, (X, Y) in ((x0, (B[0], A[1])), (x1, (lifted[0], A[1]))):
        t = closest_on_polylines(X[None], Y[None])[2][0]
        i = np.clip(np.floor(t).astype(int), 0, m - 2)
        ids, ends = layout.vid[:, 1], np.stack([layout.vid[i, 2], layout.vid[i + 1, 2]], -1)
        phi, _ = seam(x, layout, ids, ends, t - i, np.tile(normal, (m, 1)))
        step, _ = seam_offsets(X, Y, np.tile(normal, (m, 1)))
        assert np.abs(phi) == pytest.approx(step, abs=1e-12)
    assert np.abs(phi).max() > 0.01                              # the lift (less the tilt)
