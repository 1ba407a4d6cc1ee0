"""``dgpc init`` on a reference triangle mesh (SPEC §5): geodesic parallel coordinates traced
from a base curve, a planar grid projected along a direction, or an imported quad net.

``--method geodesic`` follows the smooth definition of geodesic parallel coordinates (paper
Def. 2.1, §2.1): the u-lines are geodesics shot orthogonally from a base curve (the section of
the mesh by the plane through its area centroid orthogonal to the direction), sampled at equal
arc length, so the v-lines are geodesic parallels and ``optimize`` only polishes (§3.2 Fig. 8,
§6.2.5: the paper needs "a sensible initial guess"). Geodesics that leave the mesh are trimmed
to the largest rectangle of the grid whose points all lie on the mesh.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.rectangle import largest_band, largest_rectangle
from dgpc_cli.geodesics.section import plane_section, sample_curve
from dgpc_cli.geodesics.tracing import (
    MeshGeodesics,
    face_normals,
    plane_axes,
    principal_frame,
    sample_geodesic,
)
from dgpc_cli.io.coordinates import bad_rows, coordinate_problem
from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.metrics.residuals import gpc_angle_defect_max
from dgpc_cli.stages.net_size import check_net_size

log = logging.getLogger(__name__)

#: Columns of the probing fan per requested column (and its bounds).
PROBE_FACTOR, PROBE_MIN, PROBE_MAX = 4, 101, 401
#: Inset of the base curve's ends, relative to its length (a geodesic started exactly on the
#: boundary may leave the mesh at once).
END_INSET = 1e-7
#: Bisection steps that push the ends of the column band towards the boundary.
REFINE_STEPS = 30
#: Loss of geodesic range, relative, accepted for each step of the band's ends towards the boundary.
REFINE_SLACK = 1e-6
#: Default number of columns when neither --cols nor --spacing is given.
DEFAULT_COLS = 21


def _unit(direction, source="--direction") -> np.ndarray:
    d = np.asarray(direction, dtype=float).reshape(-1)
    if d.shape != (3,) or not np.isfinite(d).all() or np.linalg.norm(d) == 0:
        raise DgpcError("a direction is three numbers x,y,z, not all zero", source=source)
    return d / np.linalg.norm(d)


def _has_boundary(faces: np.ndarray) -> bool:
    key = np.sort(np.asarray(faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(key, axis=0, return_counts=True)
    return bool((counts == 1).any())


def _positions(lo: float, hi: float, count: int | None, spacing: float | None):
    """Equally spaced positions in ``[lo, hi]``: ``count`` of them spanning it, or as many as
    fit at ``spacing``, centred."""
    if count is None:
        count = int(math.floor((hi - lo) / spacing + 1e-9)) + 1
        start = lo + 0.5 * ((hi - lo) - (count - 1) * spacing)
        return start + spacing * np.arange(count)
    return np.linspace(lo, hi, count)


def _check_count(count: int, what: str, option: str):
    if count < 3:
        raise DgpcError(f"the usable part of the mesh gives only {count} {what}; a net needs "
                        "at least 3 (lower --spacing)", source=option)


def _check_size(cols: int | None, rows: int | None, spacing: float | None, across: float,
                along: float) -> None:
    """Refuse a net beyond the memory limit before its positions are made: ``cols`` columns
    over the length ``across`` (or as many as fit at ``spacing``), ``rows`` rows over the length
    ``along`` (or at ``spacing``, or square quads)."""
    n = cols if cols is not None else across / spacing + 1
    if rows is not None:
        m = rows
    elif spacing is not None:
        m = along / spacing + 1
    else:
        m = along / (across / max(n - 1, 1)) + 1 if across > 0 else 1
    source = "--spacing" if spacing is not None else "--rows/--cols"
    check_net_size(m, n, source, "use a larger --spacing" if spacing is not None
                   else "use fewer --rows or --cols")


def _base_curve(mesh: ReferenceMesh, centre, direction):
    pieces = plane_section(mesh.vertices, mesh.faces, centre, direction)
    if not pieces or pieces[0].length <= 0:
        raise DgpcError("the plane through the area centroid orthogonal to the direction does "
                        "not cut the mesh", source="--direction")
    if len(pieces) > 1:
        log.info("plane section has %d pieces; the longest (%.6g) is the base curve",
                 len(pieces), pieces[0].length)
    return pieces[0]


def _base_seeds(curve, s, normals):
    """Base points at arc lengths ``s``, their faces and unit u-directions ``t × n`` (so that
    the net normal T^u × T^v agrees with the mesh normal)."""
    points, faces, tangent = sample_curve(curve, s)
    n = normals[faces]
    tangent = tangent - np.sum(tangent * n, axis=1, keepdims=True) * n
    u = np.cross(tangent, n)
    return points, faces, u / np.linalg.norm(u, axis=1, keepdims=True)


def _refine_end(curve, normals, tracer, reach, t_in, t_out, A, B, steps=REFINE_STEPS):
    """The base-curve position nearest ``t_out`` on the way from ``t_in`` whose geodesic still
    reaches nearly ``A`` ahead and ``B`` behind (within :data:`REFINE_SLACK` of ``A + B``;
    bisection), and the range ``(t, A, B)`` it leaves."""
    slack = REFINE_SLACK * (A + B)
    for _ in range(steps):
        t = 0.5 * (t_in + t_out)
        pts, fcs, u = _base_seeds(curve, np.array([t]), normals)
        _, _, ahead, behind = tracer.fan(pts, fcs, u, reach)
        if ahead[0] >= A - slack and behind[0] >= B - slack:
            t_in, A, B = t, min(A, float(ahead[0])), min(B, float(behind[0]))
        else:
            t_out = t
    return t_in, A, B


def init_geodesic(mesh: ReferenceMesh, *, direction=None, rows: int | None = None,
                  cols: int | None = None, spacing: float | None = None) -> NetArtifact:
    """A net of geodesic parallel coordinates on ``mesh`` (SPEC §5 ``--method geodesic``).

    Base curve: the longest piece of the section by the plane through the area centroid
    orthogonal to ``direction`` (default: the longest principal axis). From ``n`` points at
    equal arc length on it, geodesics are traced both ways orthogonally to it (potpourri3d);
    ``m`` points at equal arc length (a common step) on each. Columns and the geodesic range are
    the largest rectangle of the grid on the mesh, found on a finer probing fan. ``rows``
    default: square quads; ``cols`` default: :data:`DEFAULT_COLS`; ``spacing`` (model units)
    replaces ``cols`` (and ``rows`` when that is not given). On a closed mesh the geodesics are
    cut at the mesh's extent along the direction, each side of the plane.
    """
    V, F = mesh.vertices, mesh.faces
    centre, axes = principal_frame(V, F)
    d = axes[:, 0] if direction is None else _unit(direction)
    curve = _base_curve(mesh, centre, d)
    normals, _ = face_normals(V, F)
    heights = (V - centre) @ d
    if _has_boundary(F):
        reach = 4.0 * mesh.bbox_diagonal
    else:
        reach = float(max(heights.max(), -heights.min()))
        log.info("closed mesh: geodesics cut at %.6g each side of the base plane", reach)
    L = curve.length
    tracer = MeshGeodesics(V, F)

    want = cols if cols is not None else (DEFAULT_COLS if spacing is None else None)
    probe = int(np.clip(PROBE_FACTOR * (want or DEFAULT_COLS), PROBE_MIN, PROBE_MAX))
    lo, hi = (0.0, L * (1 - 1.0 / probe)) if curve.closed else (END_INSET * L,
                                                                (1 - END_INSET) * L)
    t_probe = np.linspace(lo, hi, probe)
    pts, fcs, u = _base_seeds(curve, t_probe, normals)
    _, _, ahead, behind = tracer.fan(pts, fcs, u, reach)
    band = largest_band(t_probe, ahead, behind)
    if band is None:
        raise DgpcError("no geodesic from the base curve stays on the mesh", source=mesh.path)
    i, j, A, B = band
    t0, t1 = float(t_probe[i]), float(t_probe[j])
    # push each end of the band out towards the next probe column as far as its geodesic still
    # spans [-B, A] (bisection): the net then reaches the mesh's boundary closely
    if i > 0:
        t0, A, B = _refine_end(curve, normals, tracer, reach, t0, float(t_probe[i - 1]),
                               A, B)
    if j < probe - 1:
        t1, A, B = _refine_end(curve, normals, tracer, reach, t1, float(t_probe[j + 1]),
                               A, B)
    _check_size(want, rows, spacing, t1 - t0, A + B)
    t = _positions(t0, t1, want, spacing)
    _check_count(len(t), "columns", "--spacing")

    pts, fcs, u = _base_seeds(curve, t, normals)
    forward, backward, ahead, behind = tracer.fan(pts, fcs, u, reach)
    A, B = min(A, float(ahead.min())), min(B, float(behind.min()))
    if A + B <= 0:
        raise DgpcError("the geodesics from the base curve leave the mesh at once",
                        source=mesh.path)
    if rows is None and spacing is None:
        rows = max(3, int(round((A + B) / ((t1 - t0) / (len(t) - 1)))) + 1)
    s = _positions(-B, A, rows, spacing if rows is None else None)
    _check_count(len(s), "rows", "--spacing")
    f = np.stack([sample_geodesic(fw, bw, s) for fw, bw in zip(forward, backward,
                                                                 strict=True)], axis=1)
    log.info("geodesic init: base curve %.6g long (columns at %.6g..%.6g), geodesics "
             "%.6g..%.6g, net %d x %d", L, t0, t1, -B, A, *f.shape[:2])
    data = {"init": {"method": "geodesic", "direction": d.tolist(),
                     "centroid": centre.tolist(), "base_curve_length": L,
                     "base_curve_closed": curve.closed, "base_curve_range": [t0, t1],
                     "geodesic_range": [-B, A], "probe_columns": probe}}
    parameters = {"method": "geodesic", "direction": d.tolist(), "rows": rows, "cols": cols,
                  "spacing": spacing}
    return NetArtifact(f=f, parameters=parameters, data=data)


def _cast(mesh: ReferenceMesh, tree, origins: np.ndarray, d: np.ndarray):
    """First hits of rays ``origins (k, 3)`` along ``-d``: points ``(k, 3)`` and a hit mask."""
    dirs = np.broadcast_to(-d, origins.shape).copy()
    fid, _, _ = tree.intersect_ray_first(mesh.vertices, mesh.faces,
                                         np.ascontiguousarray(origins), dirs)
    fid = np.asarray(fid, dtype=np.int64)
    hit = fid >= 0
    normals, _ = face_normals(mesh.vertices, mesh.faces)
    nf = normals[np.where(hit, fid, 0)]
    v0 = mesh.vertices[mesh.faces[np.where(hit, fid, 0), 0]]
    denom = np.sum(dirs * nf, axis=1)
    ok = hit & (np.abs(denom) > 1e-300)
    t = np.where(ok, np.sum((v0 - origins) * nf, axis=1) / np.where(ok, denom, 1.0), np.nan)
    return origins + t[:, None] * dirs, ok


def init_project(mesh: ReferenceMesh, *, direction, rows: int | None = None,
                 cols: int | None = None, spacing: float | None = None) -> NetArtifact:
    """A planar grid projected onto ``mesh`` along ``direction`` (SPEC §5 ``--method project``):
    rays along −direction from above the mesh, first hits (the side the direction points to).

    The grid lies in the plane orthogonal to the direction, u along the longest principal axis
    of the projected surface, v across (so the net normal points along the direction); it is
    the largest rectangle of a finer probing grid whose rays all hit, then ``rows × cols``
    points (or ``spacing``) in it. The net is not yet geodesic: ``optimize --mode fit`` makes
    it so.
    """
    import igl

    d = _unit(direction)
    V, F = mesh.vertices, mesh.faces
    c, e1, e2 = plane_axes(V, F, d)
    x, y, h = (V - c) @ e1, (V - c) @ e2, (V - c) @ d
    above = c + (h.max() + 0.1 * mesh.bbox_diagonal) * d
    tree = igl.AABB()
    tree.init(V, F)

    def rays(xs, ys):
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        return above + X[..., None] * e1 + Y[..., None] * e2

    want_r = rows
    res = int(np.clip(PROBE_FACTOR * max(rows or 0, cols or 0, DEFAULT_COLS), PROBE_MIN,
                      PROBE_MAX))
    span = max(np.ptp(x), np.ptp(y))
    inset = END_INSET * span
    xs = np.linspace(x.min() + inset, x.max() - inset, res)
    ys = np.linspace(y.min() + inset, y.max() - inset, res)
    _, ok = _cast(mesh, tree, rays(xs, ys).reshape(-1, 3), d)
    rect = largest_rectangle(ok.reshape(res, res))
    if rect is None:
        raise DgpcError("no rectangle of the projected grid lies on the mesh", source=mesh.path)
    r0, r1, c0, c1 = rect
    for shrink in range(6):  # final rays between probe rays may miss: shrink by a probe step
        x0, x1 = xs[min(r0 + shrink, r1)], xs[max(r1 - shrink, r0)]
        y0, y1 = ys[min(c0 + shrink, c1)], ys[max(c1 - shrink, c0)]
        if x1 <= x0 or y1 <= y0:
            break
        ncols = cols if cols is not None else (DEFAULT_COLS if spacing is None else None)
        _check_size(ncols, want_r, spacing, y1 - y0, x1 - x0)
        gy = _positions(y0, y1, ncols, spacing)
        if want_r is None and spacing is None:
            want_r = max(3, int(round((x1 - x0) / ((y1 - y0) / (len(gy) - 1)))) + 1)
        gx = _positions(x0, x1, want_r, spacing if want_r is None else None)
        _check_count(len(gx), "rows", "--spacing")
        _check_count(len(gy), "columns", "--spacing")
        P, ok = _cast(mesh, tree, rays(gx, gy).reshape(-1, 3), d)
        if ok.all():
            f = P.reshape(len(gx), len(gy), 3)
            log.info("project init: grid %.6g x %.6g in the plane, net %d x %d", x1 - x0,
                     y1 - y0, *f.shape[:2])
            data = {"init": {"method": "project", "direction": d.tolist(),
                             "centroid": c.tolist(), "plane_axes": [e1.tolist(), e2.tolist()],
                             "plane_range": [[float(x0), float(x1)], [float(y0), float(y1)]],
                             "probe_grid": res}}
            parameters = {"method": "project", "direction": d.tolist(), "rows": rows,
                          "cols": cols, "spacing": spacing}
            return NetArtifact(f=f, parameters=parameters, data=data)
    raise DgpcError("the projected grid does not stay on the mesh (its outline is too ragged)",
                    source=mesh.path)


# --- an existing quad net ------------------------------------------------------------------

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
    index). A net written by ``dgpc`` reads back unchanged.
    """
    path = Path(path)
    V, Q = read_quad_obj(path)
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
    return NetArtifact(f=np.asarray(f, dtype=float),
                       parameters={"method": "from-quads"}, data=data)
