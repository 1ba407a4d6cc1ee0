"""The directions of a reference mesh's longest extents, for ``init``'s search of base curves
(SPEC §5): a roof over an apse is about as wide as long and its principal axes tilt with its
height, so neither the principal axes nor a sweep about them names its spine; the sides of the
box of least volume around it do (a 40 × 39 × 13.5 m roof: its 40 m side runs along the
spine, horizontal).
"""

from __future__ import annotations

import numpy as np

#: The box is fitted to at most this many vertices of the convex hull (evenly picked by index):
#: its extents move by well under a percent, and the search of the box stays fast on hulls of
#: thousands of facets.
HULL_POINTS = 400


def extent_axes(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The sides of the oriented bounding box of least volume around ``vertices (k, 3)``
    (``trimesh.bounds.oriented_bounds`` on their convex hull): unit axes ``(3, 3)`` as
    columns, longest side first, each signed so that its largest component is positive, and
    the box's extents ``(3,)`` in the same order. A flat mesh (no hull of volume): the
    rectangle of least area in its plane (``oriented_bounds_2D``), and its normal."""
    from scipy.spatial import ConvexHull, QhullError
    from trimesh.bounds import oriented_bounds, oriented_bounds_2D

    V = np.asarray(vertices, float)
    try:
        ids = np.sort(ConvexHull(V).vertices)
    except QhullError:
        centred = V - V.mean(axis=0)
        plane = np.linalg.svd(centred, full_matrices=False)[2]        # rows: in-plane, normal
        transform, extents = oriented_bounds_2D(centred @ plane[:2].T)
        rows = np.asarray(transform)[:2, :2] @ plane[:2]
        rotation = np.vstack([rows, plane[2]])
        extents = np.append(np.asarray(extents, float), 0.0)
    else:
        ids = ids[np.unique(np.linspace(0, len(ids) - 1,
                                        min(len(ids), HULL_POINTS)).astype(int))]
        transform, extents = oriented_bounds(V[ids])
        rotation = np.asarray(transform)[:3, :3]      # rows: the box's axes
    order = np.argsort(-np.asarray(extents), kind="stable")
    axes = rotation[order].T
    k = np.argmax(np.abs(axes), axis=0)
    axes = axes * np.sign(axes[k, np.arange(3)])
    return axes, np.asarray(extents, float)[order]
