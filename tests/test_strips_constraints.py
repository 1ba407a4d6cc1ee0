"""Planarity, lateral, slide-fairness, surface-closeness and anchor terms of the strip polish:
Jacobians against finite differences, fixed patterns, and what their residuals measure."""

import numpy as np
import pytest
from jacobian_check import FrozenReference, assert_jacobian_matches_finite_differences

from dgpc_cli.core.constraints.planarity import (
    QuadGridLayout,
    anchor,
    lateral,
    planarity,
    quad_samples,
    slide_fairness,
    surface_closeness,
)
from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.strips.quality import bilinear_samples

NAMES = ["planarity", "lateral", "surface_closeness", "anchor", "slide_fairness"]


def _state(layout, rng):
    u, v = np.meshgrid(np.linspace(0, 1, layout.m), np.linspace(0, 0.4, layout.k), indexing="ij")
    p = np.stack([u, v, 0.2 * np.sin(3 * u + v)], axis=-1) + 0.03 * rng.standard_normal(
        (layout.m, layout.k, 3))
    x = layout.pack(p)
    return x + 0.05 * rng.standard_normal(x.size)


def _terms(layout, rng):
    points = rng.standard_normal((layout.m, layout.k, 3))
    t = rng.standard_normal((layout.m, layout.k, 3))
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    samples = quad_samples(layout)
    frozen = FrozenReference(len(samples[0]), rng)
    ids = np.r_[np.arange(layout.n_vertices), 0, 1]
    return {"planarity": lambda x: planarity(x, layout),
            "lateral": lambda x: lateral(x, layout, points.reshape(-1, 3)[ids],
                                         t.reshape(-1, 3)[ids], ids),
            "surface_closeness": lambda x: surface_closeness(x, layout, frozen, samples),
            "anchor": lambda x: anchor(x, layout, points),
            "slide_fairness": lambda x: slide_fairness(x, layout, points, t)}


@pytest.mark.parametrize("name", NAMES)
def test_jacobian_matches_finite_differences(name):
    rng = np.random.default_rng(11)
    layout = QuadGridLayout(5, 3)
    term = _terms(layout, rng)[name]
    x = _state(layout, rng)
    assert_jacobian_matches_finite_differences(term, x, layout.size)


@pytest.mark.parametrize("name", NAMES)
def test_jacobian_pattern_does_not_depend_on_values(name):
    rng = np.random.default_rng(5)
    layout = QuadGridLayout(4, 2)
    term = _terms(layout, rng)[name]
    _, J1 = term(_state(layout, rng))
    _, J2 = term(np.full(layout.size, 1e-3))
    assert np.array_equal(J1.row, J2.row) and np.array_equal(J1.col, J2.col)


def test_planarity_vanishes_exactly_on_planar_quads_only():
    layout = QuadGridLayout(4, 2)
    u, v = np.meshgrid(np.arange(4.0), np.array([0.0, 0.7]), indexing="ij")
    flat = np.stack([u, v, 0.3 * u + 0.1 * v], axis=-1)      # a plane
    phi, _ = planarity(layout.pack(flat), layout)
    assert np.abs(phi).max() < 1e-14
    bent = flat.copy()
    bent[2, 1, 2] += 0.05                                      # lift one vertex off the plane
    phi, _ = planarity(layout.pack(bent), layout)
    assert np.abs(phi).max() > 1e-3


def test_lateral_lets_a_vertex_slide_and_lift_but_not_cross():
    layout = QuadGridLayout(2, 2)
    points = np.zeros((4, 3))
    b = np.broadcast_to([0.0, 1.0, 0.0], (4, 3))              # across the geodesic (along x)
    along_and_up = layout.pack(np.zeros((2, 2, 3)) + np.array([0.3, 0.0, 0.2]))
    across = layout.pack(np.zeros((2, 2, 3)) + np.array([0.0, 0.2, 0.0]))
    assert np.abs(lateral(along_and_up, layout, points, b)[0]).max() == 0.0
    assert np.allclose(lateral(across, layout, points, b)[0], 0.2)


def test_quad_samples_are_the_three_by_three_patch_samples():
    layout = QuadGridLayout(4, 2)
    rng = np.random.default_rng(2)
    p = rng.standard_normal((4, 2, 3))
    ids, coefficients = quad_samples(layout)
    s = np.einsum("kc,kcj->kj", coefficients, p.reshape(-1, 3)[ids])
    assert np.allclose(coefficients.sum(axis=1), 1.0)
    want = np.unique(np.round(bilinear_samples(p[:, 0], p[:, 1], 3), 12), axis=0)
    assert np.array_equal(np.unique(np.round(s, 12), axis=0), want)
    assert len(s) == len(want)                                 # each sample taken once


def test_surface_closeness_is_the_signed_distance_to_the_surface():
    layout = QuadGridLayout(3, 2)
    plane = ReferenceSurface(np.array([[-5.0, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]),
                             np.array([[0, 1, 2], [0, 2, 3]]))
    u, v = np.meshgrid(np.arange(3.0), [0.0, 1.0], indexing="ij")
    grid = np.stack([u, v, np.zeros_like(u)], axis=-1)
    phi, _ = surface_closeness(layout.pack(grid), layout, plane, quad_samples(layout))
    assert np.abs(phi).max() == 0.0
    grid[1, 1, 2] = 0.4                                        # lift one vertex
    phi, _ = surface_closeness(layout.pack(grid), layout, plane, quad_samples(layout))
    assert np.isclose(phi.max(), 0.4) and np.isclose(np.sort(phi)[-2], 0.2)
    assert phi.min() == 0.0


def test_slide_fairness_allows_a_common_shift_but_not_a_zigzag():
    layout = QuadGridLayout(6, 2)
    u, v = np.meshgrid(np.arange(6.0), np.array([0.0, 0.5]), indexing="ij")
    start = np.stack([u, v, np.zeros_like(u)], axis=-1)
    t = np.broadcast_to([1.0, 0.0, 0.0], start.shape)
    shifted = start + [0.3, 0.0, 0.0]
    assert np.abs(slide_fairness(layout.pack(shifted), layout, start, t)[0]).max() < 1e-14
    zigzag = start.copy()
    zigzag[1::2, :, 0] += 0.4                                  # every other ruling moved on
    phi, _ = slide_fairness(layout.pack(zigzag), layout, start, t)
    assert np.allclose(np.abs(phi), 0.8)
