"""The finite-difference check every constraint term's Jacobian passes (SPEC §4)."""

import numpy as np


def assert_jacobian_matches_finite_differences(term, x, size, h=1e-6, rtol=1e-7):
    """``term(x) -> (phi, J)``: J (sparse, shape (len(phi), size)) equals central differences
    of phi within ``rtol`` of its largest entry, and is not identically zero."""
    phi, J = term(x)
    assert J.shape == (phi.size, size)
    J = J.toarray()
    fd = np.empty_like(J)
    for c in range(size):
        dx = np.zeros(size)
        dx[c] = h
        fd[:, c] = (term(x + dx)[0] - term(x - dx)[0]) / (2 * h)
    assert np.abs(J - fd).max() <= rtol * max(1.0, np.abs(J).max())
    assert np.abs(J).max() > 0, "the Jacobian is identically zero"
