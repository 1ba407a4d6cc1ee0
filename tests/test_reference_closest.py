"""Closest points and normals on the reference surface (libigl AABB)."""

import numpy as np
import pytest
import trimesh
from data_files import WAVE

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.io.mesh import load_mesh


def plane(k=4, flip=False):
    """Unit square [0, 1]² on z = 0, 2k² triangles wound counterclockwise seen from +z."""
    u, v = np.meshgrid(np.linspace(0, 1, k + 1), np.linspace(0, 1, k + 1), indexing="ij")
    vertices = np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], axis=1)
    vid = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces[:, ::-1] if flip else faces


def brute_force_distance(vertices, faces, points):
    """Distance from each point to the nearest triangle, by testing every triangle."""
    tri = vertices[faces]
    k, t = len(points), len(faces)
    closest = trimesh.triangles.closest_point(np.tile(tri, (k, 1, 1)), np.repeat(points, t, 0))
    return np.linalg.norm(closest - np.repeat(points, t, 0), axis=1).reshape(k, t).min(axis=1)


def test_plane_is_exact():
    surface = ReferenceSurface(*plane())
    rng = np.random.default_rng(0)
    q = np.column_stack([rng.random((50, 2)), rng.normal(size=50)])
    p, n = surface.closest(q)
    assert p.shape == (50, 3) and n.shape == (50, 3)
    assert np.allclose(p, q * [1, 1, 0], atol=1e-14, rtol=0)
    assert np.array_equal(n, np.tile([0.0, 0.0, 1.0], (50, 1)))


def test_plane_clamps_outside_and_follows_winding():
    surface = ReferenceSurface(*plane(flip=True))
    p, n = surface.closest(np.array([[2.0, 0.5, 1.0], [-1.0, -1.0, -3.0]]))
    assert np.allclose(p, [[1.0, 0.5, 0.0], [0.0, 0.0, 0.0]], atol=1e-14)
    assert np.allclose(n, [0.0, 0.0, -1.0])


def test_sphere_against_brute_force_and_chord_sag():
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    vertices, faces = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    surface = ReferenceSurface(vertices, faces)
    rng = np.random.default_rng(1)
    dirs = rng.normal(size=(40, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    q = dirs * rng.uniform(0.3, 2.0, size=(40, 1))
    p, n = surface.closest(q)
    dist = np.linalg.norm(p - q, axis=1)
    assert np.allclose(dist, brute_force_distance(vertices, faces, q), atol=1e-12)
    # on the mesh: between the inscribed radius (chord sag) and the sphere
    centers = vertices[faces].mean(axis=1)
    r_in = np.abs(np.einsum("ij,ij->i", centers, sphere.face_normals)).min()
    radii = np.linalg.norm(p, axis=1)
    assert (radii >= r_in - 1e-12).all() and (radii <= 1.0 + 1e-12).all()
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert (np.einsum("ij,ij->i", n, p / radii[:, None]) > 0.99).all()  # outward normals


def test_scaled():
    sphere = trimesh.creation.icosphere(subdivisions=2)
    surface = ReferenceSurface(sphere.vertices, sphere.faces)
    q = np.random.default_rng(2).normal(size=(20, 3))
    p, n = surface.closest(q)
    p2, n2 = surface.scaled(2.5).closest(2.5 * q)
    assert np.allclose(p2, 2.5 * p) and np.allclose(n2, n)
    assert surface.scaled(2.5).bbox_diagonal == pytest.approx(2.5 * surface.bbox_diagonal)
    with pytest.raises(ValueError):
        surface.scaled(-1.0)


def test_from_mesh_wave_vertices_are_fixed_points():
    mesh = load_mesh(WAVE)
    surface = ReferenceSurface.from_mesh(mesh)
    p, n = surface.closest(mesh.vertices)
    assert np.allclose(p, mesh.vertices, atol=1e-9 * mesh.bbox_diagonal)
    normals = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).face_normals
    _, nc = surface.closest(mesh.vertices[mesh.faces].mean(axis=1))  # face centroids
    assert np.allclose(nc, normals, atol=1e-9)  # each face's own normal, oriented by winding
    q = mesh.vertices[::150] + np.random.default_rng(3).normal(scale=0.5, size=(21, 3))
    p2, _ = surface.closest(q)
    expected = brute_force_distance(mesh.vertices, mesh.faces, q)
    assert np.allclose(np.linalg.norm(p2 - q, axis=1), expected, atol=1e-10)


def test_degenerate_faces_dropped_and_bad_input():
    vertices, faces = plane(1)
    vertices = np.vstack([vertices, [[0.5, 0.5, 5.0]]])
    faces = np.vstack([faces, [[0, 4, 4]]])  # zero-area sliver reaching up to z = 5
    surface = ReferenceSurface(vertices, faces)
    assert len(surface.faces) == 2
    p, n = surface.closest(np.array([[0.5, 0.5, 4.0]]))
    assert np.allclose(p, [[0.5, 0.5, 0.0]]) and np.allclose(n, [[0, 0, 1]])
    p, n = surface.closest(np.zeros((0, 3)))
    assert p.shape == (0, 3) and n.shape == (0, 3)
    with pytest.raises(ValueError):
        surface.closest(np.zeros(3))
    with pytest.raises(ValueError):
        ReferenceSurface(vertices, [[0, 1, 9]])
