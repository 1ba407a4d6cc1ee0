"""Two-sided Hausdorff distance between a net and a reference triangle mesh (SPEC §7, paper Fig. 8).

Uses pymeshlab's ``get_hausdorff_distance`` filter, which is one-directional (from the samples
of ``sampledmesh`` to the surface of ``targetmesh``), in both directions. Samples are chosen
here, deterministically, and handed to the filter as a point cloud with ``samplevert=True`` and
``samplenum`` ≥ their number (every vertex is used; MeshLab's own face sampling is random), so
results are reproducible. MeshLab computes in single precision; coordinates are centred on the
reference's bounding box first to keep the relative error near 1e-7 of the diagonal.
"""

from __future__ import annotations

import math

import numpy as np

from dgpc_cli.metrics.frames import as_grid

__all__ = ["hausdorff", "net_triangles", "surface_samples"]

#: Default number of face samples aimed at per direction (vertices come on top).
DEFAULT_SAMPLES = 100_000


def net_triangles(f) -> tuple[np.ndarray, np.ndarray]:
    """The net as a triangle mesh: vertices ``(m·n, 3)`` (id ``u·n + v``) and faces
    ``(2(m−1)(n−1), 3)``; each quad (u,v),(u+1,v),(u+1,v+1),(u,v+1) is split along its
    diagonal (u,v)–(u+1,v+1), with the orientation of the quad."""
    f = as_grid(f)
    m, n, _ = f.shape
    vid = np.arange(m * n).reshape(m, n)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return f.reshape(-1, 3).copy(), faces


def _validate_mesh(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 3:
        raise ValueError(f"reference vertices must be a (k, 3) array with k ≥ 3, got shape "
                         f"{v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError("reference mesh has non-finite vertex coordinates")
    fc = np.asarray(faces)
    if fc.ndim != 2 or fc.shape[1] != 3 or fc.shape[0] < 1:
        raise ValueError(f"reference faces must be a (k, 3) array of triangles, got shape "
                         f"{fc.shape}")
    if not np.issubdtype(fc.dtype, np.integer):
        if not np.all(np.isfinite(fc)) or np.any(fc != np.round(fc)):
            raise ValueError("reference faces must hold integer vertex indices")
    fc = fc.astype(np.int64)
    if fc.min() < 0 or fc.max() >= v.shape[0]:
        raise ValueError(f"reference faces index vertices outside 0..{v.shape[0] - 1}")
    return v, fc


def surface_samples(vertices: np.ndarray, faces: np.ndarray,
                    target: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Deterministic samples of a triangle mesh, shape ``(k, 3)``.

    All vertices, plus on every triangle the points of the barycentric lattice
    ``(i, j, k−i−j)/k`` except its corners (edge points and interior points), with the level
    ``k = clip(ceil(√(2·target/#faces)), 1, 32)`` (k = 1: the vertices only, for meshes
    with more faces than ``target``) so that there are about ``target`` face
    samples. Edge points shared by two triangles are repeated (harmless for a maximum).
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    level = int(min(32, max(1, math.ceil(math.sqrt(2.0 * target / max(len(faces), 1))))))
    i, j = np.meshgrid(np.arange(level + 1), np.arange(level + 1), indexing="ij")
    keep = (i + j <= level)
    i, j = i[keep], j[keep]
    k = level - i - j
    corner = (i == level) | (j == level) | (k == level)
    bary = np.stack([i, j, k], axis=1)[~corner] / level              # (s, 3)
    tri = vertices[faces]                                              # (F, 3, 3)
    pts = np.einsum("sk,fkd->fsd", bary, tri).reshape(-1, 3)
    return np.concatenate([vertices, pts])


def _one_way(ms, sampled_id: int, target_id: int, n_samples: int, maxdist: float) -> dict:
    import pymeshlab

    return ms.get_hausdorff_distance(sampledmesh=sampled_id, targetmesh=target_id,
                                     samplevert=True, sampleedge=False, samplefauxedge=False,
                                     sampleface=False, samplenum=int(n_samples),
                                     maxdist=pymeshlab.PureValue(float(maxdist)))


def hausdorff(net_f, ref_vertices, ref_faces, *, samples: int = DEFAULT_SAMPLES) -> dict:
    """Hausdorff distance between a net ``(m, n, 3)`` and a reference triangle mesh.

    The net is triangulated by :func:`net_triangles`. Each surface is sampled by
    :func:`surface_samples` (about ``samples`` face samples plus the vertices) and the samples'
    distances to the other surface are measured with pymeshlab (``get_hausdorff_distance``,
    no distance cut-off). Returns::

        {"net_to_reference_max", "net_to_reference_mean", "reference_to_net_max",
         "reference_to_net_mean", "max" (two-sided Hausdorff distance),
         "mean" (average of the two one-way means), "diagonal" (of the reference's bounding
         box), "relative" (max / diagonal), "n_samples_net", "n_samples_reference"}

    All floats (the distances in single precision). Nothing is printed: the MeshSet is
    created with ``verbose=False``. Typical nets on their reference take well under a second;
    MeshLab's grid search gets slow (tens of seconds) when most samples are far from the
    other surface. Raises ``ValueError`` for a malformed reference mesh.
    """
    import pymeshlab

    nv, nf = net_triangles(net_f)
    rv, rf = _validate_mesh(ref_vertices, ref_faces)
    lo, hi = rv.min(axis=0), rv.max(axis=0)
    centre = 0.5 * (lo + hi)
    diagonal = float(np.linalg.norm(hi - lo))
    nv, rv = nv - centre, rv - centre
    span = np.concatenate([nv, rv])
    maxdist = 2.0 * float(np.linalg.norm(span.max(axis=0) - span.min(axis=0))) + 1.0

    net_samples = surface_samples(nv, nf, samples)
    ref_samples = surface_samples(rv, rf, samples)

    ms = pymeshlab.MeshSet(verbose=False)
    ids = {}
    for name, mesh in (
            ("reference", pymeshlab.Mesh(vertex_matrix=rv, face_matrix=rf.astype(np.int32))),
            ("net", pymeshlab.Mesh(vertex_matrix=nv, face_matrix=nf.astype(np.int32))),
            ("net_samples", pymeshlab.Mesh(vertex_matrix=net_samples)),
            ("reference_samples", pymeshlab.Mesh(vertex_matrix=ref_samples))):
        ms.add_mesh(mesh, name)
        ids[name] = ms.current_mesh_id()
    net_to_ref = _one_way(ms, ids["net_samples"], ids["reference"], len(net_samples), maxdist)
    ref_to_net = _one_way(ms, ids["reference_samples"], ids["net"], len(ref_samples), maxdist)

    a_max, b_max = float(net_to_ref["max"]), float(ref_to_net["max"])
    both = max(a_max, b_max)
    return {
        "net_to_reference_max": a_max,
        "net_to_reference_mean": float(net_to_ref["mean"]),
        "reference_to_net_max": b_max,
        "reference_to_net_mean": float(ref_to_net["mean"]),
        "max": both,
        "mean": 0.5 * (float(net_to_ref["mean"]) + float(ref_to_net["mean"])),
        "diagonal": diagonal,
        "relative": both / diagonal if diagonal > 0 else None,
        "n_samples_net": int(net_to_ref["n_samples"]),
        "n_samples_reference": int(ref_to_net["n_samples"]),
    }
