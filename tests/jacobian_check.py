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


class FrozenReference:
    """Fixed closest points and normals (or boundary tangents) for ``k`` query points, whatever
    the query: the approximation-type terms hold them fixed in their Jacobians."""

    def __init__(self, k, rng):
        n = rng.standard_normal((k, 3))
        self.n = n / np.linalg.norm(n, axis=1, keepdims=True)
        self.p = rng.standard_normal((k, 3))

    def closest(self, q):
        return self.p[: len(q)], self.n[: len(q)]

    def closest_on_boundary(self, q):
        return self.p[: len(q)], self.n[: len(q)]
