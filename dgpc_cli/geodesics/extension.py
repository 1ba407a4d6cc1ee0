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
#: A boundary face lower than this fraction of its boundary edge, or a boundary edge shorter
#: than this fraction of the mean, gives no outward direction of its own.
SLIVER = 1e-2
#: Where the boundary turns by more than this (radians) at a vertex, a corner, the rings are
#: mitred sharply; elsewhere they follow the averaged outward direction.
CORNER = np.radians(40.0)
#: Arc length (in mean boundary edges) either side of a vertex over which the outward
#: direction of a smooth stretch is averaged, at the ends of edges shorter than SHORT (in mean
#: boundary edges).
SMOOTHING, SHORT = 2.0, 0.5
#: A net traced out to ``init --extend F`` is fitted to the mesh continued to this many times
#: F, so its rim never meets a boundary (where the closest point would pull it back).
FIT_REACH = 2.0
#: A patch's surroundings (:func:`surrounded`) are cut from the whole mesh continued by this
#: many times their reach (the reach is measured in space, the continuation along the
#: boundary's outward direction) ...
SURROUND_MARGIN = 1.5
#: ... by at most this fraction of the whole mesh's diagonal, or as far as it does not fold
#: (found to 2^-SURROUND_STEPS of that).
MAX_SURROUND, SURROUND_STEPS = 0.5, 6


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


def outward_normals(V: np.ndarray, F: np.ndarray, edges: np.ndarray,
                    face_of: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit outward directions ``(s, 3)`` of the boundary edges in their faces' tangent planes
    (right of a → b), and the unit surface normals ``(s, 3)`` they were taken in. A sliver
    face (height below :data:`SLIVER` of its boundary edge, as a mesh cut by a plane through
    its vertices has) has no reliable normal: the area-weighted normal at the edge's ends
    stands in; an edge shorter than :data:`SLIVER` of the mean has no reliable direction: it
    takes the outward direction of the edge before it."""
    normals, area = face_normals(V, F)
    along = V[edges[:, 1]] - V[edges[:, 0]]
    length = np.linalg.norm(along, axis=1)
    nrm = normals[face_of]
    thin = 2.0 * area[face_of] < SLIVER * length ** 2
    if thin.any():
        vn = np.zeros_like(V)
        np.add.at(vn, F.ravel(), np.repeat(normals * area[:, None], 3, axis=0))
        en = vn[edges[:, 0]] + vn[edges[:, 1]]
        nrm = np.where(thin[:, None], en / np.linalg.norm(en, axis=1, keepdims=True), nrm)
    out = np.cross(along, nrm)
    out /= np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300)
    tiny = length < SLIVER * length.mean()
    if tiny.any():
        before = np.full(int(edges.max()) + 1, -1)
        before[edges[:, 1]] = np.arange(len(edges))
        prev = before[edges[:, 0]]                             # the edge ending where e starts
        for _ in range(int(tiny.sum())):                       # chains of tiny edges
            take = tiny & (prev >= 0) & ~tiny[np.maximum(prev, 0)]
            if not take.any():
                break
            out[take], nrm[take] = out[prev[take]], nrm[prev[take]]
            tiny = tiny & ~take
    return out, nrm


def chained(edges: np.ndarray) -> list[np.ndarray]:
    """The directed boundary edges ``(s, 2)`` chained into loops: lists of edge indices in
    order (one walk per loop; an edge follows the one that ends where it starts)."""
    follow = np.full(int(edges.max()) + 1, -1, dtype=np.int64)
    follow[edges[:, 0]] = np.arange(len(edges))
    seen = np.zeros(len(edges), dtype=bool)
    loops = []
    for first in range(len(edges)):  # one walk per loop, along its edges
        if seen[first]:
            continue
        order, e = [], first
        while e >= 0 and not seen[e]:
            seen[e] = True
            order.append(e)
            e = follow[edges[e, 1]]
        loops.append(np.asarray(order, dtype=np.int64))
    return loops


def _along_loop_average(edges, length, out, window, smooth_start):
    """For the start vertex of every boundary edge: the mean ``(s, 3)`` (normalized) of the
    edges' ``out``, a function of arc length constant on each edge, over the arc length within
    ``window`` of the vertex, never across a corner (``smooth_start[e]`` False: a corner at the
    start of e). The integral is interpolated from its values at the edge ends, so the mean
    moves continuously with the vertex."""
    result = np.zeros_like(out)
    for chain in chained(edges):  # one pass per loop (a handful)
        corners = np.flatnonzero(~smooth_start[chain])
        if corners.size:
            chain = np.roll(chain, -int(corners[0]))   # start the walk at a corner
        L, o = length[chain], out[chain]
        ends = np.concatenate([[0.0], np.cumsum(L)])
        total = ends[-1]
        s = ends[:-1]                                  # the start vertex of each edge
        if corners.size:
            run = np.cumsum(~smooth_start[chain]) - 1
            first = ends[np.searchsorted(run, run, side="left")]
            last = ends[np.searchsorted(run, run, side="right")]
            knots, weights = ends, L
        else:                                          # a closed smooth loop: wrap around
            first, last = s - total, s + total
            knots = np.concatenate([ends[:-1] - total, ends[:-1], ends + total])
            weights, o = np.tile(L, 3), np.tile(o, (3, 1))
        integral = np.concatenate([np.zeros((1, 3)), np.cumsum(weights[:, None] * o, axis=0)])
        a, b = np.maximum(s - window, first), np.minimum(s + window, last)
        at = [np.stack([np.interp(x, knots, integral[:, j]) for j in range(3)], axis=1)
              for x in (a, b)]
        mean = (at[1] - at[0]) / np.maximum(b - a, 1e-300)[:, None]
        result[chain] = mean / np.maximum(np.linalg.norm(mean, axis=1, keepdims=True), 1e-300)
    return result


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
    _, grown_from = outward_normals(V, F[:n_original], edges, face_of)
    added = normals[n_original:].reshape(2, -1, len(edges), 3)       # (tri, ring, edge, 3)
    return int((np.einsum("trsj,sj->trs", added, grown_from) <= 0).sum())


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
    out, _ = outward_normals(V, F, edges, face_of)
    along = V[edges[:, 1]] - V[edges[:, 0]]
    loop = np.unique(edges)                                     # boundary vertices, sorted
    slot = np.searchsorted(loop, edges)                         # (s, 2) positions in loop
    n_in = np.zeros((len(loop), 3))
    n_out = np.zeros((len(loop), 3))
    n_in[slot[:, 1]] = out                                      # edge arriving at the vertex
    n_out[slot[:, 0]] = out                                     # edge leaving it
    length = np.linalg.norm(along, axis=1)
    # the mitre m with m·n_in = m·n_out = 1 (offset edges stay parallel), capped at corners
    cos = np.einsum("ij,ij->i", n_in, n_out)
    mitre = (n_in + n_out) / (1.0 + cos)[:, None]
    size = np.linalg.norm(mitre, axis=1, keepdims=True)
    mitre *= np.minimum(1.0, MAX_MITRE / np.maximum(size, 1e-300))
    # at the ends of a short edge on a smooth stretch the direction is the edges' outward field
    # averaged over SMOOTHING mean edges of arc length: facet normals differ from edge to edge,
    # and the rings over a short edge whose ends took them as they are would fold a short way
    # out (elsewhere the mitre keeps the offset edges parallel)
    width = float(np.mean(length))
    smooth = cos > np.cos(CORNER)
    short = np.zeros(len(loop), dtype=bool)
    short[slot[length < SHORT * width].ravel()] = True
    averaged = _along_loop_average(edges, length, out, SMOOTHING * width, smooth[slot[:, 0]])
    field = np.zeros((len(loop), 3))
    field[slot[:, 0]] = averaged
    mitre = np.where((smooth & short)[:, None], field, mitre)
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


def surrounded(patch: ReferenceMesh, whole: ReferenceMesh, fraction: float) -> ReferenceMesh:
    """What a net on ``patch`` (a patch of ``whole``, ``init --patches``) runs past the patch
    on, out to ``fraction`` of the patch's diagonal: the whole mesh, continued in its own
    boundary's tangent planes (as far as that does not fold), cropped to the faces within that
    reach of the patch (the piece around the patch). Across a cut a net so goes on over the
    neighbouring patch, the surface itself, where the patch's own continuation would leave it
    in the cut's tangent planes and fold at the patch's concave corners. Path and sha256 stay
    the patch's; a fraction of 0 gives the patch itself."""
    from dgpc_cli.core.reference import ReferenceSurface

    if fraction <= 0:
        return patch
    reach = fraction * patch.bbox_diagonal
    want = min(SURROUND_MARGIN * reach / whole.bbox_diagonal, MAX_SURROUND)
    check_extension_size(whole, want)
    V, F, folds = _continuation(whole, want)
    if folds:
        V, F, _ = _continuation(whole, largest_unfolded(whole, want, steps=SURROUND_STEPS))
    foot, _ = ReferenceSurface(patch.vertices, patch.faces).closest(V)
    near = np.linalg.norm(V - foot, axis=1) <= reach
    F = F[near[F].any(axis=1)]
    # the piece around the patch: the largest connected one
    k = len(V)
    graph = coo_array((np.ones(2 * len(F)), (F[:, [0, 1]].ravel(), F[:, [1, 2]].ravel())),
                      shape=(k, k))
    _, label = connected_components(graph, directed=False)
    sizes = np.bincount(label[F[:, 0]])
    F = F[label[F[:, 0]] == np.argmax(sizes)]
    used = np.unique(F)
    index = np.full(k, -1, np.int64)
    index[used] = np.arange(len(used))
    return dataclasses.replace(patch, vertices=np.ascontiguousarray(V[used]),
                               faces=np.ascontiguousarray(index[F]))
