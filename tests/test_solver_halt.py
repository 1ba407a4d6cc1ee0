"""The solver's ``halt`` hook: a caller that would reject where a run is heading ends it early."""

import numpy as np
from scipy import sparse

from dgpc_cli.core.solver import Schedule, guided_projection
from dgpc_cli.core.solver.guided_projection import Term


def _square_root_of_4(x):
    """φ(x) = x² − 4 per component, J = diag(2x): Newton from 1 runs 1 → 2.5 → 2.05 → … → 2."""
    return x * x - 4.0, sparse.coo_matrix(sparse.diags(2.0 * x))


TERMS = [Term("root", _square_root_of_4, Schedule.constant(1.0))]


def test_without_halt_the_run_converges_to_the_root():
    result = guided_projection(np.ones(2), TERMS, tol=1e-12, max_iter=50)
    assert result.status == "converged"
    np.testing.assert_allclose(result.x, 2.0, atol=1e-12)
    assert result.iterations >= 4


def test_halt_ends_the_run_at_the_first_point_it_refuses():
    seen = []

    def halt(x):
        seen.append(x.copy())
        return "overshot 2.2" if x[0] > 2.2 else None

    result = guided_projection(np.ones(2), TERMS, tol=1e-12, max_iter=50, halt=halt)
    assert result.status == "halted" and result.message == "overshot 2.2"
    assert result.iterations == 1
    np.testing.assert_allclose(result.x, 2.5, rtol=1e-5)   # the refused point, not x0
    assert len(seen) == 1 and seen[0][0] > 2.2             # never asked about the start
    assert not result.success


def test_halt_that_never_objects_changes_nothing():
    plain = guided_projection(np.ones(2), TERMS, tol=1e-12, max_iter=50)
    calls = []
    watched = guided_projection(np.ones(2), TERMS, tol=1e-12, max_iter=50,
                                halt=lambda x: calls.append(x.copy()))
    assert watched.status == plain.status and watched.iterations == plain.iterations
    np.testing.assert_array_equal(watched.x, plain.x)
    assert 0 < len(calls) < plain.iterations              # the converged point is not asked
