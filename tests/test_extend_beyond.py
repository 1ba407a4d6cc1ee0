"""Nets that run beyond their reference (`init --extend`, paper Fig. 14): the mesh continued
past its outer boundary, and a fit that covers the whole reference."""

from pathlib import Path

import numpy as np
import pytest
import trimesh
from cli_helpers import dgpc, metrics

from dgpc_cli.geodesics.extension import boundary_edges, extend_mesh, folded_faces
from dgpc_cli.io.mesh import write_mesh_obj
from dgpc_cli.io.net import read_net

GRIDSHELL = Path(__file__).resolve().parents[1] / "samples" / "meshes" / "gridshell.obj"


def _square(k=10, size=10.0, hole=False, slot=False):
    u, v = np.meshgrid(np.linspace(0, size, k + 1), np.linspace(0, size, k + 1), indexing="ij")
    V = np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], 1)
    vid = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    keep = np.ones((k, k), bool)
    if hole:
        keep[k // 2 - 1:k // 2 + 1, k // 2 - 1:k // 2 + 1] = False
    if slot:                                    # a slot one cell wide from the edge inwards
        keep[k // 2, :k // 2] = False
    F = np.concatenate([np.stack([a, b, c], -1)[keep], np.stack([a, c, d], -1)[keep]])
    return V, F


def test_extend_mesh_grows_a_square_by_the_distance_and_keeps_it_manifold():
    V, F = _square()
    V2, F2 = extend_mesh(V, F, 1.5)
    assert np.array_equal(V2[:len(V)], V) and np.array_equal(F2[:len(F)], F)
    assert np.allclose(V2.min(axis=0), [-1.5, -1.5, 0]) and np.allclose(V2.max(axis=0),
                                                                         [11.5, 11.5, 0])
    mesh = trimesh.Trimesh(V2, F2, process=False)
    assert mesh.is_winding_consistent
    assert mesh.area == pytest.approx(13.0 ** 2, rel=1e-12)       # mitred corners: a square
    assert (mesh.face_normals[:, 2] > 0).all()                      # same side as the input
    key = np.sort(F2[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    assert np.unique(key, axis=0, return_counts=True)[1].max() == 2  # manifold


def test_extend_mesh_leaves_holes_alone():
    V, F = _square(hole=True)
    V2, F2 = extend_mesh(V, F, 1.0)
    mesh = trimesh.Trimesh(V2, F2, process=False)
    assert mesh.area == pytest.approx(12.0 ** 2 - 4.0, rel=1e-12)
    assert len(boundary_edges(F2)[0]) == len(boundary_edges(F)[0])  # hole + outer, same counts


def test_a_continuation_that_would_fold_is_refused(tmp_path):
    """Rings grown into a slot one cell wide meet after half a cell and turn over: init names
    --extend and the largest extension that does not fold; nothing is written."""
    V, F = _square(slot=True)
    assert folded_faces(*extend_mesh(V, F, 0.3), len(F)) == 0
    assert folded_faces(*extend_mesh(V, F, 1.0), len(F)) > 0
    path = tmp_path / "slot.obj"
    path.write_bytes(write_mesh_obj(path, V, F))
    r = dgpc("init", path, "--method", "geodesic", "--extend", 0.1, "-o", tmp_path / "n",
             expect=1)
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and "--extend" in err and "folds" in err
    largest = float(err.rsplit("at most ", 1)[1].split()[0])
    diagonal = np.linalg.norm(np.ptp(V, axis=0))
    assert 0.3 / diagonal < largest < 0.6 / diagonal      # the slot closes at half its width
    assert not list(tmp_path.glob("n.*"))
    dgpc("init", path, "--method", "geodesic", "--extend", 0.02, "-o", tmp_path / "n")


def test_extended_gridshell_net_covers_the_reference(tmp_path):
    """A geodesic net kept on the reference leaves its corners uncovered; with --extend 0.1 the
    fitted net covers all of it: reference-to-net Hausdorff ≤ 1.2e-3 of the diagonal (the
    paper's Fig. 14 figure), the vertices over the reference on it, R at solver tolerance."""
    for extend, stem in ((0.0, "in"), (0.1, "out")):
        dgpc("init", GRIDSHELL, "--method", "geodesic", "--direction", "1,0,0", "--rows", 25,
             "--cols", 19, "--extend", extend, "-o", tmp_path / f"{stem}0")
        dgpc("optimize", tmp_path / f"{stem}0", "--mode", "fit", "-o", tmp_path / stem)
    inside, beyond = metrics(tmp_path / "in"), metrics(tmp_path / "out")
    assert inside["coverage"]["area_fraction"] < 0.97
    assert beyond["coverage"]["area_fraction"] == pytest.approx(1.0, abs=1e-12)
    h = beyond["hausdorff"]
    assert h["reference_to_net_max"] <= 1.2e-3 * h["diagonal"]
    assert h["reference_to_net_max"] < 0.1 * inside["hausdorff"]["reference_to_net_max"]
    assert beyond["R"] <= 1e-8
    assert beyond["residuals"]["approximation"] <= 1e-8
    net = read_net(tmp_path / "out")
    assert net.parameters["extend"] == 0.1
    assert read_net(tmp_path / "out0").data["reference"]["path"].endswith("gridshell.obj")
    # the net really runs past the reference (10 × 8 in x, y), by up to 0.1 of the diagonal
    f = net.f.reshape(-1, 3)
    assert f[:, 0].min() < -0.2 and f[:, 0].max() > 10.2
    assert f[:, :2].min() >= -0.1 * h["diagonal"] - 1e-9


def test_extend_needs_a_mesh(tmp_path):
    r = dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
             "--extend", 0.1, "-o", tmp_path / "n", expect=2)
    assert "--extend" in r.stderr
    assert not list(tmp_path.iterdir())
