"""The strips' "width" figure of `dgpc report` shows the width across the strip, not the
length of its slanted rulings (which it showed under that name)."""

import numpy as np
import pytest

from dgpc_cli.report.strips import quad_widths


def test_a_slanted_ruling_does_not_widen_the_strip():
    """A strip 2 wide whose rulings lean by 5 along it (rulings √29 long), then a quad
    widening from 2 to 4: its area (shoelace) over its mean length along the strip."""
    A = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]])
    B = np.array([[5.0, 2.0, 0.0], [15.0, 2.0, 0.0], [25.0, 4.0, 0.0]])
    widths = quad_widths(np.stack([A, B], axis=1))
    assert widths.shape == (2, 1)
    assert widths[0, 0] == pytest.approx(2.0)
    ruling = np.linalg.norm(B[0] - A[0])
    assert ruling == pytest.approx(np.sqrt(29.0)) and widths[0, 0] < ruling
    quad = np.array([A[1], A[2], B[2], B[1]])[:, :2]
    x, y = quad[:, 0], quad[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    along = 0.5 * (10.0 + np.sqrt(104.0))
    assert area == pytest.approx(25.0)
    assert widths[1, 0] == pytest.approx(area / along)


def test_a_strip_in_space_keeps_its_width_whatever_its_orientation():
    rng = np.random.default_rng(0)
    Q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    A = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
    B = A + [0.0, 0.5, 0.0]
    widths = quad_widths(np.stack([A @ Q.T, B @ Q.T], axis=1))
    assert widths[0, 0] == pytest.approx(0.5)
