"""Boundary curves of a reference mesh as base curves of ``init --method geodesic`` (SPEC §5:
"a base curve ... or a boundary").

The boundary loops are cut at their corners (where the boundary turns by more than
:data:`CORNER_ANGLE` within the surface) into curves: a roof with one curved and three straight
edges has four, a dome cut by a plane two. Each curve is oriented with the mesh on its right,
so that the u-direction ``t × n`` of a base point (see ``layout.grids``) points into the
mesh, and named ``b1, b2, …`` by decreasing length.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.geodesics.extension import boundary_edges, chained
from dgpc_cli.geodesics.section import SectionCurve
from dgpc_cli.geodesics.tracing import face_normals

#: A boundary vertex where the boundary turns by more than this (radians, within the tangent
#: plane) is a corner between two boundary curves.
CORNER_ANGLE = np.radians(40.0)


@dataclass(frozen=True)
class BoundaryCurve:
    """A named boundary curve: ``curve`` (points, the face of every segment, closed or not;
    the mesh lies on its right), the ``loop`` it belongs to (0: the longest loop) and its
    mesh ``vertices (k,)``."""

    name: str
    curve: SectionCurve
    loop: int
    vertices: np.ndarray

    @property
    def length(self) -> float:
        return self.curve.length


def boundary_curves(vertices: np.ndarray, faces: np.ndarray,
                    corner_angle: float = CORNER_ANGLE) -> list[BoundaryCurve]:
    """The boundary curves of the mesh ``vertices (k, 3)``, ``faces (t, 3)`` (see the module),
    longest first; empty for a closed mesh."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    edges, face_of = boundary_edges(F)
    if len(edges) == 0:
        return []
    normals, _ = face_normals(V, F)
    loops = sorted(chained(edges), key=lambda loop: -float(np.linalg.norm(
        V[edges[loop, 1]] - V[edges[loop, 0]], axis=1).sum()))
    pieces = []
    for k, loop in enumerate(loops):
        e = edges[loop]
        d = V[e[:, 1]] - V[e[:, 0]]
        n = normals[face_of[loop]]
        # turning at the start vertex of each edge: from the previous edge to this one,
        # measured in the plane of the face of this edge
        prev = np.roll(d, 1, axis=0)
        prev = prev - np.sum(prev * n, axis=1, keepdims=True) * n
        here = d - np.sum(d * n, axis=1, keepdims=True) * n
        turn = np.arctan2(np.linalg.norm(np.cross(prev, here), axis=1),
                          np.sum(prev * here, axis=1))
        corners = np.flatnonzero(turn > corner_angle)
        closed_loop = e[-1, 1] == e[0, 0]
        if not closed_loop:
            corners = np.union1d(corners, [0])
        if corners.size == 0:
            runs = [np.arange(len(loop))]
        else:
            order = np.roll(np.arange(len(loop)), -int(corners[0]))
            runs = np.split(order, np.flatnonzero(np.isin(order, corners))[1:])
        for run in runs:
            ids = np.append(e[run, 0], e[run[-1], 1])
            closed = corners.size == 0
            # reversed: the mesh on the right of the curve
            pieces.append((k, ids[::-1], face_of[loop][run][::-1], closed))
    pieces.sort(key=lambda p: (-float(np.linalg.norm(np.diff(V[p[1]], axis=0), axis=1).sum()),
                               int(p[1].min())))
    return [BoundaryCurve(name=f"b{i + 1}",
                          curve=SectionCurve(points=V[ids], faces=fcs, closed=closed),
                          loop=k, vertices=ids)
            for i, (k, ids, fcs, closed) in enumerate(pieces)]


def describe(curves: list[BoundaryCurve]) -> str:
    """``"b1 (20 long, loop 0), b2 (…)"`` for messages."""
    return ", ".join(f"{c.name} ({c.length:.4g} long, loop {c.loop})" for c in curves)


def relocated(curve: SectionCurve, vertices: np.ndarray, faces: np.ndarray) -> SectionCurve:
    """``curve`` (drawn on another triangulation of the same surface: a patch cut from a mesh)
    with the faces of ``vertices, faces`` nearest its segments' midpoints (libigl AABB)."""
    import igl

    mid = np.ascontiguousarray(0.5 * (curve.points[1:] + curve.points[:-1]))
    found = igl.point_mesh_squared_distance(mid, np.ascontiguousarray(vertices, dtype=float),
                                            np.ascontiguousarray(faces, dtype=np.int64))[1]
    return SectionCurve(points=curve.points, faces=np.asarray(found, np.int64),
                        closed=curve.closed)


def prolonged(curve: SectionCurve, vertices: np.ndarray, faces: np.ndarray,
              length: float, tracer=None) -> SectionCurve:
    """The open ``curve`` on the mesh ``vertices, faces`` continued at both ends by geodesics
    (potpourri3d) along its end tangents, each up to ``length`` long: a boundary curve carried
    on into the continuation of ``init --extend`` (its first-order prolongation, as the rings
    of :func:`~dgpc_cli.geodesics.extension.extend_mesh` continue the surface). The faces of the
    new segments are those nearest their midpoints (libigl AABB). ``tracer``: a
    :class:`~dgpc_cli.geodesics.tracing.MeshGeodesics` of the mesh already made."""
    import igl

    from dgpc_cli.geodesics.tracing import MeshGeodesics

    if curve.closed or length <= 0:
        return curve
    V = np.ascontiguousarray(vertices, dtype=float)
    F = np.ascontiguousarray(faces, dtype=np.int64)
    tracer = MeshGeodesics(V, F) if tracer is None else tracer
    normals, _ = face_normals(V, F)
    P = curve.points

    def trace(point, face, direction):
        n = normals[face]
        direction = direction - (direction @ n) * n
        bary = tracer.barycentric(point[None], np.array([face]))[0]
        return tracer.trace(face, bary, direction / np.linalg.norm(direction), length)

    def faces_of(polyline):
        polyline = polyline[np.concatenate([[True], np.any(np.diff(polyline, axis=0), 1)])]
        if len(polyline) < 2:
            return polyline[:0], np.zeros(0, dtype=np.int64)
        mid = np.ascontiguousarray(0.5 * (polyline[1:] + polyline[:-1]))
        return polyline, np.asarray(igl.point_mesh_squared_distance(mid, V, F)[1], np.int64)

    head, head_faces = faces_of(trace(P[0], curve.faces[0], P[0] - P[1])[::-1])
    tail, tail_faces = faces_of(trace(P[-1], curve.faces[-1], P[-1] - P[-2]))
    points = np.concatenate([head[:-1], P, tail[1:]])
    fcs = np.concatenate([head_faces, curve.faces, tail_faces])
    return SectionCurve(points=points, faces=fcs, closed=False)
