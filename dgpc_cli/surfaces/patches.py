"""A triangle mesh split into patches along curves that follow its creases (``init --patches``).

One bisection cuts a mesh along a level set of its Fiedler vector: the eigenvector of the
second-smallest eigenvalue of ``L φ = λ M φ``, with ``M`` the Voronoi mass matrix and ``L`` the
Laplacian of the vertex graph whose edge weights are the (non-negative part of the) cotangent
weights, each damped by the crease across its edge, ``exp(−θ / θ̄)`` (θ the angle between the
normals of the edge's two faces, θ̄ its area-weighted mean over the interior edges). The Fiedler
vector varies slowly inside a lobe and fast across the valleys and crests between lobes (spectral
mesh segmentation, Liu and Zhang 2004). Its level sets at 21 levels between the 25th and 75th
area percentiles, and those of the next eigenvector, are scored by their isoperimetric ratio
(the cut's length times the sum of the reciprocal areas on each side: the shortest cut that
leaves two large pieces, the neck between two lobes; both sides kept connected); each level
lies in the widest gap between the sorted vertex values near its percentile (no sliver
triangles), and the mesh is cut exactly along the best one
(``trimesh.intersections.slice_faces_plane``, the field standing in for the signed distance to
a plane); the cut curves are the new boundary edges on it, joined into polylines.

Everything is deterministic: the eigensolver starts from a fixed vector, the vector's sign is
fixed (its largest entry in magnitude is positive), ties go to the lower level.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Levels of the Fiedler vector scored for a cut, and the area percentiles they span.
LEVELS, LOW, HIGH = 21, 0.25, 0.75
#: A level lies in the widest gap between the sorted values of φ within this many vertices of
#: its percentile, so that no vertex lies (nearly) on the cut.
GAP_WINDOW = 8
#: Eigenvectors whose level sets are tried: the Fiedler vector and the next (on a symmetric
#: mesh one of them is often symmetric, the other cuts along the plane of symmetry).
FIELDS = 2
#: A patch with fewer vertices is not cut further.
MIN_VERTICES = 30


@dataclass
class Patch:
    """A piece of a mesh: ``vertices (k, 3)``, ``faces (t, 3)``; ``cuts``: the cut curves on its
    boundary that separate it from its neighbours (polylines ``(j, 3)``)."""

    vertices: np.ndarray
    faces: np.ndarray
    cuts: list[np.ndarray] = field(default_factory=list)

    @property
    def area(self) -> float:
        return float(_face_areas(self.vertices, self.faces).sum())


def _face_areas(V, F) -> np.ndarray:
    tri = np.asarray(V, float)[np.asarray(F)]
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)


def _edge_weights(V: np.ndarray, F: np.ndarray):
    """Vertex pairs ``(e, 2)`` (i < j), their cotangent weights and their crease-damped
    cotangent weights ``(e,)``."""
    import igl
    from scipy.sparse import triu

    C = triu(igl.cotmatrix(V, F), k=1).tocoo()
    pairs = np.stack([C.row, C.col], axis=1).astype(np.int64)
    w = np.maximum(np.asarray(C.data, float), 0.0)
    # the angle between the normals of the two faces of every interior edge
    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = 0.5 * np.linalg.norm(n, axis=1)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    directed = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    key = np.sort(directed, axis=1)
    face_of = np.repeat(np.arange(len(F)), 3)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face_of = key[order], face_of[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    a, b = face_of[:-1][same], face_of[1:][same]
    theta = np.arccos(np.clip(np.einsum("ij,ij->i", n[a], n[b]), -1.0, 1.0))
    weight = area[a] + area[b]
    mean = float((theta * weight).sum() / weight.sum()) if weight.sum() > 0 else 0.0
    crease = np.ones(len(pairs))
    if mean > 0:
        n_v = np.int64(len(V))
        edge_keys = key[:-1][same] @ np.array([n_v, 1])          # sorted, as key is
        pair_keys = pairs @ np.array([n_v, 1])
        at = np.clip(np.searchsorted(edge_keys, pair_keys), 0, len(edge_keys) - 1)
        found = edge_keys[at] == pair_keys
        crease[found] = np.exp(-theta[at[found]] / mean)
    return pairs, w, w * crease


def fiedler(V: np.ndarray, F: np.ndarray, count: int = 1) -> list[np.ndarray]:
    """The crease-damped Fiedler vector ``φ (k,)`` of the mesh (see the module) and the
    ``count − 1`` eigenvectors after it, each scaled to ``max |φ| = 1`` with that entry
    positive."""
    import igl
    from scipy.sparse import coo_array, diags
    from scipy.sparse.linalg import eigsh

    V = np.asarray(V, float)
    F = np.asarray(F, np.int64)
    pairs, _, w = _edge_weights(V, F)
    k = len(V)
    W = coo_array((np.concatenate([w, w]), (np.concatenate([pairs[:, 0], pairs[:, 1]]),
                                            np.concatenate([pairs[:, 1], pairs[:, 0]]))),
                  shape=(k, k)).tocsc()
    L = (diags(np.asarray(W.sum(axis=1)).ravel()) - W).tocsc()
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI).tocsc()
    v0 = np.linspace(1.0, 2.0, k)
    scale = float(M.diagonal().mean())
    vals, vecs = eigsh(L, k=count + 1, M=M, sigma=-1e-6 * float(L.diagonal().mean()) / scale,
                       which="LM", v0=v0)
    out = []
    for i in np.argsort(vals)[1:count + 1]:
        phi = vecs[:, int(i)] / np.abs(vecs[:, int(i)]).max()
        out.append(-phi if phi[int(np.argmax(np.abs(phi)))] < 0 else phi)
    return out


def _connected(F: np.ndarray, keep: np.ndarray, count: int) -> bool:
    """Whether the faces ``keep`` of ``F`` form one piece (through shared vertices)."""
    from scipy.sparse import coo_array
    from scipy.sparse.csgraph import connected_components

    faces = F[keep]
    if len(faces) == 0:
        return False
    rows = np.repeat(np.arange(len(faces)), 3)
    g = coo_array((np.ones(len(rows)), (rows, faces.ravel())), shape=(len(faces), count))
    g = (g @ g.T).tocsr()
    return connected_components(g, directed=False)[0] == 1


def cut_length(V: np.ndarray, F: np.ndarray, phi: np.ndarray, c: float) -> float:
    """Length of the level set ``φ = c`` on the mesh (``φ`` linear on every triangle, no vertex
    on the level): one segment across every triangle it crosses."""
    V, F = np.asarray(V, float), np.asarray(F, np.int64)
    i, j = F, F[:, [1, 2, 0]]                                     # the edges of every face
    below = phi < c
    crosses = below[i] != below[j]                                # (t, 3)
    faces = np.flatnonzero(crosses.sum(axis=1) == 2)
    if len(faces) == 0:
        return 0.0
    i, j, crosses = i[faces], j[faces], crosses[faces]
    denom = np.where(crosses, phi[j] - phi[i], 1.0)
    t = np.where(crosses, (c - phi[i]) / denom, 0.0)
    P = V[i] + t[..., None] * (V[j] - V[i])                       # (k, 3, 3)
    two = np.argsort(~crosses, axis=1, kind="stable")[:, :2]
    rows = np.arange(len(faces))
    return float(np.linalg.norm(P[rows, two[:, 0]] - P[rows, two[:, 1]], axis=1).sum())


def best_level(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, float, dict]:
    """The field ``φ`` and the level ``c`` of the best cut (see the module), and its record
    (isoperimetric ratio of the cut, area share of the side ``φ < c``)."""
    import igl

    mass = igl.massmatrix(np.asarray(V, float), np.asarray(F, np.int64),
                          igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    best = None
    for which, phi in enumerate(fiedler(V, F, FIELDS), start=1):
        order = np.argsort(phi, kind="stable")
        cum = np.cumsum(mass[order]) / mass.sum()
        for q in np.linspace(LOW, HIGH, LEVELS):
            i = int(np.searchsorted(cum, q))
            lo, hi = max(i - GAP_WINDOW, 0), min(i + GAP_WINDOW, len(order) - 1)
            gaps = np.diff(phi[order[lo:hi + 1]])
            j = lo + int(np.argmax(gaps))
            c = 0.5 * (phi[order[j]] + phi[order[j + 1]])
            below = phi < c
            a_lo = float(mass[below].sum())
            a_hi = float(mass.sum()) - a_lo
            if a_lo <= 0 or a_hi <= 0:
                continue
            score = cut_length(V, F, phi, c) * (1.0 / a_lo + 1.0 / a_hi)
            if best is not None and not score < best[0] - 1e-12 * abs(best[0]):
                continue
            side = below[F]
            if not (_connected(F, side.all(axis=1), len(V))
                    and _connected(F, (~side).all(axis=1), len(V))):
                continue
            best = (score, phi, float(c), a_lo / float(mass.sum()), which)
    if best is None:
        raise ValueError("no level of the mesh's Fiedler vectors cuts it into two pieces")
    score, phi, c, share, which = best
    return phi, c, {"cut_ratio": score, "area_share": share, "eigenvector": which}


def _polylines(segments: np.ndarray) -> list[np.ndarray]:
    """Segments ``(k, 2, 3)`` joined end to end into polylines (ends closer than a millionth
    of the mean segment merged first; ``shapely.ops.linemerge``), longest first."""
    from shapely.geometry import MultiLineString
    from shapely.ops import linemerge
    from trimesh.grouping import unique_rows

    seg = np.asarray(segments, float).reshape(-1, 2, 3)
    seg = seg[np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1) > 0]
    if len(seg) == 0:
        return []
    size = float(np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1).mean())
    pts = seg.reshape(-1, 3)
    first, inverse = unique_rows(np.round(pts / (1e-6 * size)))
    snapped = pts[first][inverse].reshape(-1, 2, 3)
    snapped = snapped[np.any(snapped[:, 0] != snapped[:, 1], axis=1)]
    merged = linemerge(MultiLineString([s.tolist() for s in snapped]))
    lines = [np.asarray(g.coords, float) for g in getattr(merged, "geoms", [merged])]
    lines.sort(key=lambda p: (-float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()),
                              tuple(p[0])))
    return lines


def _piece(V: np.ndarray, F: np.ndarray, dots: np.ndarray):
    """The part of the mesh where ``dots > 0``, its triangles cut along ``dots = 0``
    (``trimesh.intersections.slice_faces_plane`` on the vertices ``(x, y, dots)`` and the plane
    ``z = 0``, the true ``z`` carried as a texture coordinate: both are interpolated along the
    cut edges with the same parameter), unused vertices dropped; and the cut as segments
    ``(k, 2, 3)`` (its boundary edges whose both ends lie on ``dots = 0``)."""
    import trimesh
    from trimesh.constants import tol
    from trimesh.intersections import slice_faces_plane

    fake = np.column_stack([V[:, 0], V[:, 1], dots])
    uv = np.column_stack([V[:, 2], np.zeros(len(V))])
    nv, nf, nuv = slice_faces_plane(fake, F, np.array([0.0, 0.0, 1.0]), np.zeros(3), uv=uv)
    nv, nf, nuv = np.asarray(nv, float), np.asarray(nf, np.int64), np.asarray(nuv, float)
    real = np.column_stack([nv[:, 0], nv[:, 1], nuv[:, 0]])
    on_cut = np.abs(nv[:, 2]) <= tol.merge
    used = np.unique(nf)
    remap = np.full(len(real), -1, np.int64)
    remap[used] = np.arange(len(used))
    real, nf, on_cut = real[used], remap[nf], on_cut[used]
    mesh = trimesh.Trimesh(real, nf, process=False)
    edges = mesh.edges_sorted[trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)]
    edges = edges[on_cut[edges].all(axis=1)]
    return real, nf, real[edges]


def bisect(patch: Patch) -> tuple[Patch, Patch, list[np.ndarray], dict]:
    """The two patches ``φ < c`` and ``φ > c`` of the best cut of ``patch`` (see the module),
    the cut curves (polylines) and the cut's record."""
    V, F = np.asarray(patch.vertices, float), np.asarray(patch.faces, np.int64)
    if len(V) < MIN_VERTICES:
        raise ValueError(f"a patch of {len(V)} vertices is too small to cut (fewer than "
                         f"{MIN_VERTICES})")
    phi, c, record = best_level(V, F)
    lo_v, lo_f, cut = _piece(V, F, c - phi)
    hi_v, hi_f, _ = _piece(V, F, phi - c)
    curves = _polylines(cut)
    a = Patch(lo_v, lo_f, cuts=[*_near(patch.cuts, lo_v, lo_f), *curves])
    b = Patch(hi_v, hi_f, cuts=[*_near(patch.cuts, hi_v, hi_f), *curves])
    return a, b, curves, {**record, "level": c}


def _near(curves: list[np.ndarray], V: np.ndarray, F: np.ndarray) -> list[np.ndarray]:
    """The parts of the earlier cut curves that lie on the piece ``V, F`` (their longest run
    of points within a millionth of an edge of its vertices), so that a piece keeps only its
    own cuts."""
    from scipy.spatial import cKDTree

    if not curves:
        return []
    tree = cKDTree(V)
    tol = 1e-6 * float(np.median(np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1)))
    out = []
    for p in curves:
        on = tree.query(p)[0] <= tol
        runs = np.flatnonzero(np.diff(np.concatenate([[0], on.astype(np.int8), [0]])))
        if len(runs) == 0:
            continue
        starts, ends = runs[0::2], runs[1::2]
        k = int(np.argmax(ends - starts))
        if ends[k] - starts[k] >= 2:
            out.append(p[starts[k]:ends[k]])
    return out


def split(vertices: np.ndarray, faces: np.ndarray, count: int) -> tuple[list[Patch], list]:
    """``count`` patches of the mesh: the largest patch bisected until there are that many;
    the patches (in order of their area centroid along the mesh's longest axis) and one record
    per cut (its curves and figures)."""
    patches = [Patch(np.asarray(vertices, float), np.asarray(faces, np.int64))]
    cuts = []
    while len(patches) < count:
        i = max(range(len(patches)), key=lambda k: (patches[k].area, -k))
        a, b, curves, record = bisect(patches[i])
        patches[i:i + 1] = [a, b]
        cuts.append({"curves": curves, **record})
    return order_patches(patches, vertices), cuts


def order_patches(patches: list[Patch], vertices: np.ndarray) -> list[Patch]:
    """Patches sorted by their area centroid along the longest axis of ``vertices``."""
    V = np.asarray(vertices, float)
    _, _, vt = np.linalg.svd(V - V.mean(axis=0), full_matrices=False)
    axis = vt[0] if vt[0][np.argmax(np.abs(vt[0]))] > 0 else -vt[0]

    def key(p: Patch):
        a = _face_areas(p.vertices, p.faces)
        centre = (p.vertices[p.faces].mean(axis=1) * a[:, None]).sum(axis=0) / a.sum()
        return float(centre @ axis)

    return sorted(patches, key=key)
