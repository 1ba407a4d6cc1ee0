"""``dgpc init`` on a reference triangle mesh (SPEC §5): geodesic parallel coordinates traced
from a base curve, or a planar grid projected along a direction.

``--method geodesic`` follows the smooth definition of geodesic parallel coordinates (paper
Def. 2.1, §2.1): the u-lines are geodesics shot orthogonally from a base curve (the section of
the mesh by the plane through its area centroid orthogonal to the direction, or a boundary
curve), sampled at equal arc length, so the v-lines are geodesic parallels and ``optimize``
only polishes (§3.2 Fig. 8, §6.2.5: the paper needs "a sensible initial guess"). Geodesics that
leave the mesh are trimmed to the largest rectangle of the grid whose points all lie on the
mesh.

Both builders return a :class:`MeshGrid`: the net, the parameters of its rows and columns, and
how to make it again over a smaller rectangle of them (``layout.choice`` shrinks a
degenerate net that way).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.rectangle import largest_band, largest_rectangle
from dgpc_cli.geodesics.section import SectionCurve, plane_section, sample_curve
from dgpc_cli.geodesics.tracing import (
    MeshGeodesics,
    face_normals,
    plane_axes,
    principal_frame,
    sample_geodesic,
)
from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.layout.net_size import check_net_size

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
#: Default number of columns when neither --cols nor --edge-length is given.
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
                        "at least 3 (lower --edge-length)", source=option)


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
    source = "--edge-length" if spacing is not None else "--rows/--cols"
    check_net_size(m, n, source, "use a larger --edge-length" if spacing is not None
                   else "use fewer --rows or --cols")


def rotated(d: np.ndarray, axis: np.ndarray, degrees: float) -> np.ndarray:
    """``d (3,)`` turned by ``degrees`` about the unit ``axis`` (Rodrigues)."""
    a = math.radians(degrees)
    return (d * math.cos(a) + np.cross(axis, d) * math.sin(a)
            + axis * float(axis @ d) * (1 - math.cos(a)))


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


@dataclass
class MeshGrid:
    """A net made on a mesh: ``net``, the parameter of every row ``u (m,)`` and column
    ``v (n,)`` (arc lengths along the geodesics and the base curve, or plane coordinates), a
    ``label`` for messages (``"section 90°"``, ``"boundary b2"``), ``remake(u0, u1, v0, v1)``
    that makes the net again over that rectangle of the parameters (same --rows/--cols or
    --edge-length settings), and whether the net is meant to be gpc already (``traced``: geodesics
    traced on the mesh; a projected grid is not, ``optimize --mode fit`` makes it so)."""

    net: NetArtifact
    u: np.ndarray
    v: np.ndarray
    label: str
    remake: Callable[[float, float, float, float], MeshGrid]
    traced: bool = True


@dataclass
class MeshTracing:
    """What tracing geodesics on a mesh needs, made once for every net traced on it: the
    geodesic tracer, the face normals, whether the mesh has a boundary and its principal frame
    ``(centre, axes)``."""

    tracer: MeshGeodesics
    normals: np.ndarray
    bounded: bool
    frame: tuple[np.ndarray, np.ndarray]

    @classmethod
    def of(cls, mesh: ReferenceMesh) -> MeshTracing:
        V, F = mesh.vertices, mesh.faces
        return cls(MeshGeodesics(V, F), face_normals(V, F)[0], _has_boundary(F),
                   principal_frame(V, F))


class _Fan:
    """Geodesics shot orthogonally from a base ``curve`` on ``mesh`` (tracing state)."""

    def __init__(self, mesh: ReferenceMesh, curve: SectionCurve, reach: float,
                 tracing: MeshTracing):
        self.mesh, self.curve, self.reach = mesh, curve, reach
        self.normals, self.tracer = tracing.normals, tracing.tracer

    def band(self, want: int | None):
        """Columns ``t0..t1`` on the base curve and the geodesic range ``[-B, A]`` of the
        largest rectangle on the mesh, found on a probing fan and refined at its ends; and the
        number of probe columns."""
        curve, L = self.curve, self.curve.length
        probe = int(np.clip(PROBE_FACTOR * (want or DEFAULT_COLS), PROBE_MIN, PROBE_MAX))
        lo, hi = (0.0, L * (1 - 1.0 / probe)) if curve.closed else (END_INSET * L,
                                                                    (1 - END_INSET) * L)
        t_probe = np.linspace(lo, hi, probe)
        pts, fcs, u = _base_seeds(curve, t_probe, self.normals)
        _, _, ahead, behind = self.tracer.fan(pts, fcs, u, self.reach)
        band = largest_band(t_probe, ahead, behind)
        if band is None:
            raise DgpcError("no geodesic from the base curve stays on the mesh",
                            source=self.mesh.path)
        i, j, A, B = band
        t0, t1 = float(t_probe[i]), float(t_probe[j])
        # push each end of the band out towards the next probe column as far as its geodesic
        # still spans [-B, A] (bisection): the net then reaches the mesh's boundary closely
        if i > 0:
            t0, A, B = _refine_end(curve, self.normals, self.tracer, self.reach, t0,
                                   float(t_probe[i - 1]), A, B)
        if j < probe - 1:
            t1, A, B = _refine_end(curve, self.normals, self.tracer, self.reach, t1,
                                   float(t_probe[j + 1]), A, B)
        return t0, t1, A, B, probe

    def net(self, t0, t1, s0, s1, rows, cols, spacing):
        """Columns at ``t0..t1`` (``cols`` of them or at ``spacing``), their geodesics sampled at
        ``rows`` common arc lengths in ``[s0, s1]`` (default: square quads); ``(f, s, t)``."""
        want = cols if cols is not None else (DEFAULT_COLS if spacing is None else None)
        _check_size(want, rows, spacing, t1 - t0, s1 - s0)
        t = _positions(t0, t1, want, spacing)
        _check_count(len(t), "columns", "--edge-length")
        pts, fcs, u = _base_seeds(self.curve, t, self.normals)
        forward, backward, ahead, behind = self.tracer.fan(pts, fcs, u, self.reach)
        s0, s1 = max(s0, -float(behind.min())), min(s1, float(ahead.min()))
        if s1 - s0 <= 0:
            raise DgpcError("the geodesics from the base curve leave the mesh at once",
                            source=self.mesh.path)
        if rows is None and spacing is None:
            rows = max(3, int(round((s1 - s0) / ((t1 - t0) / (len(t) - 1)))) + 1)
        s = _positions(s0, s1, rows, spacing if rows is None else None)
        _check_count(len(s), "rows", "--edge-length")
        f = np.stack([sample_geodesic(fw, bw, s) for fw, bw in zip(forward, backward,
                                                                     strict=True)], axis=1)
        return f, s, t


def init_geodesic(mesh: ReferenceMesh, *, base: SectionCurve | None = None,
                  base_name: str | None = None, direction=None, angle: float = 0.0,
                  rows: int | None = None, cols: int | None = None,
                  spacing: float | None = None,
                  tracing: MeshTracing | None = None) -> MeshGrid:
    """A net of geodesic parallel coordinates on ``mesh`` (SPEC §5 ``--method geodesic``).

    Base curve: ``base`` (a boundary curve named ``base_name``, oriented with the mesh on its
    right, see :mod:`dgpc_cli.geodesics.boundary`), else the longest piece of the section by
    the plane through the area centroid orthogonal to ``direction`` (default: the longest
    principal axis) turned by ``angle`` degrees about the normal axis (the shortest principal
    axis). From ``n`` points at equal arc length on it, geodesics are traced both ways
    orthogonally to it (potpourri3d); ``m`` points at equal arc length (a common step) on each.
    Columns and the geodesic range are the largest rectangle of the grid on the mesh, found on
    a finer probing fan. ``rows`` default: square quads; ``cols`` default:
    :data:`DEFAULT_COLS`; ``spacing`` (model units) replaces ``cols`` (and ``rows`` when that is
    not given). On a closed mesh the geodesics are cut at the mesh's extent along the
    direction, each side of the plane. ``tracing``: :meth:`MeshTracing.of` the mesh, when
    several nets are traced on it.
    """
    V = mesh.vertices
    tracing = MeshTracing.of(mesh) if tracing is None else tracing
    centre, axes = tracing.frame
    record: dict = {"method": "geodesic", "centroid": centre.tolist()}
    if base is None:
        d = axes[:, 0] if direction is None else _unit(direction)
        if angle:
            d = rotated(d, axes[:, 2], angle)
        curve = _base_curve(mesh, centre, d)
        label = f"section {angle:g}°" if direction is None else "section"
        record.update(base="section", direction=d.tolist(), angle=angle)
    else:
        curve, d = base, None
        label = f"boundary {base_name}"
        record.update(base="boundary", base_name=base_name)
    if tracing.bounded or d is None:
        reach = 4.0 * mesh.bbox_diagonal
    else:
        heights = (V - centre) @ d
        reach = float(max(heights.max(), -heights.min()))
        log.info("closed mesh: geodesics cut at %.6g each side of the base plane", reach)
    fan = _Fan(mesh, curve, reach, tracing)
    want = cols if cols is not None else (DEFAULT_COLS if spacing is None else None)
    t0, t1, A, B, probe = fan.band(want)
    record.update(base_curve_length=curve.length, base_curve_closed=curve.closed,
                  probe_columns=probe)
    parameters = {"method": "geodesic", "direction": None if d is None else d.tolist(),
                  "rows": rows, "cols": cols, "spacing": spacing}

    def make(s0, s1, c0, c1) -> MeshGrid:
        f, s, t = fan.net(c0, c1, s0, s1, rows, cols, spacing)
        log.info("geodesic init (%s): base curve %.6g long (columns at %.6g..%.6g), "
                 "geodesics %.6g..%.6g, net %d x %d", label, curve.length, t[0], t[-1], s[0],
                 s[-1], *f.shape[:2])
        data = {"init": {**record, "base_curve_range": [float(t[0]), float(t[-1])],
                         "geodesic_range": [float(s[0]), float(s[-1])]}}
        return MeshGrid(NetArtifact(f=f, parameters=dict(parameters), data=data), s, t, label,
                        make)

    return make(-B, A, t0, t1)


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


def init_project(mesh: ReferenceMesh, *, direction=None, angle: float = 0.0,
                 rows: int | None = None, cols: int | None = None,
                 spacing: float | None = None) -> MeshGrid:
    """A planar grid projected onto ``mesh`` along ``direction`` (SPEC §5 ``--method project``):
    rays along −direction from above the mesh, first hits (the side the direction points to).

    The grid lies in the plane orthogonal to the direction (default: the shortest principal
    axis, the mesh's overall normal), u along the longest principal axis of the projected
    surface turned by ``angle`` degrees about the direction, v across (so the net normal points
    along the direction); it is the largest rectangle of a finer probing grid whose rays all
    hit, then ``rows × cols`` points (or ``spacing``) in it. The net is not yet geodesic:
    ``optimize --mode fit`` makes it so.
    """
    import igl

    V, F = mesh.vertices, mesh.faces
    d = principal_frame(V, F)[1][:, 2] if direction is None else _unit(direction)
    c, e1, e2 = plane_axes(V, F, d)
    if angle:
        e1 = rotated(e1, d, angle)
        e2 = np.cross(d, e1)
    x, y, h = (V - c) @ e1, (V - c) @ e2, (V - c) @ d
    above = c + (h.max() + 0.1 * mesh.bbox_diagonal) * d
    tree = igl.AABB()
    tree.init(V, F)

    def rays(xs, ys):
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        return above + X[..., None] * e1 + Y[..., None] * e2

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
    parameters = {"method": "project", "direction": d.tolist(), "rows": rows, "cols": cols,
                  "spacing": spacing}
    label = f"project {angle:g}°"

    def make(x0, x1, y0, y1) -> MeshGrid | None:
        ncols = cols if cols is not None else (DEFAULT_COLS if spacing is None else None)
        _check_size(ncols, rows, spacing, y1 - y0, x1 - x0)
        gy = _positions(y0, y1, ncols, spacing)
        want_r = rows
        if want_r is None and spacing is None:
            want_r = max(3, int(round((x1 - x0) / ((y1 - y0) / (len(gy) - 1)))) + 1)
        gx = _positions(x0, x1, want_r, spacing if want_r is None else None)
        _check_count(len(gx), "rows", "--edge-length")
        _check_count(len(gy), "columns", "--edge-length")
        P, ok = _cast(mesh, tree, rays(gx, gy).reshape(-1, 3), d)
        if not ok.all():
            return None
        f = P.reshape(len(gx), len(gy), 3)
        log.info("project init (%s): grid %.6g x %.6g in the plane, net %d x %d", label,
                 x1 - x0, y1 - y0, *f.shape[:2])
        data = {"init": {"method": "project", "direction": d.tolist(), "angle": angle,
                         "centroid": c.tolist(), "plane_axes": [e1.tolist(), e2.tolist()],
                         "plane_range": [[float(x0), float(x1)], [float(y0), float(y1)]],
                         "probe_grid": res}}
        return MeshGrid(NetArtifact(f=f, parameters=dict(parameters), data=data), gx, gy,
                        label, make, traced=False)

    for shrink in range(6):  # final rays between probe rays may miss: shrink by a probe step
        x0, x1 = xs[min(r0 + shrink, r1)], xs[max(r1 - shrink, r0)]
        y0, y1 = ys[min(c0 + shrink, c1)], ys[max(c1 - shrink, c0)]
        if x1 <= x0 or y1 <= y0:
            break
        grid = make(x0, x1, y0, y1)
        if grid is not None:
            return grid
    raise DgpcError("the projected grid does not stay on the mesh (its outline is too ragged)",
                    source=mesh.path)
