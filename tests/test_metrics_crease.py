"""The crease measure: third differences across the geodesics along the rows, in mean edges."""

import numpy as np
import pytest

from dgpc_cli.metrics.crease import crease
from dgpc_cli.metrics.summary import net_metrics


def circle_rows(m=5, n=21, radius=3.0, span=2.0):
    """Rows on circles of ``radius`` (one per height), ``n`` vertices over ``span`` radians."""
    t = np.linspace(0.0, span, n)
    row = np.stack([radius * np.cos(t), radius * np.sin(t), np.zeros(n)], axis=-1)
    return np.stack([row + [0.0, 0.0, 0.5 * k] for k in range(m)])


def test_a_flat_grid_and_an_affine_image_have_no_crease():
    u, v = np.meshgrid(np.arange(6.0), np.arange(9.0), indexing="ij")
    f = np.stack([u, v, 0.0 * u], axis=-1)
    A = np.array([[1.0, 0.3, 0.1], [0.0, 1.2, -0.4], [0.2, 0.0, 0.9]])
    assert crease(f).shape == (6, 6)
    assert crease(f).max() == 0.0 and crease(f @ A.T).max() <= 1e-12


def test_a_circle_reads_its_third_difference_and_a_kink_stands_out():
    """On a circle the third difference of chords of angle θ is 8 sin³(θ/2) · r, about θ² in
    units of the chord; a vertex pushed by 0.2 edges along the normal reads ≈ 3 × 0.2 next to
    it (the stencil's weight 3), and nothing more than 1 × 0.2 three vertices away."""
    f = circle_rows()
    theta = 2.0 / 20
    c = crease(f)
    chord = 2 * 3.0 * np.sin(theta / 2)
    # the mean edge mixes the chords with the rows' spacing 0.5
    mean = (4 * 21 * 0.5 + 5 * 20 * chord) / (4 * 21 + 5 * 20)
    assert c == pytest.approx(8 * np.sin(theta / 2) ** 3 * 3.0 / mean, rel=1e-9)
    kinked = f.copy()
    kinked[2, 10, :2] *= 1 - 0.2 * mean / 3.0
    k = crease(kinked)
    assert k[2, 8] == pytest.approx(3 * 0.2, rel=0.05)
    assert k[2].max() >= 10 * c.max()
    assert np.allclose(k[[0, 1, 3, 4]], crease(f)[[0, 1, 3, 4]], rtol=1e-2)


def test_short_rows_have_no_crease_and_the_metrics_record_it():
    assert crease(np.zeros((4, 3, 3))).shape == (4, 0)
    m = net_metrics(circle_rows())
    assert m["crease_max"] == pytest.approx(crease(circle_rows()).max())


def smoothest_push(term, m=17, n=17):
    """The flat m×n grid with its rim held and its middle vertex pushed out of the plane
    by one edge: the displacement of least ``term`` energy (a linear least-squares problem in
    the free vertices' heights, the term's own Jacobian). Returns the pushed net."""
    from scipy.sparse.linalg import lsqr

    from dgpc_cli.core.layout import NetLayout

    layout = NetLayout(m, n)
    u, v = np.meshgrid(np.arange(float(m)), np.arange(float(n)), indexing="ij")
    f0 = np.stack([u, v, 0.0 * u], axis=-1).reshape(-1, 3)
    _, J = term(layout.pack(f0), layout, f0)
    z = J.tocsc()[:, layout.f_cols(np.arange(m * n))[:, 2]]   # heights only
    held = np.zeros((m, n), bool)
    held[[0, -1]] = held[:, [0, -1]] = held[m // 2, n // 2] = True
    held = held.ravel()
    h = np.zeros(m * n)
    h[(m // 2) * n + n // 2] = 1.0
    h[~held] = lsqr(z[:, ~held], -(z[:, held] @ h[held]), atol=1e-14, btol=1e-14)[0]
    f = f0.copy()
    f[:, 2] = h
    return f.reshape(m, n, 3)


def test_third_differences_of_the_displacement_spread_a_push_that_second_ones_crease():
    """Second differences of the displacement are a discrete thin plate: its answer to a held,
    pushed vertex peaks sharply there (curvature ∝ log r: 0.043 mean edges at the push, 0.003
    at the rim); third differences spread it over the whole grid (here the biquadratic bubble
    u(m−1−u)·v(n−1−v), whose third differences along u and v vanish)."""
    from dgpc_cli.core.constraints import displacement_fairness, displacement_smoothness

    plate = crease(smoothest_push(displacement_fairness))
    smooth = crease(smoothest_push(displacement_smoothness))
    assert plate.max() >= 0.04 and smooth.max() <= 1e-9
    assert plate.max() == pytest.approx(plate[8, 6:8].max())         # at the push
