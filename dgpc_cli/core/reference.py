"""The reference surface: closest points and normals on a triangle mesh (paper §5.1).

Backed by libigl's AABB tree, built once per surface (SPEC §10: much faster than
trimesh.proximity on 100k-triangle references); a scaled copy shares the tree and scales the
queries instead (building the tree of a 300k-triangle reference takes about a second).
"""

from __future__ import annotations

import copy

import igl
import numpy as np

#: Triangles with area below this fraction of (bounding-box diagonal)² are dropped.
DEGENERATE_AREA = 1e-20


class ReferenceSurface:
    """A triangle mesh ``vertices (k, 3)``, ``faces (t, 3)`` queried for closest points.

    Face normals follow the winding (right-hand rule); degenerate faces are dropped.
    """

    #: Factor of this view's coordinates over the tree's (see :meth:`scaled`).
    _scale = 1.0

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        V = np.ascontiguousarray(vertices, dtype=np.float64)
        F = np.ascontiguousarray(faces, dtype=np.int64)
        if V.ndim != 2 or V.shape[1] != 3 or F.ndim != 2 or F.shape[1] != 3:
            raise ValueError(f"expected vertices (k, 3) and faces (t, 3), got {V.shape}, {F.shape}")
        if F.size == 0 or F.min() < 0 or F.max() >= len(V):
            raise ValueError("faces must be non-empty and index existing vertices")
        if not np.isfinite(V).all():
            raise ValueError("vertices must be finite")
        cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        norm = np.linalg.norm(cross, axis=1)
        diag = float(np.linalg.norm(np.ptp(V, axis=0)))
        keep = norm > 2.0 * DEGENERATE_AREA * diag**2
        if not keep.any():
            raise ValueError("all faces are degenerate")
        F = np.ascontiguousarray(F[keep])
        self._V, self.faces = V, F
        self.face_normals = np.ascontiguousarray(cross[keep] / norm[keep, None])
        for a in (self._V, self.faces, self.face_normals):
            a.setflags(write=False)
        self._tree = igl.AABB()
        self._tree.init(V, F)
        self._cache: dict = {}                # shared with the scaled views

    @classmethod
    def from_mesh(cls, mesh) -> ReferenceSurface:
        """From a :class:`dgpc_cli.io.mesh.ReferenceMesh` (or anything with vertices, faces)."""
        return cls(mesh.vertices, mesh.faces)

    @property
    def vertices(self) -> np.ndarray:
        """Vertex coordinates ``(k, 3)`` of this (possibly scaled) surface."""
        return self._V if self._scale == 1.0 else self._V * self._scale

    @property
    def bbox_diagonal(self) -> float:
        """Length of the axis-aligned bounding-box diagonal."""
        return float(np.linalg.norm(np.ptp(self._V, axis=0))) * self._scale

    def scaled(self, s: float) -> ReferenceSurface:
        """The surface with every coordinate multiplied by ``s > 0`` (normals unchanged): a
        view that shares this one's tree and boundary and scales the queries."""
        if not (np.isfinite(s) and s > 0):
            raise ValueError(f"scale must be positive and finite, got {s}")
        view = copy.copy(self)
        view._scale = self._scale * s
        return view

    def closest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closest points ``p (k, 3)`` on the mesh to ``points (k, 3)`` and the unit normals
        ``n (k, 3)`` of the faces they lie on."""
        P = np.ascontiguousarray(points, dtype=np.float64)
        if P.ndim != 2 or P.shape[1] != 3:
            raise ValueError(f"expected points (k, 3), got shape {P.shape}")
        if len(P) == 0:
            return np.zeros((0, 3)), np.zeros((0, 3))
        if self._scale != 1.0:
            P = P / self._scale
        _, face_ids, p = self._tree.squared_distance(self._V, self.faces, P)
        p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
        return (p if self._scale == 1.0 else p * self._scale), self.face_normals[face_ids]

    @property
    def boundary_segments(self) -> tuple[np.ndarray, np.ndarray]:
        """End points ``a, b (s, 3)`` of the boundary edges (edges of one face only); empty for a
        closed mesh."""
        if "boundary" not in self._cache:
            F = self.faces
            edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
            keys = edges[:, 0] * np.int64(len(self._V)) + edges[:, 1]   # one int per edge
            unique, counts = np.unique(keys, return_counts=True)
            once = unique[counts == 1]
            a, b = once // len(self._V), once % len(self._V)
            self._cache["boundary"] = (self._V[a], self._V[b])
        a, b = self._cache["boundary"]
        return (a, b) if self._scale == 1.0 else (a * self._scale, b * self._scale)

    def closest_on_boundary(self, points: np.ndarray, chunk: int = 256):
        """Closest points ``b (k, 3)`` on the mesh boundary to ``points (k, 3)`` and the unit
        tangents ``t (k, 3)`` of the boundary edges they lie on. ValueError for a closed mesh."""
        a, b = self.boundary_segments
        if len(a) == 0:
            raise ValueError("the mesh has no boundary")
        P = np.asarray(points, dtype=float).reshape(-1, 3)
        d = b - a
        dd = np.maximum(np.einsum("ij,ij->i", d, d), np.finfo(float).tiny)
        foot, tangent = np.empty_like(P), np.empty_like(P)
        for lo in range(0, len(P), chunk):
            q = P[lo:lo + chunk, None, :]                                      # (c, 1, 3)
            s = np.clip(np.einsum("csj,sj->cs", q - a, d) / dd, 0.0, 1.0)      # (c, s)
            c = a + s[..., None] * d                                           # (c, s, 3)
            best = np.argmin(np.einsum("csj,csj->cs", q - c, q - c), axis=1)
            rows = np.arange(len(best))
            foot[lo:lo + chunk] = c[rows, best]
            tangent[lo:lo + chunk] = d[best] / np.sqrt(dd[best])[:, None]
        return foot, tangent
