"""Where a planar strip's rulings cross (a folded quad), in its (t, s) parameters: a trimmed
part is refused only where the fold lies inside it, not where the outline cuts the fold away
(a net made finer for a largest strip width crossed its rulings only beyond a patch's
outline)."""

import numpy as np
import pytest

from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.soundness import require_sound_strips
from dgpc_cli.strips.crossing import backward, folded_inside, folds


def _strip():
    """A flat strip 5 quads long, 1 wide: side A runs back between rows 2 and 3 (A_3 at
    x = 1.8), so rulings 2 and 3 meet at s = 1/6 on ruling 2."""
    k = np.arange(6.0)
    P = np.stack([k, np.zeros(6), np.zeros(6)], 1)
    Q = P + [0.0, 1.0, 0.0]
    A, B = P.copy(), Q.copy()
    A[3, 0] = 1.8
    return A, B, P, Q


def test_the_fold_is_the_triangle_between_the_backward_side_and_where_the_rulings_meet():
    A, B, P, Q = _strip()
    assert backward(A, P).tolist() == [False, False, True, False, False]
    assert not backward(B, Q).any()
    [(row, s0, s1)] = folds(A, B, P, Q)
    assert (row, s0) == (2, 0.0) and s1 == pytest.approx(1 / 6)
    assert folds(P, Q, P, Q).shape == (0, 3)


def test_a_part_is_folded_only_where_it_covers_the_fold():
    A, B, P, Q = _strip()
    whole = [(0, 0), (5, 0), (5, 1), (0, 1)]
    assert folded_inside(A, B, P, Q, [whole])
    # the outline cuts the strip along s = 0.5 there, or ends at row 2: the fold is cut away
    assert not folded_inside(A, B, P, Q, [[(0, 0.5), (5, 0.5), (5, 1), (0, 1)]])
    assert not folded_inside(A, B, P, Q, [[(0, 0), (2, 0), (2, 1), (0, 1)]])
    # a part that reaches into the fold's corner
    assert folded_inside(A, B, P, Q, [[(0, 0.5), (2.5, 0.05), (5, 0.5), (5, 1), (0, 1)]])


def test_without_the_net_the_fold_is_found_against_the_middle_line():
    A, B, _, _ = _strip()
    [(row, s0, s1)] = folds(A, B)
    assert (row, s0) == (2, 0.0) and s1 == pytest.approx(1 / 6)


def test_unfold_refuses_a_trimmed_strip_only_where_a_part_covers_its_fold():
    """``unfold``'s gate: the fold's rows lie in the part's row span either way; refused only
    where the part's outline covers the fold."""
    A, B, _, _ = _strip()
    span = [[[0, 5]]]
    with pytest.raises(DgpcError, match="S-v00 is folded"):
        require_sound_strips([(A, B)], ["S-v00"], "s.json", span,
                             [[[(0, 0), (5, 0), (5, 1), (0, 1)]]])
    require_sound_strips([(A, B)], ["S-v00"], "s.json", span,
                         [[[(0, 0.5), (5, 0.5), (5, 1), (0, 1)]]])
