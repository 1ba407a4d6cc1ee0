"""The crease guard of a drag: zero while a row's third differences stay within a margin of the
start net's, the excess past it otherwise (and its Jacobian on both sides of the margin)."""

import numpy as np
import pytest
from jacobian_check import assert_jacobian_matches_finite_differences

from dgpc_cli.core.constraints.crease_guard import CREASE_MARGIN, CREASE_RATIO, crease_guard
from dgpc_cli.core.layout import NetLayout
from dgpc_cli.metrics.crease import CREASE_LIMIT


def circle_rows(m=4, n=12, radius=4.0, span=1.5):
    """Rows on circles of ``radius``, one per height 0, 1, 2 …: their third differences are
    8 sin³(θ/2)·r along every row, θ the angle between neighbours."""
    t = np.linspace(0.0, span, n)
    row = np.stack([radius * np.cos(t), radius * np.sin(t), np.zeros(n)], axis=-1)
    return np.stack([row + [0.0, 0.0, 1.0 * k] for k in range(m)])


def row_third_differences(g):
    """‖d₃‖ of every run of four vertices along the rows of ``g (m, n, 3)``, ``(m, n − 3)``."""
    return np.linalg.norm(g[:, 3:] - 3 * g[:, 2:-1] + 3 * g[:, 1:-2] - g[:, :-3], axis=-1)


def test_the_margin_leaves_the_crease_the_metrics_flag_unreached():
    assert 0 < CREASE_MARGIN < CREASE_LIMIT


def test_a_smooth_drag_is_free_and_a_kink_pays_its_excess():
    """A rigid motion and a scaling by 1 % keep every run within the margin (residual 0);
    a vertex pushed by 0.2 along the normal grows the third differences of the three runs it
    belongs to by 3 × 0.2 (the middle ones) and 1 × 0.2: their residuals are that growth
    less the margin, the other rows' residuals stay 0."""
    f0 = circle_rows()
    layout = NetLayout(*f0.shape[:2])
    c, s = np.cos(0.3), np.sin(0.3)
    moved = 1.01 * f0 @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + [1.0, 2.0, 3.0]
    phi, _ = crease_guard(layout.pack(moved), layout, f0)
    assert phi.shape == (4 * 9,) and np.all(phi == 0.0)

    kinked = f0.copy()
    kinked[1, 6, :2] *= 1 - 0.2 / 4.0          # 0.2 towards the axis
    phi, _ = crease_guard(layout.pack(kinked), layout, f0)
    phi = phi.reshape(4, 9)
    growth = row_third_differences(kinked) - row_third_differences(f0)
    assert np.all(phi[[0, 2, 3]] == 0.0)
    assert phi[1] == pytest.approx(np.maximum(growth[1] - CREASE_MARGIN, 0.0), abs=1e-12)
    # the runs v = 3 … 6 (weight 1 on the kink) to v = 6 … 9: the middle two carry it thrice
    # (within the rows' own third difference, 0.01, which the push does not quite align with)
    assert phi[1, [4, 5]] == pytest.approx(3 * 0.2 - CREASE_MARGIN, abs=0.02)
    assert phi[1, [3, 6]] == pytest.approx(0.2 - CREASE_MARGIN, abs=0.02)
    assert np.all(phi[1, [0, 1, 2, 7, 8]] == 0.0)


def test_a_coarse_row_may_bend_by_a_multiple_of_its_own_third_difference():
    """Five vertices over 3 rad (0.75 rad apart): each row's third difference is 1.6 on its
    own. The middle vertex pushed out by 0.3 (growth 0.51, above the margin) is free, within
    twice that; pushed out by 2.0 (growth 5.2) it pays the excess."""
    f0 = circle_rows(m=2, n=5, span=3.0)
    layout = NetLayout(2, 5)
    own = row_third_differences(f0)
    assert own == pytest.approx(8 * np.sin(0.375) ** 3 * 4.0, rel=1e-9)
    for push, paid in ((0.3, False), (2.0, True)):
        moved = f0.copy()
        moved[0, 2, :2] *= 1 + push / 4.0
        phi, _ = crease_guard(layout.pack(moved), layout, f0)
        growth = row_third_differences(moved)[0] - own[0]
        assert growth.max() > CREASE_MARGIN
        assert phi[:2] == pytest.approx(np.maximum(growth - CREASE_RATIO * own[0], 0.0),
                                        abs=1e-12)
        assert (phi.max() > 0) == paid


def test_its_jacobian_matches_finite_differences_where_it_acts():
    f0 = circle_rows()
    layout = NetLayout(*f0.shape[:2])
    kinked = f0.copy()
    kinked[2, 5, :2] *= 0.9
    x = layout.pack(kinked)
    phi, J = crease_guard(x, layout, f0)
    assert 0 < np.count_nonzero(phi) < phi.size
    assert_jacobian_matches_finite_differences(lambda y: crease_guard(y, layout, f0), x,
                                               layout.size)
