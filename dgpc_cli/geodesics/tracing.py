"""Geodesics traced on a triangle mesh with potpourri3d's ``GeodesicTracer`` (SPEC §10), and
the principal frame of a mesh."""

from __future__ import annotations

import numpy as np


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals ``(t, 3)`` (right-hand rule of the winding) and areas ``(t,)`` of the faces."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    norm = np.linalg.norm(cross, axis=1)
    return cross / np.where(norm > 0, norm, 1.0)[:, None], 0.5 * norm


def _canonical_sign(axes: np.ndarray) -> np.ndarray:
    """Flip each column so that its largest-magnitude component is positive (determinism)."""
    k = np.argmax(np.abs(axes), axis=0)
    return axes * np.sign(axes[k, np.arange(axes.shape[1])])


def principal_frame(vertices: np.ndarray, faces: np.ndarray):
    """Area centroid ``c (3,)`` and principal axes ``(3, 3)`` (columns, by decreasing spread) of
    the surface: eigenvectors of the area-weighted covariance of the face centroids."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    _, area = face_normals(V, F)
    centroids = V[F].mean(axis=1)
    w = area / area.sum()
    c = w @ centroids
    d = centroids - c
    cov = (d * w[:, None]).T @ d
    evals, evecs = np.linalg.eigh(cov)
    return c, _canonical_sign(evecs[:, ::-1])


def plane_axes(vertices: np.ndarray, faces: np.ndarray, direction: np.ndarray):
    """``(c, e1, e2)``: area centroid and an orthonormal basis of the plane orthogonal to
    ``direction`` with ``e1`` the longest principal axis of the surface projected on the plane
    and ``e1 × e2 = direction``."""
    V, F = np.asarray(vertices, float), np.asarray(faces, np.int64)
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    _, area = face_normals(V, F)
    centroids = V[F].mean(axis=1)
    w = area / area.sum()
    c = w @ centroids
    p = (centroids - c) - np.outer((centroids - c) @ d, d)
    cov = (p * w[:, None]).T @ p
    evals, evecs = np.linalg.eigh(cov)
    e1 = _canonical_sign(evecs[:, [2]])[:, 0]
    e1 = e1 - (e1 @ d) * d
    e1 /= np.linalg.norm(e1)
    return c, e1, np.cross(d, e1)


class MeshGeodesics:
    """Straightest geodesics on a triangle mesh (potpourri3d ``GeodesicTracer``, which unfolds
    the triangles along the path, geometry-central's ``traceGeodesic``).

    A trace stops at the boundary or after the requested length.
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        import potpourri3d as pp3d

        self.vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self._tracer = pp3d.GeodesicTracer(self.vertices, self.faces)

    def barycentric(self, points: np.ndarray, face_ids: np.ndarray) -> np.ndarray:
        """Barycentric coordinates ``(k, 3)`` of ``points (k, 3)`` in their faces."""
        import igl

        T = self.vertices[self.faces[face_ids]]
        P = np.ascontiguousarray(points, dtype=np.float64)
        bary = igl.barycentric_coordinates(P, np.ascontiguousarray(T[:, 0]),
                                           np.ascontiguousarray(T[:, 1]),
                                           np.ascontiguousarray(T[:, 2]))
        bary = np.clip(bary, 0.0, None)
        return bary / bary.sum(axis=1, keepdims=True)

    def trace(self, face: int, bary: np.ndarray, direction: np.ndarray,
              length: float) -> np.ndarray:
        """The geodesic polyline ``(k, 3)`` from the point ``bary`` of ``face`` in the tangent
        ``direction`` (unit, in the face's plane), at most ``length`` long; it starts at the
        point itself."""
        path = self._tracer.trace_geodesic_from_face(int(face), np.asarray(bary, float),
                                                     np.asarray(direction, float) * length)
        return np.asarray(path, dtype=np.float64).reshape(-1, 3)

    def fan(self, points, face_ids, u_dirs, length: float):
        """Geodesics both ways from each base point: lists of forward and backward polylines
        (each starts at its base point) and their lengths ``ahead (n,)``, ``behind (n,)``.

        One trace per seed and side (the seeds are few, each trace runs in C++).
        """
        bary = self.barycentric(points, face_ids)
        forward = [self.trace(f, b, u, length) for f, b, u in zip(face_ids, bary, u_dirs,
                                                                   strict=True)]
        backward = [self.trace(f, b, -u, length) for f, b, u in zip(face_ids, bary, u_dirs,
                                                                    strict=True)]
        return forward, backward, polyline_lengths(forward), polyline_lengths(backward)


def polyline_lengths(polylines: list[np.ndarray]) -> np.ndarray:
    """Length of each polyline ``(k_i, 3)``, ``(len(polylines),)``."""
    return np.array([float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
                     for p in polylines])


def sample_geodesic(forward: np.ndarray, backward: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points ``(len(s), 3)`` at signed arc lengths ``s`` on the geodesic made of ``backward``
    (reversed, negative s) and ``forward`` (positive s); both start at the base point."""
    path = np.concatenate([backward[::-1], forward[1:]])
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    cum -= cum[len(backward) - 1]
    keep = np.concatenate([[True], np.diff(cum) > 0])   # drop repeated points
    cum, path = cum[keep], path[keep]
    return np.stack([np.interp(s, cum, path[:, k]) for k in range(3)], axis=1)
