"""Planarity, closeness and anchor terms of the strip polish: Jacobians against finite
differences, fixed patterns, and what their residuals measure."""

import numpy as np
import pytest
from jacobian_check import assert_jacobian_matches_finite_differences

from dgpc_cli.core.constraints.planarity import QuadGridLayout, anchor, closeness, planarity


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
    return {"planarity": lambda x: planarity(x, layout),
            "closeness": lambda x: closeness(x, layout, points, t),
            "anchor": lambda x: anchor(x, layout, points)}


@pytest.mark.parametrize("name", ["planarity", "closeness", "anchor"])
def test_jacobian_matches_finite_differences(name):
    rng = np.random.default_rng(11)
    layout = QuadGridLayout(5, 3)
    term = _terms(layout, rng)[name]
    x = _state(layout, rng)
    assert_jacobian_matches_finite_differences(term, x, layout.size)


@pytest.mark.parametrize("name", ["planarity", "closeness", "anchor"])
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


def test_closeness_allows_sliding_along_the_line_only():
    layout = QuadGridLayout(2, 2)
    points = np.zeros((2, 2, 3))
    t = np.broadcast_to([1.0, 0.0, 0.0], (2, 2, 3))
    slid = points + np.array([0.3, 0.0, 0.0])
    off = points + np.array([0.0, 0.2, 0.0])
    assert np.abs(closeness(layout.pack(slid), layout, points, t)[0]).max() == 0.0
    assert np.allclose(np.abs(closeness(layout.pack(off), layout, points, t)[0]).max(), 0.2)
