"""The arched roof of two corners (tests/outline_meshes.py) is what it claims: one boundary
loop that is an arch in a vertical plane and a ground edge, a manifold of clean triangles,
and bumps beside saddles of the issue's size."""

import numpy as np
import pytest
from outline_meshes import arch_roof

from dgpc_cli.geodesics.boundary import boundary_curves


@pytest.fixture(scope="module")
def mesh():
    return arch_roof()


def test_one_boundary_loop_of_two_corners_an_arch_and_a_ground_edge(mesh):
    import trimesh

    V, F = mesh
    m = trimesh.Trimesh(V, F, process=False)
    assert m.is_winding_consistent and not m.is_watertight
    _, count = np.unique(m.edges_sorted, axis=0, return_counts=True)
    assert count.max() == 2                                        # manifold
    assert np.degrees(m.face_angles.min()) > 10.0                  # no slivers
    extent = np.ptp(V, axis=0)
    assert extent[0] == pytest.approx(39.0, abs=0.5) and extent[1] == pytest.approx(40.0, abs=0.5)
    assert 12.0 < extent[2] < 14.0
    curves = boundary_curves(V, F)
    assert len(curves) == 2
    ground, arch = sorted(curves, key=lambda c: -c.length)
    assert ground.length == pytest.approx(97.5, abs=1.0)
    assert arch.length == pytest.approx(52.0, abs=1.5)
    assert np.abs(ground.curve.points[:, 2]).max() == 0.0
    assert np.abs(arch.curve.points[:, 0]).max() == 0.0
    # the arch has two humps: its height along y rises, falls to the dip at y = 0, rises
    p = arch.curve.points[np.argsort(arch.curve.points[:, 1])]
    mid = np.argmin(np.abs(p[:, 1]))
    assert p[:mid, 2].max() > 10.0 and p[mid:, 2].max() > 10.0 and p[mid, 2] < 7.0


def test_bumps_and_saddles_of_the_issue_size(mesh):
    import igl

    V, F = mesh
    K = igl.gaussian_curvature(V, F) / igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    inner = np.ones(len(V), bool)
    inner[igl.boundary_loop(F)] = False
    scaled = K[inner] * float(np.linalg.norm(np.ptp(V, axis=0))) ** 2
    low, high = np.percentile(scaled, [1, 99])
    assert -45 < low < -25 and 35 < high < 70
