"""Reference meshes: the four formats, cleaning, and one-line rejections."""

import hashlib

import numpy as np
import pytest
import trimesh
from data_files import WAVE

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.mesh import _plain_obj, consistent_winding, load_mesh, write_mesh_obj


def plane_grid(k=4):
    """A (k+1)² vertex grid on z = 0, two triangles per cell, all wound counterclockwise."""
    u, v = np.meshgrid(np.arange(k + 1.0), np.arange(k + 1.0), indexing="ij")
    vertices = np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], axis=1)
    vid = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces


def test_wave_obj():
    path = WAVE
    mesh = load_mesh(path)
    assert mesh.faces.shape == (5705, 3) and mesh.faces.dtype == np.int64
    assert mesh.vertices.shape == (3021, 3) and mesh.vertices.dtype == np.float64
    assert mesh.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    assert mesh.bbox_diagonal == pytest.approx(np.sqrt(43.6**2 + 44.0**2 + 6.1**2), rel=0.01)
    assert not mesh.vertices.flags.writeable
    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    assert tm.is_winding_consistent


@pytest.mark.parametrize("fmt", ["obj", "ply", "stl", "off"])
def test_formats(tmp_path, fmt):
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    path = tmp_path / f"box.{fmt.upper() if fmt == 'stl' else fmt}"
    data = box.export(file_type=fmt)
    path.write_bytes(data.encode() if isinstance(data, str) else data)
    mesh = load_mesh(path)
    assert mesh.vertices.shape == (8, 3) and mesh.faces.shape == (12, 3)  # STL merged
    assert mesh.bbox_diagonal == pytest.approx(np.sqrt(14.0))
    assert trimesh.Trimesh(mesh.vertices, mesh.faces).volume == pytest.approx(6.0)


def test_cleaning_merges_drops_and_fixes_winding(tmp_path):
    vertices, faces = plane_grid(3)
    # duplicate the vertices of face 0 (split it off), repeat face 1, add a degenerate face,
    # flip face 2
    k = len(vertices)
    vertices = np.concatenate([vertices, vertices[faces[0]]])
    faces = faces.copy()
    faces[0] = [k, k + 1, k + 2]
    faces[2] = faces[2][::-1]
    faces = np.concatenate([faces, faces[1:2], [[0, 1, 1]]])
    path = tmp_path / "p.obj"
    path.write_bytes(write_mesh_obj(path, vertices, faces))
    mesh = load_mesh(path)
    assert mesh.vertices.shape == (16, 3) and mesh.faces.shape == (18, 3)
    normals = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).face_normals
    assert np.allclose(np.abs(normals[:, 2]), 1.0)
    assert len(np.unique(np.sign(normals[:, 2]))) == 1  # one consistent orientation


def test_write_mesh_obj_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    vertices = rng.normal(size=(5, 3)) * 1e3
    faces = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]])
    data = write_mesh_obj(tmp_path / "part.obj", vertices, faces)
    assert data == write_mesh_obj(tmp_path / "part.obj", vertices, faces)
    assert b"o part\n" in data and b"\nf 1 4 5\n" in data
    back = trimesh.load(trimesh.util.wrap_as_stream(data), file_type="obj", process=False)
    assert np.array_equal(back.vertices, vertices) and np.array_equal(back.faces, faces)
    with pytest.raises(ValueError):
        write_mesh_obj(tmp_path / "x.obj", vertices, [[0, 1, 5]])


PNG = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)) * 4


@pytest.mark.parametrize("name, content, message", [
    ("missing.obj", None, "no such file"),
    ("image.obj", PNG, "not a mesh"),
    ("image.off", PNG, "not a mesh"),
    ("image.ply", PNG, "cannot read as PLY mesh"),
    # trimesh reads an STL that is not binary as ASCII, decoded by charset-normalizer where that
    # is installed (it comes with viser): then the PNG is a mesh with no faces
    ("image.stl", PNG, "cannot read as STL mesh|no faces"),
    ("empty.obj", b"", "no faces"),
    ("empty.stl", b"", "no faces"),
    ("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
    ("text.obj", b"hello\nthis is not a mesh\n", "no faces"),
    ("nan.obj", b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
     "vertex 3 has a non-finite coordinate"),
    ("one.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "at least 2 non-degenerate faces, has 1"),
    ("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n",
     "at least 2 non-degenerate faces, has 0"),
    ("mesh.3ds", b"v 0 0 0\n", "unsupported mesh format '.3ds'"),
])
def test_rejections(tmp_path, name, content, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(DgpcError, match=message) as err:
        load_mesh(path)
    assert err.value.source == str(path) and "\n" not in str(err.value)


def test_rejects_directory(tmp_path):
    (tmp_path / "d.obj").mkdir()
    with pytest.raises(DgpcError, match="is a directory"):
        load_mesh(tmp_path / "d.obj")


def test_consistent_winding_restores_random_flips():
    mesh = load_mesh(WAVE)
    rng = np.random.default_rng(7)
    flipped = rng.random(len(mesh.faces)) < 0.3
    flipped[0] = False  # the root face keeps its orientation
    faces = mesh.faces.copy()
    faces[flipped] = faces[flipped][:, ::-1]
    # a second, disjoint patch whose root face is flipped: it stays flipped as a whole
    other = mesh.faces[:50][:, ::-1] + len(mesh.vertices)
    fixed = consistent_winding(np.concatenate([faces, other]))
    assert np.array_equal(fixed[: len(faces)], mesh.faces)
    assert np.array_equal(fixed[len(faces):], other)


def test_consistent_winding_leaves_a_consistent_mesh_as_it_is():
    """A consistent mesh comes back unchanged (a copy), also with a third face on an edge (not
    a manifold edge, so it constrains nothing); one flipped face among them is turned back."""
    mesh = load_mesh(WAVE)
    a, b, _ = mesh.faces[0]
    extra = np.array([[b, a, len(mesh.vertices)]])               # a third face on edge (a, b)
    faces = np.concatenate([mesh.faces, extra])
    same = consistent_winding(faces)
    assert np.array_equal(same, faces) and same is not faces
    flipped = faces.copy()
    flipped[5] = flipped[5][::-1]
    assert np.array_equal(consistent_winding(flipped), faces)
@pytest.mark.parametrize("line_end", [b"\n", b"\r\n"])
def test_plain_obj_reads_as_trimesh_does(tmp_path, line_end):
    """The fast reader of plain triangle OBJ files gives trimesh's vertices and faces (line
    ends, comments, tabs, groups); anything else (polygons, slashes, colours, negative indices)
    goes to trimesh."""
    vertices, faces = plane_grid(3)
    vertices = vertices + [0.125, -2.5e-3, 1e-9]
    lines = [b"# a comment", b"o grid", *(b"v %r\t%r %r" % tuple(p) for p in vertices.tolist()),
             b"g faces", b"s off", *(b"f %d %d %d" % tuple(t) for t in (faces + 1).tolist())]
    path = tmp_path / "grid.obj"
    path.write_bytes(line_end.join(lines) + line_end)
    mesh = load_mesh(path)
    ref = trimesh.load(path, process=False)
    assert np.array_equal(mesh.vertices, ref.vertices)
    assert np.array_equal(np.sort(mesh.faces, axis=1), np.sort(ref.faces, axis=1))
    assert _plain_obj(path.read_bytes()) is not None
    head = [b"v 0 0 0", b"v 1 0 0", b"v 1 1 0", b"v 0 1 0"]
    for other in ([*head, b"f 1 2 3 4"], [*head, b"f 1/1 2/2 3/3"], [*head, b"f -4 -3 -2"],
                  [*head[:3], b"v 0 1 0 0.5 0.5 0.5", b"f 1 2 3"], [*head, b"f 1 2 x"]):
        assert _plain_obj(b"\n".join(other) + b"\n") is None     # trimesh reads these
