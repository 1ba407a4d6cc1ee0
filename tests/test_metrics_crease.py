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
