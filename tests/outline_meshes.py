"""Reference meshes with non-rectangular outlines (issue: "a roof with one curved and three
straight edges, and a dome clipped by a plane"), built here so that the tests own them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from dgpc_cli.io.mesh import write_mesh_obj

#: Roof: 20 × 12 m in plan; the far edge bulges out by ROOF_BULGE (a circular-ish arc).
ROOF_SIZE, ROOF_BULGE = (20.0, 12.0), 0.5
#: Dome: the upper half of a sphere of radius DOME_RADIUS centred on z = 0, cut by the plane
#: x = DOME_CUT.
DOME_RADIUS, DOME_CUT = 10.0, 4.0


def _grid_faces(rows: int, cols: int) -> np.ndarray:
    """Triangles ``(2·rows·cols, 3)`` of a ``(rows + 1) × (cols + 1)`` vertex grid, with the
    diagonals alternating (no preferred direction)."""
    vid = np.arange((rows + 1) * (cols + 1)).reshape(rows + 1, cols + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    flip = ((np.arange(rows)[:, None] + np.arange(cols)[None, :]) % 2).astype(bool)
    t1 = np.where(flip[..., None], np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    t2 = np.where(flip[..., None], np.stack([b, c, d], -1), np.stack([a, c, d], -1))
    return np.concatenate([t1.reshape(-1, 3), t2.reshape(-1, 3)])


def roof(rows: int = 48, cols: int = 30) -> tuple[np.ndarray, np.ndarray]:
    """A doubly curved roof over the plan ``0 ≤ x ≤ 20``, ``0 ≤ y ≤ 12 + bulge·sin(πx/20)``:
    three straight edges (y = 0, x = 0, x = 20) and one curved edge. Heights: a gentle
    saddle-free dome, ``z = 3 + 1.2 sin(πx/20) + 0.02 y (12 − y)``, metres."""
    (lx, ly) = ROOF_SIZE
    s, t = np.meshgrid(np.linspace(0, 1, rows + 1), np.linspace(0, 1, cols + 1), indexing="ij")
    x = lx * s
    y = t * (ly + ROOF_BULGE * np.sin(np.pi * x / lx))
    z = 3.0 + 1.2 * np.sin(np.pi * x / lx) + 0.02 * y * (ly - y)
    V = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return V, _grid_faces(rows, cols)


def clipped_dome(subdivisions: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """A hemispherical dome of radius 10 m standing on z = 0, cut by the vertical plane
    ``x = 4``: the part ``z ≥ 0, x ≤ 4`` of an icosphere (an irregular triangulation, not
    aligned with any net; the cut through its equator leaves sliver triangles along the
    ground, as real meshes cut by a plane have). Outline: half of the ground circle and the
    arc the plane cuts."""
    import trimesh
    from trimesh.intersections import slice_mesh_plane

    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=DOME_RADIUS)
    dome = slice_mesh_plane(sphere, plane_normal=[0, 0, 1], plane_origin=[0, 0, 0])
    dome = slice_mesh_plane(dome, plane_normal=[-1, 0, 0], plane_origin=[DOME_CUT, 0, 0])
    return np.asarray(dome.vertices, float), np.asarray(dome.faces, np.int64)


def write(path: Path, mesh: tuple[np.ndarray, np.ndarray]) -> Path:
    """Write ``(vertices, faces)`` as an OBJ file at ``path``; returns the path."""
    V, F = mesh
    path.write_bytes(write_mesh_obj(path, V, F))
    return path
