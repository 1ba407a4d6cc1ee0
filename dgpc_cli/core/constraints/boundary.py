"""Closeness of the net's boundary to the reference's boundary (a companion of §5.1).

The approximation term lets vertices slide along the reference, so nothing keeps a fitted net
covering it: under the developability or gpc conditions its boundary creeps inwards. Net
boundary vertices that start on the reference's boundary curve keep to it instead.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def boundary(x, layout, reference, vertex_ids):
    """Residuals ``(I − t tᵀ)(f_i − b_i)`` (3 per vertex) for the vertices ``vertex_ids``:
    b_i the closest point of the reference's boundary (``reference.closest_on_boundary(points)
    -> (b, t)``, recomputed at every x, held fixed in the Jacobian) and t the boundary's unit
    tangent there. A vertex may slide along the boundary curve but not leave it."""
    f, _, _ = layout.split(x)
    vertex_ids = np.asarray(vertex_ids)
    q = f[vertex_ids]
    b, t = reference.closest_on_boundary(q)
    P = np.eye(3)[None] - t[:, :, None] * t[:, None, :]                     # (k, 3, 3)
    phi = np.einsum("kij,kj->ki", P, q - b).ravel()
    rows = np.arange(phi.size).reshape(-1, 3, 1)
    cols = layout.f_cols(vertex_ids)[:, None, :]
    return phi, jacobian(phi.size, layout.size, (rows, cols, P))
