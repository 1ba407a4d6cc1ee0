"""Reference meshes (OBJ/PLY/STL/OFF) read through trimesh, cleaned, validated (SPEC §2, §5)."""

from __future__ import annotations

import hashlib
import io
import logging
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ..errors import DgpcError
from .bounded_read import read_regular
from .coordinates import bad_rows, coordinate_problem

log = logging.getLogger(__name__)

FORMATS = ("obj", "ply", "stl", "off")
#: The ``v`` and ``f`` lines of an OBJ (what follows the keyword).
_OBJ_VERTEX = re.compile(rb"^v (.*)$", re.MULTILINE)
_OBJ_FACE = re.compile(rb"^f (.*)$", re.MULTILINE)
#: Triangles thinner than this fraction of the bounding-box diagonal count as degenerate.
DEGENERATE_HEIGHT = 1e-10


@dataclass(frozen=True)
class ReferenceMesh:
    """A cleaned triangle mesh: ``vertices (k, 3)`` float64, ``faces (t, 3)`` int64, consistently
    wound; ``path`` and ``sha256`` of the file it came from."""

    vertices: np.ndarray
    faces: np.ndarray
    path: Path
    sha256: str

    @property
    def bbox_diagonal(self) -> float:
        """Length of the axis-aligned bounding-box diagonal."""
        return float(np.linalg.norm(self.vertices.max(axis=0) - self.vertices.min(axis=0)))


def _read(path: Path) -> bytes:
    """The mesh file's bytes: a regular file of at most 2 GiB (:mod:`.bounded_read`)."""
    return read_regular(path, "a mesh file")


def _plain_obj(data: bytes):
    """(vertices, faces) of an OBJ that holds only ``v x y z`` lines and triangles ``f i j k``
    of positive indices (besides comments, groups and the like), parsed by numpy at a fraction
    of trimesh's time; None for anything else (trimesh reads those)."""
    v = _OBJ_VERTEX.findall(data)
    f = _OBJ_FACE.findall(data)
    faces = b" ".join(f)
    if not v or not f or b"/" in faces or b"-" in faces:
        return None
    try:
        with warnings.catch_warnings():  # numpy 1.x warns where 2.x raises
            warnings.simplefilter("error", DeprecationWarning)
            vertices = np.fromstring(b" ".join(v), dtype=np.float64, sep=" ")
            faces = np.fromstring(faces, dtype=np.int64, sep=" ")
    except (ValueError, DeprecationWarning):
        return None
    if vertices.size != 3 * len(v) or faces.size != 3 * len(f):
        return None                      # colours after coordinates, polygons: trimesh
    return vertices.reshape(-1, 3), faces.reshape(-1, 3) - 1


def _parse(data: bytes, fmt: str, path: Path):
    """Raw (vertices, faces) via ``trimesh.load(..., force="mesh", process=False)`` (plain
    triangle OBJ files by :func:`_plain_obj`)."""
    if fmt == "obj" and b"\0" not in data[:4096]:
        plain = _plain_obj(data)
        if plain is not None:
            return plain
    import trimesh

    name = fmt.upper()
    if fmt in ("obj", "off"):  # text formats
        try:
            data.decode("utf-8")
        except UnicodeDecodeError:
            if b"\0" in data:
                raise DgpcError(f"not a mesh: binary data in a .{fmt} file", source=path) from None
            data = data.decode("latin-1").encode("utf-8")
    try:
        loaded = trimesh.load(io.BytesIO(data), file_type=fmt, force="mesh", process=False)
    except Exception as e:  # trimesh raises anything from ValueError to IndexError
        detail = "unreadable data" if isinstance(e, ImportError) else f"{type(e).__name__}: {e}"
        raise DgpcError(f"cannot read as {name} mesh ({detail[:120]})", source=path) from None
    vertices = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))), dtype=np.int64)
    return vertices, faces


def consistent_winding(faces: np.ndarray) -> np.ndarray:
    """Faces ``(t, 3)`` re-wound so that neighbours agree (each manifold edge is traversed in
    opposite directions by its two faces); the lowest face of each connected patch keeps its
    orientation. Vectorized replacement for ``trimesh.repair.fix_winding`` (which needs
    networkx): parity of "same-direction" edges along a spanning forest of the face graph."""
    faces = np.asarray(faces, dtype=np.int64)
    t = len(faces)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    key = np.sort(directed, axis=1)
    forward = directed[:, 0] < directed[:, 1]
    n = np.int64(faces.max()) + 1 if faces.size else np.int64(1)
    edge = key[:, 0] * n + key[:, 1]                             # one int64 per edge
    order = np.argsort(edge, kind="stable")                      # half-edges by edge
    ordered = edge[order]
    start = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]])
    counts = np.diff(np.r_[start, ordered.size])                 # half-edges of each edge
    manifold = np.repeat(counts, counts) == 2
    pairs = order[manifold].reshape(-1, 2)  # the two half-edges of each manifold edge
    if len(pairs) == 0:
        return faces.copy()
    fa, fb = pairs[:, 0] // 3, pairs[:, 1] // 3
    same = forward[pairs[:, 0]] == forward[pairs[:, 1]]
    if not same.any():                      # already consistent: the forest would flip nothing
        return faces.copy()
    same = same.astype(np.float64)
    graph = sparse.coo_matrix((2.0 + same, (fa, fb)), shape=(t, t)).tocsr()
    forest = csgraph.minimum_spanning_tree(graph + graph.T)
    _, labels = csgraph.connected_components(forest, directed=False)
    roots = np.unique(labels, return_index=True)[1]
    dist = csgraph.dijkstra(forest, directed=False, indices=roots, min_only=True)
    flip = np.round(dist).astype(np.int64) % 2 == 1  # odd number of same-direction edges
    out = faces.copy()
    out[flip] = out[flip][:, ::-1]
    return out


def clean_mesh(vertices: np.ndarray, faces: np.ndarray):
    """Merge duplicate vertices, drop degenerate and duplicate faces and unused vertices, fix the
    winding consistently. ``vertices (k, 3)``, ``faces (t, 3)`` → cleaned copies."""
    import trimesh

    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=True)  # merges vertices
    diag = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0))) if len(mesh.vertices) else 0.0
    keep = mesh.nondegenerate_faces(height=DEGENERATE_HEIGHT * diag) & mesh.unique_faces()
    mesh.update_faces(keep)
    mesh.remove_unreferenced_vertices()
    return (np.ascontiguousarray(mesh.vertices, dtype=np.float64),
            np.ascontiguousarray(consistent_winding(mesh.faces), dtype=np.int64))


def check_manifold(vertices: np.ndarray, faces: np.ndarray, source,
                   raw_vertices: np.ndarray | None = None) -> None:
    """DgpcError naming ``source`` unless every edge of ``faces (t, 3)`` (consistently wound)
    borders at most two faces, in opposite directions, and no vertex is pinched
    (:func:`pinched_vertices`): the geodesic tracer needs a manifold, oriented surface.
    ``raw_vertices``: the vertices as the file lists them, to name a pinched vertex by its
    index there."""
    faces = np.asarray(faces, dtype=np.int64)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    n = np.int64(faces.max()) + 1 if faces.size else np.int64(1)
    # one int64 key per edge (as in consistent_winding): far faster than unique rows
    undirected = np.sort(directed, axis=1)
    _, first, counts = np.unique(undirected[:, 0] * n + undirected[:, 1], return_index=True,
                                 return_counts=True)
    if (counts > 2).any():
        edge = _edge(vertices, undirected[first], counts)
        raise DgpcError(f"not a manifold mesh: the edge {edge} borders {int(counts.max())} "
                        "faces (at most 2; remove the extra faces)", source=source)
    _, first, counts = np.unique(directed[:, 0] * n + directed[:, 1], return_index=True,
                                 return_counts=True)
    if (counts > 1).any():
        raise DgpcError(f"the mesh cannot be oriented consistently (a Möbius strip?): the "
                        f"edge {_edge(vertices, directed[first], counts)} runs the same way in "
                        "two faces", source=source)
    pinched = pinched_vertices(faces)
    if pinched.size:
        point = vertices[pinched[0]]
        where = ", ".join(f"{x:g}" for x in point)
        index = "" if raw_vertices is None else _file_index(raw_vertices, point)
        more = f" ({pinched.size} such vertices)" if pinched.size > 1 else ""
        raise DgpcError(f"not a manifold mesh: vertex {index}({where}) is where separate fans "
                        f"of faces touch (a bow-tie: two boundary loops or sheets meet at one "
                        f"point){more}; give each fan its own vertex, or remove a fan",
                        source=source)


def _file_index(raw_vertices: np.ndarray, point: np.ndarray) -> str:
    """``"N "``: the 1-based index in the file of the first vertex at ``point`` (as OBJ
    counts them), or ``""`` when none matches exactly."""
    match = np.flatnonzero(np.all(np.asarray(raw_vertices) == point, axis=1))
    return f"{int(match[0]) + 1} " if match.size else ""


def pinched_vertices(faces: np.ndarray) -> np.ndarray:
    """The vertices (indices, ascending) of ``faces (t, 3)`` where the surface is pinched (a
    "bow-tie": two fans of faces, or more, meet at the vertex and nowhere else, so that two
    boundary loops, or two sheets, run through it). ``faces`` must have manifold edges.

    The corners of the faces at each vertex are linked across every edge two faces share
    there; a vertex whose corners form more than one connected group is pinched. Vectorized:
    one connected-components pass over the 3t corners."""
    faces = np.asarray(faces, dtype=np.int64)
    t = len(faces)
    if t == 0:
        return np.zeros(0, dtype=np.int64)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)        # half-edge h of face h//3
    n = np.int64(faces.max()) + 1
    key = np.sort(directed, axis=1)
    order = np.argsort(key[:, 0] * n + key[:, 1], kind="stable")
    edge = (key[:, 0] * n + key[:, 1])[order]
    start = np.flatnonzero(np.r_[True, edge[1:] != edge[:-1]])
    counts = np.diff(np.r_[start, edge.size])
    pairs = order[np.repeat(counts, counts) == 2].reshape(-1, 2)  # the two half-edges
    corner = np.arange(3 * t).reshape(t, 3)                       # corner (face, slot)
    links = []
    for end in (0, 1):          # both ends of the shared edge: link the two faces' corners
        vertex = directed[pairs[:, 0], end]
        fa, fb = pairs[:, 0] // 3, pairs[:, 1] // 3
        ca = corner[fa, np.argmax(faces[fa] == vertex[:, None], axis=1)]
        cb = corner[fb, np.argmax(faces[fb] == vertex[:, None], axis=1)]
        links.append(np.stack([ca, cb], axis=1))
    links = np.concatenate(links) if links else np.zeros((0, 2), dtype=np.int64)
    graph = sparse.coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])),
                              shape=(3 * t, 3 * t))
    _, label = csgraph.connected_components(graph, directed=False)
    groups = np.unique(np.stack([faces.ravel(), label], axis=1), axis=0)[:, 0]
    vertex, fans = np.unique(groups, return_counts=True)
    return vertex[fans > 1]


def _edge(vertices, edges, counts) -> str:
    """The edge of ``edges`` with the largest count, by its end points."""
    a, b = (vertices[i] for i in edges[np.argmax(counts)])
    return "from ({}) to ({})".format(*(", ".join(f"{x:g}" for x in p) for p in (a, b)))


def face_components(faces: np.ndarray) -> np.ndarray:
    """Label ``(t,)`` of the connected piece (faces sharing vertices) of every face."""
    faces = np.asarray(faces, dtype=np.int64)
    k = int(faces.max()) + 1 if faces.size else 0
    rows = np.repeat(np.arange(len(faces)), 3)
    incidence = sparse.coo_matrix((np.ones(rows.size), (rows, faces.ravel())),
                                  shape=(len(faces), k)).tocsr()
    _, labels = csgraph.connected_components(incidence @ incidence.T, directed=False)
    return labels


def largest_piece(vertices: np.ndarray, faces: np.ndarray):
    """The connected piece of largest area: ``(vertices, faces, n_pieces)``, unused vertices
    dropped."""
    labels = face_components(faces)
    n_pieces = int(labels.max()) + 1
    if n_pieces == 1:
        return vertices, faces, 1
    from trimesh.triangles import area as triangle_areas

    area = triangle_areas(vertices[faces])
    keep = labels == int(np.argmax(np.bincount(labels, weights=area)))
    used, inverse = np.unique(faces[keep], return_inverse=True)
    return (np.ascontiguousarray(vertices[used]),
            np.ascontiguousarray(inverse.reshape(-1, 3).astype(np.int64)), n_pieces)


def load_mesh(path: str | Path, *, pieces: str = "all") -> ReferenceMesh:
    """Read a reference triangle mesh (OBJ, PLY, STL, OFF), cleaned as in :func:`clean_mesh`.

    ``pieces``: ``"all"`` keeps every connected piece, ``"one"`` rejects a mesh of several
    pieces, ``"largest"`` keeps the piece of largest area (``--largest-component``).

    DgpcError (one line, naming the file): missing or unreadable file, not a mesh, no faces,
    non-finite coordinates, fewer than 2 faces after cleaning, several pieces (``"one"``).
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise DgpcError(f"unsupported mesh format '{path.suffix}' (use OBJ, PLY, STL or OFF)",
                        source=path)
    data = _read(path)
    vertices, faces = _parse(data, fmt, path)
    if len(faces) == 0 or vertices.ndim != 2 or vertices.shape[1] != 3:
        raise DgpcError("not a surface mesh: no faces", source=path)
    bad = bad_rows(vertices)
    if bad.size:
        raise DgpcError(f"vertex {int(bad[0]) + 1} has {coordinate_problem(vertices[bad[0]])} "
                        f"({bad.size} such vertices)", source=path)
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise DgpcError("a face refers to a vertex that does not exist", source=path)
    n_raw, raw_vertices = len(faces), vertices
    vertices, faces = clean_mesh(vertices, faces)
    if pieces != "all" and len(faces):
        kept, kept_faces, n_pieces = largest_piece(vertices, faces)
        if n_pieces > 1 and pieces == "one":
            raise DgpcError(f"the mesh has {n_pieces} separate pieces; use "
                            "--largest-component to keep the largest", source=path)
        if n_pieces > 1:
            log.info("%s: kept the largest of %d pieces (%d of %d faces)", path, n_pieces,
                     len(kept_faces), len(faces))
        vertices, faces = kept, kept_faces
    if len(faces) < 2:
        raise DgpcError(f"needs at least 2 non-degenerate faces, has {len(faces)} "
                        f"(of {n_raw} before cleaning)", source=path)
    check_manifold(vertices, faces, path, raw_vertices)
    log.info("%s: %d vertices, %d faces (%d dropped)", path, len(vertices), len(faces),
             n_raw - len(faces))
    vertices.setflags(write=False)
    faces.setflags(write=False)
    return ReferenceMesh(vertices=vertices, faces=faces, path=path,
                         sha256=hashlib.sha256(data).hexdigest())


def write_mesh_obj(path: str | Path, vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """Deterministic OBJ bytes of a triangle mesh (``repr`` floats, 1-based faces); the object is
    named after ``path``'s stem. ``vertices (k, 3)``, ``faces (t, 3)``. Nothing is written."""
    from .. import __version__

    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError(f"expected vertices (k, 3) and faces (t, 3), got {vertices.shape} "
                         f"and {faces.shape}")
    if faces.size and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise ValueError("a face refers to a vertex that does not exist")
    lines = [f"# dgpc {__version__}", f"o {Path(path).stem or 'mesh'}"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a} {b} {c}" for a, b, c in (faces + 1).tolist()]
    return ("\n".join(lines) + "\n").encode("utf-8")
