"""Reference meshes for `dgpc init`: pieces, and bad input (issue 3): a hole in the middle, a
closed mesh, two triangles work as documented; a PNG renamed .obj, several pieces and a zero
direction exit 1 with one line, writing nothing."""

import numpy as np
import pytest
import trimesh
from cli_helpers import dgpc, metrics

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.mesh import load_mesh, write_mesh_obj
from dgpc_cli.io.net import read_net


def grid_mesh(k=20, size=10.0, hole=None):
    """A flat square [0, size]² of k×k cells (two triangles each), minus the cells inside the
    centred square of side ``hole``."""
    u, v = np.meshgrid(np.linspace(0, size, k + 1), np.linspace(0, size, k + 1), indexing="ij")
    V = np.stack([u.ravel(), v.ravel(), 0.02 * np.sin(u.ravel()) * np.cos(v.ravel())], 1)
    vid = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    keep = np.ones((k, k), bool)
    if hole:
        centre = (np.arange(k) + 0.5) * size / k - size / 2
        keep = ~((np.abs(centre)[:, None] < hole / 2) & (np.abs(centre)[None, :] < hole / 2))
    F = np.concatenate([np.stack([a, b, c], -1)[keep], np.stack([a, c, d], -1)[keep]])
    return V, F


def save(path, V, F):
    path.write_bytes(write_mesh_obj(path, V, F))
    return path


def one_line_error(result, *words):
    err = result.stderr.strip()
    assert len(err.splitlines()) == 1 and err.startswith("Error:"), err
    for w in words:
        assert w in err, (w, err)


def written(tmp_path):
    return sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("out"))


def test_several_pieces_rejected_unless_largest_component(tmp_path):
    V, F = grid_mesh(10)
    V2, F2 = grid_mesh(4, size=3.0)
    path = save(tmp_path / "two.obj", np.concatenate([V, V2 + [20, 0, 0]]),
                np.concatenate([F, F2 + len(V)]))
    with pytest.raises(DgpcError, match="2 separate pieces"):
        load_mesh(path, pieces="one")
    assert len(load_mesh(path).faces) == len(F) + len(F2)          # default keeps all
    big = load_mesh(path, pieces="largest")
    assert len(big.faces) == len(F) and big.vertices[:, 0].max() == pytest.approx(10.0)
    r = dgpc("init", path, "--method", "geodesic", "-o", tmp_path / "out", expect=1)
    one_line_error(r, "two.obj", "--largest-component")
    assert written(tmp_path) == []
    dgpc("init", path, "--method", "geodesic", "--largest-component", "-o", tmp_path / "out")
    f = read_net(tmp_path / "out").f
    assert f[..., 0].max() <= 10.0 + 1e-9
    # optimize keeps to the piece the net was made on (the reference it records is the file)
    dgpc("optimize", tmp_path / "out", "--mode", "fit", "-o", tmp_path / "fit")
    fitted = read_net(tmp_path / "fit")
    assert fitted.parameters["largest_component"] is True
    diagonal = metrics(tmp_path / "fit")["hausdorff"]["diagonal"]
    assert diagonal == pytest.approx(np.linalg.norm(np.ptp(big.vertices, axis=0)), rel=1e-9)


def test_hole_in_the_middle_is_avoided(tmp_path):
    path = save(tmp_path / "holed.obj", *grid_mesh(20, hole=4.0))
    dgpc("init", path, "--method", "geodesic", "--rows", 12, "--cols", 9, "-o",
         tmp_path / "out")
    f = read_net(tmp_path / "out").f
    assert f.shape == (12, 9, 3)
    # no net vertex and no edge midpoint inside the hole
    mids = np.concatenate([f.reshape(-1, 3), (0.5 * (f[1:] + f[:-1])).reshape(-1, 3),
                           (0.5 * (f[:, 1:] + f[:, :-1])).reshape(-1, 3)])
    inside = (np.abs(mids[:, 0] - 5) < 2 - 1e-9) & (np.abs(mids[:, 1] - 5) < 2 - 1e-9)
    assert not inside.any()
    dgpc("init", path, "--method", "project", "--direction", "0,0,1", "--rows", 6, "--cols", 5,
         "-o", tmp_path / "proj")
    f = read_net(tmp_path / "proj").f
    inside = (np.abs(f[..., 0] - 5) < 2 - 1e-9) & (np.abs(f[..., 1] - 5) < 2 - 1e-9)
    assert not inside.any()


def test_closed_mesh_works_as_documented(tmp_path):
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=2.0)
    path = save(tmp_path / "ball.obj", sphere.vertices, sphere.faces)
    dgpc("init", path, "--method", "geodesic", "--direction", "0,0,1", "--rows", 9, "--cols",
         12, "-o", tmp_path / "out")
    f = read_net(tmp_path / "out").f
    r = np.linalg.norm(f, axis=-1)
    assert np.allclose(r, 2.0, atol=0.01)                  # on the sphere
    assert np.abs(f[..., 2]).max() <= 2.0 + 1e-9            # cut at the mesh's extent
    dgpc("init", path, "--method", "project", "--direction", "0,0,1", "--rows", 5, "--cols", 5,
         "-o", tmp_path / "top")
    assert (read_net(tmp_path / "top").f[..., 2] > 0).all()  # the side the direction points to


def test_two_triangles(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]])
    path = save(tmp_path / "two.obj", V, np.array([[0, 1, 2], [0, 2, 3]]))
    dgpc("init", path, "--method", "geodesic", "--rows", 4, "--cols", 4, "-o", tmp_path / "out")
    f = read_net(tmp_path / "out").f
    assert f.shape == (4, 4, 3) and np.abs(f[..., 2]).max() == 0.0
    assert f[..., :2].min() >= -1e-12 and f[..., :2].max() <= 1 + 1e-12


@pytest.mark.parametrize("args, words, code", [
    (["--method", "geodesic", "--direction", "0,0,0"], ["--direction", "not all zero"], 2),
    (["--method", "project", "--direction", "1,a,0"], ["--direction"], 2),
    (["--method", "project", "--direction", "0,0,1", "--edge-length", "100mm"], ["--edge-length"],
     1),
])
def test_bad_options_exit_2_or_1(tmp_path, args, words, code):
    """A malformed option is a usage error (2); a spacing the mesh cannot take is bad data (1)."""
    path = save(tmp_path / "m.obj", *grid_mesh(6))
    r = dgpc("init", path, *args, "-o", tmp_path / "out", expect=code)
    one_line_error(r, *words)
    assert written(tmp_path) == []


def test_png_renamed_obj(tmp_path):
    png = tmp_path / "photo.obj"
    png.write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR" + bytes(range(256)))
    r = dgpc("init", png, "--method", "geodesic", "-o", tmp_path / "out", expect=1)
    one_line_error(r, "photo.obj")
    assert written(tmp_path) == []


def test_usage_errors_exit_2(tmp_path):
    path = save(tmp_path / "m.obj", *grid_mesh(6))
    dgpc("init", path, "--method", "project", "--base", "b1", "-o", tmp_path / "out",
         expect=2)                                                   # a base curve: geodesic
    dgpc("init", path, "--method", "geodesic", "--base", "b1", "--angle", 10, "-o",
         tmp_path / "out", expect=2)                                 # a boundary has no angle
    dgpc("init", path, "--method", "geodesic", "--cols", 5, "--edge-length", 1, "-o",
         tmp_path / "out", expect=2)
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
         "--method", "geodesic", "-o", tmp_path / "out", expect=2)
    assert written(tmp_path) == []
