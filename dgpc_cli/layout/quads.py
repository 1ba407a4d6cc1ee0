"""``dgpc init --from-quads`` (SPEC §5): an existing regular quad net read from an OBJ file, its
m×n grid detected; a closed ring (a surface of revolution meshed all round) is cut at a seam."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.coordinates import bad_rows, coordinate_problem
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.io.obj import count_lines
from dgpc_cli.layout.net_size import check_vertex_count
from dgpc_cli.metrics.degenerate import GPC_LIMIT, degeneracies
from dgpc_cli.metrics.residuals import gpc_angle_defect_max

log = logging.getLogger(__name__)


def read_quad_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ``(k, 3)`` and quads ``(q, 4)`` (0-based) of an OBJ file; DgpcError naming the
    file for anything that is not a pure quad mesh."""
    if path.suffix.lower() != ".obj":
        raise DgpcError(f"--from-quads reads OBJ files, not '{path.suffix}'", source=path)
    try:
        text = path.read_bytes()
    except FileNotFoundError:
        raise DgpcError("no such file", source=path) from None
    except OSError as e:
        raise DgpcError(f"cannot read: {e.strerror or e}", source=path) from None
    if b"\0" in text:
        raise DgpcError("not an OBJ file: binary data", source=path)
    # a quad net has about as many faces as vertices: count both before parsing
    vertices = max(count_lines(text, b"v"), count_lines(text, b"f"))
    check_vertex_count(vertices, str(path), "import a coarser net")
    verts, quads = [], []
    for lineno, raw in enumerate(text.decode("utf-8", errors="replace").splitlines(), 1):
        parts = raw.split()
        if not parts:
            continue
        try:
            if parts[0] == "v":
                verts.append([float(p) for p in parts[1:4]])
                if len(verts[-1]) != 3:
                    raise ValueError
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                if len(idx) != 4:
                    raise DgpcError(f"line {lineno}: a face with {len(idx)} vertices; "
                                    "--from-quads needs a mesh of quads only", source=path)
                quads.append([i - 1 if i > 0 else len(verts) + i for i in idx])
        except ValueError:
            raise DgpcError(f"line {lineno}: cannot read {raw.strip()[:60]!r}",
                            source=path) from None
    if not quads:
        raise DgpcError("no faces: --from-quads needs a regular quad net", source=path)
    V, Q = np.asarray(verts, dtype=float), np.asarray(quads, dtype=np.int64)
    if Q.min() < 0 or Q.max() >= len(V):
        raise DgpcError("a face refers to a vertex that does not exist", source=path)
    bad = bad_rows(V)
    if bad.size:
        raise DgpcError(f"vertex {int(bad[0]) + 1} has {coordinate_problem(V[bad[0]])}",
                        source=path)
    return V, Q


def cut_ring(quads: np.ndarray, n_vertices: int, source) -> tuple[np.ndarray, np.ndarray]:
    """Cut a closed ring of quads (no corner vertex: a surface of revolution meshed all round)
    open along a seam: ``(quads, seam)`` with ``seam (k,)`` the vertex ids of a grid line across
    the ring, from the boundary vertex of lowest id straight on (at every interior vertex the
    edge that shares no face with the incoming one) to the other boundary, and the faces on the
    seam's left (those that run along it in its direction) renumbered to copies of the seam
    vertices, ids ``n_vertices + 0 … k−1``. DgpcError naming ``source`` for a mesh closed all
    round or a seam that does not run straight across."""
    Q = np.asarray(quads, dtype=np.int64)
    directed = np.stack([Q, np.roll(Q, -1, axis=1)], axis=-1).reshape(-1, 2)
    key = np.sort(directed, axis=1)
    edges, counts = np.unique(key, axis=0, return_counts=True)
    boundary = edges[counts == 1]
    if boundary.size == 0:
        raise DgpcError("not a regular quad net: closed all round (no boundary, no corner); "
                        "cut it open into a ring or a rectangle first", source=source)
    on_boundary = np.zeros(n_vertices, dtype=bool)
    on_boundary[boundary.ravel()] = True
    faces_at: dict[tuple[int, int], list[int]] = {}
    for e, (a, b) in enumerate(key.tolist()):  # an import, not a hot path
        faces_at.setdefault((a, b), []).append(e // 4)
    neighbours: dict[int, set[int]] = {}
    for a, b in edges.tolist():
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)
    irregular = DgpcError("not a regular quad net: no corner vertex, and no grid line runs "
                          "straight across the ring to cut it at", source=source)
    start = int(boundary.min())
    inward = [x for x in neighbours[start] if len(faces_at[tuple(sorted((start, x)))]) == 2]
    if len(inward) != 1:
        raise irregular
    path = [start, inward[0]]
    while not on_boundary[path[-1]]:
        prev, cur = path[-2], path[-1]
        beside = set()
        for fi in faces_at[tuple(sorted((prev, cur)))]:
            q = Q[fi].tolist()
            i = q.index(cur)
            beside.update((q[i - 1], q[(i + 1) % 4]))
        ahead = neighbours[cur] - beside - {prev}
        if len(ahead) != 1 or len(path) > n_vertices:
            raise irregular
        path.append(ahead.pop())
    seam = np.asarray(path, dtype=np.int64)
    slot = np.full(n_vertices, -1, dtype=np.int64)
    slot[seam] = np.arange(len(seam))
    along = {(int(a), int(b)) for a, b in zip(seam[:-1], seam[1:], strict=True)}
    left = np.unique([e // 4 for e, (a, b) in enumerate(directed.tolist()) if (a, b) in along])
    out = Q.copy()
    block = out[left]
    out[left] = np.where(slot[block] >= 0, n_vertices + slot[block], block)
    return out, seam


def quad_grid(quads: np.ndarray, source) -> np.ndarray:
    """The vertex ids ``(m, n)`` of a regular quad net: grid coordinates propagated face by
    face from the corner vertex of lowest id (its face's order gives +u, then +v); DgpcError
    when the quads are not one m×n grid."""
    Q = np.asarray(quads, dtype=np.int64).tolist()
    edge_faces: dict[tuple[int, int], list[int]] = {}
    for fi, q in enumerate(Q):
        for k in range(4):
            a, b = q[k], q[(k + 1) % 4]
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(fi)
    if any(len(fs) > 2 for fs in edge_faces.values()):
        raise DgpcError("not a regular quad net: an edge is shared by more than two faces",
                        source=source)
    valence: dict[int, int] = {}
    for q in Q:
        for v in q:
            valence[v] = valence.get(v, 0) + 1
    corners = sorted(v for v, k in valence.items() if k == 1)
    if not corners:
        raise DgpcError("not a regular quad net: no corner vertex (closed or irregular)",
                        source=source)
    start = next(fi for fi, q in enumerate(Q) if corners[0] in q)
    q0 = Q[start]
    k0 = q0.index(corners[0])
    q0 = q0[k0:] + q0[:k0]
    coord = {q0[0]: (0, 0), q0[1]: (1, 0), q0[2]: (1, 1), q0[3]: (0, 1)}
    seen = {start}
    stack = [start]
    bad = DgpcError("not a regular quad net: the faces do not fit one m x n grid",
                    source=source)
    while stack:  # one visit per face (an import, not a hot path)
        fi = stack.pop()
        q = Q[fi]
        for k in range(4):
            x, y = q[k], q[(k + 1) % 4]
            xp, yp = q[(k - 1) % 4], q[(k + 2) % 4]  # x's and y's other neighbours
            for g in edge_faces[(min(x, y), max(x, y))]:
                if g == fi or g in seen:
                    continue
                r = Q[g]
                ix, iy = r.index(x), r.index(y)
                w = r[(ix - 1) % 4] if r[(ix + 1) % 4] == y else r[(ix + 1) % 4]
                z = r[(iy - 1) % 4] if r[(iy + 1) % 4] == x else r[(iy + 1) % 4]
                for new, old, opp in ((w, x, xp), (z, y, yp)):
                    cx, cy = coord[old]
                    ox, oy = coord[opp]
                    want = (2 * cx - ox, 2 * cy - oy)
                    if coord.setdefault(new, want) != want:
                        raise bad
                seen.add(g)
                stack.append(g)
    if len(seen) != len(Q):
        raise DgpcError(f"not a regular quad net: {len(Q) - len(seen)} faces are not connected "
                        "to the rest", source=source)
    ids = np.fromiter(coord.keys(), dtype=np.int64)
    ij = np.array(list(coord.values()), dtype=np.int64)
    ij -= ij.min(axis=0)
    m, n = (ij.max(axis=0) + 1).tolist()
    if m * n != len(ids) or (m - 1) * (n - 1) != len(Q) or \
            len(np.unique(ij[:, 0] * n + ij[:, 1])) != len(ids):
        raise bad
    grid = np.empty((m, n), dtype=np.int64)
    grid[ij[:, 0], ij[:, 1]] = ids
    return grid


def init_from_quads(path: str | Path) -> NetArtifact:
    """Import a regular quad net from an OBJ file (SPEC §5 ``--from-quads``).

    The grid comes from :func:`quad_grid`; the u-lines (geodesics) are the family with the
    smaller gpc angle defect (Prop. 2.7 (ii)) — the file's first family on a tie — and the
    orientation keeps the file's face winding (a swap of the families reverses the other
    index). A net written by ``dgpc`` reads back unchanged. A closed ring is cut at a seam
    (:func:`cut_ring`): the seam line appears twice, first and last, and ``data.init.seam``
    records it. DgpcError for a folded or collapsed net (see
    :func:`~dgpc_cli.metrics.degenerate.degeneracies`); a gpc defect above its limit only
    warns (``optimize --mode fit`` makes the net gpc).
    """
    path = Path(path)
    V, Q = read_quad_obj(path)
    seam = None
    if not (np.bincount(Q.ravel(), minlength=len(V)) == 1).any():
        Q, seam = cut_ring(Q, len(V), path)
        V = np.concatenate([V, V[seam]])
    grid = quad_grid(Q, path)
    m, n = grid.shape
    if m < 3 or n < 3:
        raise DgpcError(f"the quad net is {m} x {n}; a net needs at least 3 x 3", source=path)
    f = V[grid]
    swapped = np.transpose(f, (1, 0, 2))[:, ::-1]
    d_keep, d_swap = gpc_angle_defect_max(f), gpc_angle_defect_max(swapped)
    swap = d_keep is not None and d_swap is not None and d_swap < 0.5 * d_keep
    if swap:
        f = np.ascontiguousarray(swapped)
    log.info("%s: %d x %d quad net; geodesics along the file's %s family (gpc defect %.3g vs "
             "%.3g)", path, m, n, "second" if swap else "first", d_keep or 0.0, d_swap or 0.0)
    data = {"init": {"method": "from-quads", "families_swapped": bool(swap),
                     "gpc_angle_defect": {"first": d_keep, "second": d_swap}}}
    if seam is not None:
        line = "column" if np.array_equal(f[:, 0], f[:, -1]) else "row"
        data["init"]["seam"] = {"closed": True, "line": line,
                                "file_vertices": (seam + 1).tolist()}
        log.info("%s: a closed ring, cut at the seam through file vertices %d..%d (the %s "
                 "appears first and last)", path, seam[0] + 1, seam[-1] + 1, line)
    found = degeneracies(f, gpc_limit=None)
    if found:
        raise DgpcError(f"degenerate quad net (folded or collapsed): {found.message()}",
                        source=path)
    defect = d_swap if swap else d_keep
    if defect is not None and defect > GPC_LIMIT:
        log.warning("%s: gpc angle defect %.3g rad (above %g): far from geodesic parallel "
                    "coordinates; `optimize --mode fit` makes it a gpc net", path, defect,
                    GPC_LIMIT)
    return NetArtifact(f=np.asarray(f, dtype=float),
                       parameters={"method": "from-quads"}, data=data)
