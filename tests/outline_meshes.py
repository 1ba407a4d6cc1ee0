"""Reference meshes with non-rectangular outlines (issue: "a roof with one curved and three
straight edges, and a dome clipped by a plane"; issue: "a real roof clad by the default
command", an arched roof of two corners), built here so that the tests and the benchmarks own
them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from dgpc_cli.io.mesh import write_mesh_obj

#: Roof: 20 × 12 m in plan; the far edge bulges out by ROOF_BULGE (a circular-ish arc).
ROOF_SIZE, ROOF_BULGE = (20.0, 12.0), 0.5
#: Dome: the upper half of a sphere of radius DOME_RADIUS centred on z = 0, cut by the plane
#: x = DOME_CUT.
DOME_RADIUS, DOME_CUT = 10.0, 4.0
#: Arched roof: the planform is the ellipse ``((x − ARCH_CENTRE)/ARCH_AXES[0])² +
#: (y/ARCH_AXES[1])² ≤ 1`` cut by the vertical plane x = 0 (the arch); heights
#: ``ARCH_HEIGHT · (1 − ρ³) · (1 − ARCH_WAVE · cos(πy/ARCH_PERIODS[0]) cos(πx/ARCH_PERIODS[1]))``
#: with ρ the planform's elliptic radius, metres.
ARCH_AXES, ARCH_CENTRE = (30.0, 20.0), 9.0
ARCH_HEIGHT, ARCH_WAVE, ARCH_PERIODS = 11.0, 0.35, (13.0, 26.0)


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


def arch_roof_height(x, y) -> np.ndarray:
    """Heights of :func:`arch_roof` over the plan points ``(x, y)`` (0 on the ground edge)."""
    (ax, by), xc = ARCH_AXES, ARCH_CENTRE
    rho2 = ((np.asarray(x) - xc) / ax) ** 2 + (np.asarray(y) / by) ** 2
    base = np.clip(1.0 - rho2 ** 1.5, 0.0, None)
    wave = np.cos(np.pi * y / ARCH_PERIODS[0]) * np.cos(np.pi * x / ARCH_PERIODS[1])
    return ARCH_HEIGHT * base * (1.0 - ARCH_WAVE * wave)


def arch_roof(spacing: float = 0.6) -> tuple[np.ndarray, np.ndarray]:
    """A roof of 39 × 40 m in plan and 13.3 m high, with ONE boundary loop of only two
    corners (the feet of the arch): an arch edge of about 53 m in the vertical plane x = 0 with
    two humps (y ≈ ±10 m) and a dip between them, and a ground edge in the plane z = 0 (an
    arc of an ellipse, about 97 m, round the apse at x = 39 m). Bumps and saddles alternate
    (the cosine wave on a dome): Gaussian curvature about −0.01 to +0.02 /m².

    A clean triangulation of the plan (points of a hexagonal lattice of ``spacing`` metres
    inside, the outline sampled at the same spacing; Delaunay, the plan being convex) lifted
    onto :func:`arch_roof_height`: the ground edge lies on z = 0 exactly, the arch on x = 0."""
    from scipy.spatial import Delaunay

    (ax, by), xc = ARCH_AXES, ARCH_CENTRE
    # the ground edge: the ellipse's arc x ≥ 0, sampled evenly by arc length
    t0 = np.arccos(-xc / ax)                                 # the feet: x = 0
    t = np.linspace(-t0, t0, 20001)
    e = np.stack([xc + ax * np.cos(t), by * np.sin(t)], 1)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(e, axis=0), axis=1))])
    k = max(2, int(round(s[-1] / spacing)))
    ts = np.interp(np.linspace(0.0, s[-1], k + 1), s, t)
    ground = np.stack([xc + ax * np.cos(ts), by * np.sin(ts)], 1)
    ground[[0, -1], 0] = 0.0
    foot = ground[-1, 1]
    j = max(2, int(round(2 * foot / spacing)))
    arch = np.stack([np.zeros(j - 1), np.linspace(foot, -foot, j + 1)[1:-1]], 1)
    # the lattice, kept at least half a spacing inside the outline
    h = spacing * np.sqrt(3) / 2
    gx, gy = np.meshgrid(np.arange(0.0, xc + ax, spacing), np.arange(-by, by, h))
    gx = gx + (np.arange(gx.shape[0])[:, None] % 2) * spacing / 2
    p = np.stack([gx.ravel(), gy.ravel()], 1)
    rho = np.sqrt(((p[:, 0] - xc) / ax) ** 2 + (p[:, 1] / by) ** 2)
    inside = (p[:, 0] > 0.5 * spacing) & ((1.0 - rho) * min(ax, by) > 0.5 * spacing)
    plan = np.concatenate([ground, arch, p[inside]])
    F = Delaunay(plan).simplices.astype(np.int64)
    a, b, c = plan[F[:, 0]], plan[F[:, 1]], plan[F[:, 2]]
    area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    F = np.where((area < 0)[:, None], F[:, [0, 2, 1]], F)     # counter-clockwise: normals up
    F = F[np.abs(area) > 1e-9 * spacing**2]
    z = arch_roof_height(plan[:, 0], plan[:, 1])
    z[: len(ground)] = 0.0
    return np.column_stack([plan, z]), F


def write(path: Path, mesh: tuple[np.ndarray, np.ndarray]) -> Path:
    """Write ``(vertices, faces)`` as an OBJ file at ``path``; returns the path."""
    V, F = mesh
    path.write_bytes(write_mesh_obj(path, V, F))
    return path


#: The meshes by name, for the benchmarks and for writing them out by hand.
MESHES = {"roof": roof, "dome": clipped_dome, "arch-roof": arch_roof}

if __name__ == "__main__":
    import sys

    # python tests/outline_meshes.py NAME OUT.obj
    write(Path(sys.argv[2]), MESHES[sys.argv[1]]())
