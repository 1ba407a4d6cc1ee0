"""How much of the reference surface a net covers, and how close its vertices lie to it
(SPEC §7; issue: "the fraction of the reference's area that the net covers").

The reference is sampled evenly: every triangle is cut into ``k²`` congruent sub-triangles
(regular subdivision), each sample the centroid of one, weighted by its area. A sample counts
as covered when its closest point on the triangulated net (libigl AABB, one vectorized query)
is not on the net's boundary — a point beyond the net's edge projects onto that edge — and it
is no farther from the net than a geometric tolerance, a length the user can set (by default
:data:`TOLERANCE_OF_DIAGONAL` of the reference's bounding-box diagonal), beyond the chord height
of the net's own quad there: a net of straight edges on a curved reference lies inside it by up to
``(|δ_uu f| + 2|δ_uv f| + |δ_vv f|) / 8`` (the interpolation error of its facets, from the net's
second differences, :func:`chord_height`). (A bound of one mean net edge, as before, counted
reference area metres away from a coarse net as covered.)
"""

from __future__ import annotations

import math

import numpy as np

from dgpc_cli.metrics.frames import as_grid
from dgpc_cli.metrics.hausdorff import net_triangles

__all__ = ["chord_height", "coverage", "covered_faces", "default_tolerance",
           "subdivision_samples"]

#: Samples aimed at on the reference.
DEFAULT_SAMPLES = 60_000
#: The default coverage tolerance, as a fraction of the reference's bounding-box diagonal.
TOLERANCE_OF_DIAGONAL = 2e-3
#: Barycentric coordinate below which a closest point counts as on a net boundary edge.
ON_EDGE = 1e-9


def subdivision_samples(vertices, faces, target: int = DEFAULT_SAMPLES):
    """Centroids ``(t·k², 3)`` of the ``k²`` sub-triangles of every face and their areas
    ``(t·k²,)``, ``k = clip(round(√(target/t)), 1, 16)``."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    k = int(min(16, max(1, round(math.sqrt(target / max(len(F), 1))))))
    i, j = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
    up = (i + j) <= k - 1                                   # upright sub-triangles
    ui, uj = i[up], j[up]
    dn = (i + j) <= k - 2                                   # upside-down ones
    di, dj = i[dn], j[dn]
    bary = np.concatenate([np.stack([ui + 1 / 3, uj + 1 / 3], 1),
                           np.stack([di + 2 / 3, dj + 2 / 3], 1)]) / k      # (k², 2)
    bary = np.column_stack([1 - bary.sum(1), bary])
    tri = V[F]
    pts = np.einsum("sk,fkd->fsd", bary, tri).reshape(-1, 3)
    from trimesh.triangles import area as triangle_areas

    area = triangle_areas(tri)
    return pts, np.repeat(area / k**2, len(bary))


def _boundary_edge_mask(m: int, n: int) -> np.ndarray:
    """For the faces of :func:`net_triangles`: ``(2(m-1)(n-1), 3)`` True where the edge
    opposite corner c (c = 0, 1, 2) lies on the net's boundary."""
    u, v = np.meshgrid(np.arange(m - 1), np.arange(n - 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    # lower triangle a=(u,v), b=(u+1,v), c=(u+1,v+1): edges bc (opp a), ca (diagonal), ab
    low = np.stack([u + 1 == m - 1, np.zeros_like(u, bool), v == 0], 1)
    # upper triangle a=(u,v), c=(u+1,v+1), d=(u,v+1): edges cd (opp a), da (opp c), ac
    upp = np.stack([v + 1 == n - 1, u == 0, np.zeros_like(u, bool)], 1)
    return np.concatenate([low, upp])


def default_tolerance(ref_vertices) -> float:
    """The coverage tolerance without one given: :data:`TOLERANCE_OF_DIAGONAL` of the
    reference's bounding-box diagonal (in the reference's unit)."""
    rv = np.asarray(ref_vertices, dtype=float)
    return TOLERANCE_OF_DIAGONAL * float(np.linalg.norm(np.ptp(rv, axis=0)))


def chord_height(f) -> np.ndarray:
    """How far ``(m−1, n−1)`` each quad of the net ``f (m, n, 3)`` may lie from the smooth
    surface through its vertices: ``(|δ_uu f| + 2 |δ_uv f| + |δ_vv f|) / 8``, the bound of the
    linear interpolation error over a quad and its triangles, with the second differences of
    the net along u and v (largest at the quad's corners; rows and columns next to the boundary
    take their neighbour's) and the quad's mixed difference ``f(u+1,v+1) − f(u+1,v) − f(u,v+1)
    + f(u,v)``."""
    f = np.asarray(f, dtype=float)
    m, n, _ = f.shape
    duu = np.zeros((m, n))
    dvv = np.zeros((m, n))
    if m > 2:
        duu[1:-1] = np.linalg.norm(f[2:] - 2.0 * f[1:-1] + f[:-2], axis=-1)
        duu[0], duu[-1] = duu[1], duu[-2]
    if n > 2:
        dvv[:, 1:-1] = np.linalg.norm(f[:, 2:] - 2.0 * f[:, 1:-1] + f[:, :-2], axis=-1)
        dvv[:, 0], dvv[:, -1] = dvv[:, 1], dvv[:, -2]
    corner = duu + dvv
    corners = np.maximum.reduce([corner[:-1, :-1], corner[1:, :-1], corner[1:, 1:],
                                 corner[:-1, 1:]])
    duv = np.linalg.norm(f[1:, 1:] - f[1:, :-1] - f[:-1, 1:] + f[:-1, :-1], axis=-1)
    return (corners + 2.0 * duv) / 8.0


def _covered_samples(f: np.ndarray, rv: np.ndarray, rf: np.ndarray, samples: int,
                     tolerance: float):
    """The samples of :func:`subdivision_samples` on the reference and whether the net ``f``
    covers each (closest net point inside the net, within ``tolerance``): ``(covered (s,)
    bool, weight (s,), nv, nf)``, the last two the net's triangles
    (:func:`~dgpc_cli.metrics.hausdorff.net_triangles`)."""
    import igl

    m, n, _ = f.shape
    nv, nf = net_triangles(f)
    pts, weight = subdivision_samples(rv, rf, samples)
    d2, fid, closest = igl.point_mesh_squared_distance(pts, nv, nf)
    fid = np.asarray(fid, dtype=np.int64)
    tri = nv[nf[fid]]
    bary = igl.barycentric_coordinates(np.ascontiguousarray(closest),
                                       np.ascontiguousarray(tri[:, 0]),
                                       np.ascontiguousarray(tri[:, 1]),
                                       np.ascontiguousarray(tri[:, 2]))
    on_boundary = ((bary < ON_EDGE) & _boundary_edge_mask(m, n)[fid]).any(axis=1)
    reach = tolerance + chord_height(f).ravel()[fid % ((m - 1) * (n - 1))]
    return ~on_boundary & (np.sqrt(d2) <= reach), weight, nv, nf


def coverage(f, ref_vertices, ref_faces, *, samples: int = DEFAULT_SAMPLES,
             surface=None, tolerance: float | None = None) -> dict:
    """Area coverage of the reference by the net ``f (m, n, 3)`` and vertex distances::

        {"area_fraction": covered / reference area, "covered_area", "reference_area",
         "tolerance": the distance within which a point counts as covered,
         "tolerance_relative": the same / the reference's bounding-box diagonal,
         "vertex_distance_max": max distance of a net vertex to the reference,
         "vertex_distance_relative": the same / the reference's bounding-box diagonal}

    ``tolerance``: in the reference's unit; None: :func:`default_tolerance`.

    ``surface``: the reference as a :class:`~dgpc_cli.core.reference.ReferenceSurface`
    already built (its tree answers the vertex distances; built here otherwise).
    """
    from dgpc_cli.core.reference import ReferenceSurface

    f = as_grid(f)
    rv = np.ascontiguousarray(ref_vertices, dtype=float)
    rf = np.ascontiguousarray(ref_faces, dtype=np.int64)
    tolerance = default_tolerance(rv) if tolerance is None else float(tolerance)
    covered, weight, nv, _ = _covered_samples(f, rv, rf, samples, tolerance)
    total = float(weight.sum())
    surface = ReferenceSurface(rv, rf) if surface is None else surface
    vmax = float(np.max(np.linalg.norm(nv - surface.closest(nv)[0], axis=1)))
    diagonal = float(np.linalg.norm(np.ptp(rv, axis=0)))
    return {"area_fraction": float(weight[covered].sum() / total) if total > 0 else None,
            "covered_area": float(weight[covered].sum()), "reference_area": total,
            "tolerance": tolerance,
            "tolerance_relative": tolerance / diagonal if diagonal > 0 else None,
            "vertex_distance_max": vmax,
            "vertex_distance_relative": vmax / diagonal if diagonal > 0 else None}


def covered_faces(f, ref_vertices, ref_faces, *, samples: int = DEFAULT_SAMPLES,
                  tolerance: float | None = None) -> np.ndarray:
    """The fraction ``(t,)`` of each reference face that the net ``f (m, n, 3)`` covers, by
    the samples and the test of :func:`coverage` (so that the area-weighted sum over the faces
    is its ``covered_area``); ``tolerance`` as there."""
    f = as_grid(f)
    rv = np.ascontiguousarray(ref_vertices, dtype=float)
    rf = np.ascontiguousarray(ref_faces, dtype=np.int64)
    tolerance = default_tolerance(rv) if tolerance is None else float(tolerance)
    covered, _, _, _ = _covered_samples(f, rv, rf, samples, tolerance)
    return covered.reshape(len(rf), -1).mean(axis=1)
