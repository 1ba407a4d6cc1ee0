"""The boundary term: a fitted net keeps covering its reference (SPEC §8 Hausdorff figures).

Approximation lets vertices slide along the reference, so under the developability conditions
a net's rim creeps inwards; rim vertices that start on the reference's boundary keep to it.
"""

from pathlib import Path

import numpy as np
import pytest
from cli_helpers import dgpc, metrics

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.fitting.optimize import boundary_vertices
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net

FELT = Path(__file__).resolve().parents[1] / "samples" / "meshes" / "felt.obj"


def test_closest_on_boundary_of_a_square():
    V = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [1, 1, 0]])
    F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    surface = ReferenceSurface(V, F)
    assert len(surface.boundary_segments[0]) == 4                 # the spokes are interior
    b, t = surface.closest_on_boundary(np.array([[0.5, 0.2, 0.3], [3.0, 1.5, 0.0]]))
    assert np.allclose(b, [[0.5, 0.0, 0.0], [2.0, 1.5, 0.0]])
    assert np.allclose(np.abs(t), [[1, 0, 0], [0, 1, 0]])


def test_closed_mesh_has_no_boundary_vertices():
    import trimesh

    sphere = trimesh.creation.icosphere(2)
    surface = ReferenceSurface(sphere.vertices, sphere.faces)
    f = np.stack(np.meshgrid(np.linspace(-.5, .5, 4), np.linspace(-.5, .5, 3), [1.0],
                             indexing="ij"), -1)[:, :, 0]
    assert boundary_vertices(f, surface).size == 0


@pytest.fixture(scope="module")
def felt(tmp_path_factory):
    d = tmp_path_factory.mktemp("felt")
    dgpc("init", FELT, "--method", "geodesic", "--rows", 21, "--cols", 13, "-o", d / "n0")
    return d


def test_developable_fit_keeps_covering_the_reference(felt):
    m0 = metrics(felt / "n0")
    assert m0["coverage"]["area_fraction"] >= 0.999              # the init covers the felt
    dgpc("optimize", felt / "n0", "--mode", "developable", "--reference", FELT,
         "-o", felt / "n1")
    m1 = metrics(felt / "n1")
    assert m1["R"] <= 1e-1 and m1["jacobi_residual_max"] <= 1e-8
    assert m1["coverage"]["area_fraction"] >= 0.999
    assert m1["hausdorff"]["relative"] <= 1.1 * m0["hausdorff"]["relative"]
    rim = read_net(felt / "n1").data["boundary"]["ids"]
    assert len(rim) == 2 * (21 + 13) - 4                         # the whole rim starts on it
    surface = ReferenceSurface.from_mesh(load_mesh(FELT))
    q = read_net(felt / "n1").f.reshape(-1, 3)[rim]
    b, _ = surface.closest_on_boundary(q)
    assert np.linalg.norm(q - b, axis=1).max() <= 1e-3 * surface.bbox_diagonal


def test_without_the_boundary_term_the_rim_creeps_in(felt):
    """A case where the creep is certain, not a matter of rounding: fairness held at 0.1
    (second differences of a curved net shorten it, as a curve-shortening flow does) while
    approximation lets every vertex slide along the felt. Without the boundary and rim terms
    the net shrinks by a large fraction; with the boundary term the rim stays on the felt's
    edge; the rim term alone (which only stops it coming in) keeps nearly all of it too."""
    common = ["optimize", felt / "n0", "--mode", "fit", "--reference", FELT,
              "--weight", "fairness=0.1", "--max-iter", "60"]
    dgpc(*common, "--weight", "boundary=0", "--weight", "rim=0", "-o", felt / "shrunk")
    dgpc(*common, "-o", felt / "held")
    # held from coming in, and by nothing else, against a constant fairness: it stalls
    dgpc(*common, "--weight", "boundary=0", "-o", felt / "rim", expect=None)
    shrunk, held = metrics(felt / "shrunk"), metrics(felt / "held")
    assert shrunk["coverage"]["area_fraction"] < 0.8
    assert held["coverage"]["area_fraction"] >= 0.99
    assert metrics(felt / "rim")["coverage"]["area_fraction"] >= 0.95
    assert "boundary" not in read_net(felt / "shrunk").data
    assert "boundary" in read_net(felt / "held").data
