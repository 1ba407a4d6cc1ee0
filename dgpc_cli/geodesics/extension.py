"""A reference mesh continued beyond its outer boundary, so that geodesics can run past the
reference (paper Fig. 14: the gridshell's geodesics go "beyond the reference surface").

The continuation is first order: rings of triangles along the outer boundary loop, each ring
one step further along the outward direction in the boundary faces' tangent planes (the mitre
of the two boundary edges' outward normals, so the rings stay at a constant distance from the
edges). A geodesic reaching the boundary goes on straight in the tangent plane of the face it
leaves through, which is where the smooth surface's geodesic would go to first order.
Both nets of a gridshell are fitted to the same continuation, so their laths still meet
beyond the reference.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.sparse import coo_array
from scipy.sparse.csgraph import connected_components

from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.tracing import face_normals
from dgpc_cli.io.mesh import ReferenceMesh

#: Largest mitre length (in ring widths) at a sharp boundary corner.
MAX_MITRE = 2.0
#: Ring width in mean boundary edge lengths.
RING_WIDTH = 1.0
#: The most vertices the rings of a continuation may add (``init --extend`` against the
#: mesh's boundary: rings one boundary edge wide out to F × the diagonal).
MAX_RING_VERTICES = 2_000_000
#: A net traced out to ``init --extend F`` is fitted to the mesh continued to this many times
#: F, so its rim never meets a boundary (where the closest point would pull it back).
FIT_REACH = 2.0


def boundary_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directed boundary edges ``(s, 2)`` (as the faces wind them: the mesh lies to their
    left) and the face ``(s,)`` each belongs to."""
    F = np.asarray(faces, np.int64)
    directed = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    face_of = np.repeat(np.arange(len(F)), 3)
    key = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inverse.ravel()] == 1
    return directed[once], face_of[once]


def outer_loop(vertices: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Mask ``(s,)`` of the boundary edges on the longest boundary loop (holes are left)."""
    n = len(vertices)
    graph = coo_array((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    lengths = np.linalg.norm(vertices[edges[:, 1]] - vertices[edges[:, 0]], axis=1)
    per_loop = np.bincount(label[edges[:, 0]], weights=lengths)
    return label[edges[:, 0]] == np.argmax(per_loop)


def folded_faces(vertices: np.ndarray, faces: np.ndarray, n_original: int) -> int:
    """How many of the faces added by :func:`extend_mesh` (those after the first
    ``n_original``) are turned over against the boundary face they grew from: at a concave
    stretch of the boundary the rings run into each other and fold once they reach past the
    stretch's radius."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    normals, _ = face_normals(V, F)
    edges, face_of = boundary_edges(F[:n_original])
    outer = outer_loop(V, edges)
    edges, face_of = edges[outer], face_of[outer]
    added = normals[n_original:].reshape(2, -1, len(edges), 3)       # (tri, ring, edge, 3)
    return int((np.einsum("trsj,sj->trs", added, normals[face_of]) <= 0).sum())


def extend_mesh(vertices: np.ndarray, faces: np.ndarray,
                distance: float) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices, faces)`` of the mesh with rings added along its outer boundary out to
    ``distance`` (model units; rings about one boundary edge wide). The original vertices and
    faces come first, unchanged; the new faces keep the winding. A closed mesh comes back as
    it is."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    edges, face_of = boundary_edges(F)
    if len(edges) == 0 or distance <= 0:
        return V.copy(), F.copy()
    keep = outer_loop(V, edges)
    edges, face_of = edges[keep], face_of[keep]
    normals, _ = face_normals(V, F)
    along = V[edges[:, 1]] - V[edges[:, 0]]
    out = np.cross(along, normals[face_of])                     # right of a→b: outwards
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    loop = np.unique(edges)                                     # boundary vertices, sorted
    slot = np.searchsorted(loop, edges)                         # (s, 2) positions in loop
    n_in = np.zeros((len(loop), 3))
    n_out = np.zeros((len(loop), 3))
    n_in[slot[:, 1]] = out                                      # edge arriving at the vertex
    n_out[slot[:, 0]] = out                                     # edge leaving it
    # the mitre m with m·n_in = m·n_out = 1 (offset edges stay parallel), capped at corners
    mitre = (n_in + n_out) / (1.0 + np.einsum("ij,ij->i", n_in, n_out))[:, None]
    size = np.linalg.norm(mitre, axis=1, keepdims=True)
    mitre *= np.minimum(1.0, MAX_MITRE / np.maximum(size, 1e-300))
    width = float(np.mean(np.linalg.norm(along, axis=1)))
    rings = max(1, int(np.ceil(distance / (RING_WIDTH * width))))
    step = distance / rings
    k = np.arange(1, rings + 1)[:, None, None]
    new = (V[loop][None] + k * step * mitre[None]).reshape(-1, 3)
    ids = np.vstack([loop, len(V) + np.arange(rings * len(loop)).reshape(rings, -1)])
    a, b = ids[:, slot[:, 0]], ids[:, slot[:, 1]]              # (rings + 1, s)
    # across the edge a→b the new faces run b→a (consistent winding)
    tri1 = np.stack([b[:-1], a[:-1], a[1:]], axis=-1).reshape(-1, 3)
    tri2 = np.stack([b[:-1], a[1:], b[1:]], axis=-1).reshape(-1, 3)
    return np.vstack([V, new]), np.vstack([F, tri1, tri2])


def continued(mesh: ReferenceMesh, fraction: float) -> ReferenceMesh:
    """``mesh`` continued beyond its outer boundary by ``fraction`` of its bounding-box
    diagonal (``init --extend``): what a net running past the reference is traced on and
    fitted to. Path and sha256 stay those of the file (the continuation is rebuilt from it,
    deterministically); a fraction of 0 gives the mesh itself. DgpcError naming ``--extend``
    when the continuation folds (see :func:`folded_faces`), with the largest fraction that
    does not."""
    if fraction <= 0:
        return mesh
    check_extension_size(mesh, fraction)
    V, F, folds = _continuation(mesh, fraction)
    if folds:
        raise DgpcError(
            f"continuing {mesh.path.name} by {fraction:g} of its diagonal folds it at its "
            f"concave boundary ({folds} triangles turned over); at most "
            f"{largest_unfolded(mesh, fraction):.3g} does not", source="--extend")
    return dataclasses.replace(mesh, vertices=V, faces=F)


def check_extension_size(mesh: ReferenceMesh, extend: float) -> None:
    """DgpcError naming ``--extend`` when the continuation of ``mesh`` for ``init --extend
    extend`` (out to :data:`FIT_REACH` × ``extend`` of its diagonal, what ``optimize`` fits to)
    would add more than :data:`MAX_RING_VERTICES`; estimated before anything is allocated."""
    V, F = np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64)
    edges, _ = boundary_edges(F)
    if len(edges) == 0:
        return
    edges = edges[outer_loop(V, edges)]
    width = float(np.mean(np.linalg.norm(V[edges[:, 1]] - V[edges[:, 0]], axis=1)))
    rings = FIT_REACH * extend * mesh.bbox_diagonal / (RING_WIDTH * width)
    added = rings * len(np.unique(edges))
    if not added <= MAX_RING_VERTICES:
        largest = MAX_RING_VERTICES / added * extend
        raise DgpcError(f"continuing {mesh.path.name} by {extend:g} of its diagonal (fitted to "
                        f"{FIT_REACH:g} times that) would add {added:.3g} vertices in rings of "
                        f"{width:.3g}, beyond the limit of {MAX_RING_VERTICES}"
                        + (f"; at most {largest:.3g} stays within it" if largest > 0 else ""),
                        source="--extend")


def largest_unfolded(mesh: ReferenceMesh, fraction: float, steps: int = 12) -> float:
    """The largest extension (fraction of the diagonal, below ``fraction``, by bisection)
    whose continuation does not fold."""
    lo, hi = 0.0, fraction
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _continuation(mesh, mid)[2] == 0 else (lo, mid)
    return lo


def fit_surface(mesh: ReferenceMesh, fraction: float) -> ReferenceMesh:
    """The surface ``optimize`` fits a net made with ``init --extend fraction`` to: the mesh
    continued to :data:`FIT_REACH` × ``fraction``, or as far beyond ``fraction`` as it goes
    without folding (the mesh itself for 0)."""
    if fraction <= 0:
        return mesh
    check_extension_size(mesh, fraction)
    reach = FIT_REACH * fraction
    V, F, folds = _continuation(mesh, reach)
    if not folds:
        return dataclasses.replace(mesh, vertices=V, faces=F)
    return continued(mesh, max(largest_unfolded(mesh, reach), fraction))


def _continuation(mesh: ReferenceMesh, fraction: float) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`extend_mesh` by ``fraction`` of the diagonal and its :func:`folded_faces`."""
    V, F = extend_mesh(mesh.vertices, mesh.faces, fraction * mesh.bbox_diagonal)
    return V, F, folded_faces(V, F, len(mesh.faces))
