"""Coverage to a geometric tolerance (issue: "inspect's coverage counts anything within one
mean net edge"): a reference point is covered only where the net passes within the tolerance,
by default 0.2 % of the reference's diagonal, settable in inspect and optimize."""

import math

import numpy as np
import pytest
import trimesh
from cli_helpers import dgpc, metrics

from dgpc_cli.metrics.coverage import TOLERANCE_OF_DIAGONAL, coverage, covered_faces

A = 0.01          # the reference: the cap z = A (x² + y²) over [-5, 5]²


def _cap(k: int = 81):
    x = np.linspace(-5.0, 5.0, k)
    X, Y = np.meshgrid(x, x, indexing="ij")
    V = np.stack([X, Y, A * (X**2 + Y**2)], -1).reshape(-1, 3)
    i = np.arange(k - 1)
    iu, iv = np.meshgrid(i, i, indexing="ij")
    a = (iu * k + iv).ravel()
    F = np.concatenate([np.stack([a, a + k, a + k + 1], 1), np.stack([a, a + k + 1, a + 1], 1)])
    return V, F


def _flat_net(m: int = 11):
    """A flat 11×11 grid of unit spacing at z = 0 over the cap's footprint: it lies within
    0.5 (half a mean edge) of every point of the cap, but on it only near the centre."""
    x = np.linspace(-5.0, 5.0, m)
    X, Y = np.meshgrid(x, x, indexing="ij")
    return np.stack([X, Y, np.zeros_like(X)], -1)


def test_default_tolerance_counts_only_what_the_net_passes_close_to():
    V, F = _cap()
    cov = coverage(_flat_net(), V, F)
    diagonal = float(np.linalg.norm(np.ptp(V, axis=0)))
    assert cov["tolerance"] == pytest.approx(TOLERANCE_OF_DIAGONAL * diagonal)
    assert cov["tolerance_relative"] == pytest.approx(TOLERANCE_OF_DIAGONAL)
    # covered: the disc where the cap's height A r² stays within the tolerance (the distance to
    # the plane is the height up to the slope's cosine, below 1e-2 here)
    r = math.sqrt(cov["tolerance"] / A)
    assert cov["area_fraction"] == pytest.approx(math.pi * r**2 / 100.0, rel=0.06)
    assert cov["area_fraction"] < 0.15           # the old rule (one mean edge) said 100 %


def test_tolerance_is_a_setting():
    V, F = _cap()
    assert coverage(_flat_net(), V, F, tolerance=1.0)["area_fraction"] == pytest.approx(1.0)
    faces = covered_faces(_flat_net(), V, F, tolerance=1.0)
    assert faces.min() == 1.0
    tight = covered_faces(_flat_net(), V, F)
    area = trimesh.Trimesh(V, F, process=False).area_faces
    assert float((tight * area).sum() / area.sum()) == pytest.approx(
        coverage(_flat_net(), V, F)["area_fraction"], abs=1e-12)


def test_inspect_and_optimize_take_the_tolerance_with_a_unit(tmp_path):
    """The fit's artifact, inspect and its --coverage-tol tell the same figure."""
    import json

    V, F = _cap(41)
    trimesh.Trimesh(V, F, process=False).export(tmp_path / "cap.obj")
    dgpc("init", tmp_path / "cap.obj", "--method", "project", "--rows", 9, "--cols", 9,
         "--units", "m", "-o", tmp_path / "n0")
    dgpc("optimize", tmp_path / "n0", "--mode", "fit", "--coverage-tol", "30mm",
         "-o", tmp_path / "fit", expect=None)
    recorded = json.loads((tmp_path / "fit.json").read_text())["metrics"]["coverage"]
    assert recorded["tolerance"] == pytest.approx(0.03)
    again = metrics(tmp_path / "fit", "--coverage-tol", "0.03")     # plain: the net's unit, m
    assert again["coverage"]["area_fraction"] == pytest.approx(recorded["area_fraction"],
                                                               abs=1e-12)
    default = metrics(tmp_path / "fit")["coverage"]
    assert default["tolerance_relative"] == pytest.approx(TOLERANCE_OF_DIAGONAL)
    dgpc("inspect", tmp_path / "fit", "--coverage-tol", "-1mm", expect=2)


def _sphere_patch(k: int, r: float = 10.0):
    """Points of a sphere of radius r on a k×k grid of longitude × latitude (±40°)."""
    t = np.radians(np.linspace(-40.0, 40.0, k))
    L, B = np.meshgrid(t, t, indexing="ij")
    return r * np.stack([np.cos(B) * np.cos(L), np.cos(B) * np.sin(L), np.sin(B)], -1)


def test_a_coarse_net_on_its_reference_covers_it_up_to_its_chord_height():
    """A 7×7 net with its vertices on a sphere lies inside it by its facets' chord height (about
    e²/8R = 0.09 here, 3 % of an edge; the tolerance is 0.2 % of the diagonal, 0.026): it covers
    the patch. Lifted off the sphere by twice its chord height plus the tolerance, it does not."""
    from dgpc_cli.metrics.coverage import chord_height
    from dgpc_cli.metrics.hausdorff import net_triangles

    fine = _sphere_patch(81)
    V, F = net_triangles(fine)
    net = _sphere_patch(7)
    height = chord_height(net)
    e = np.linalg.norm(net[1:] - net[:-1], axis=-1).mean()
    assert height.shape == (6, 6)
    assert e**2 / 80.0 < height.max() < e**2 / 10.0        # the order of e² / 8R, R = 10
    assert coverage(net, V, F)["area_fraction"] == pytest.approx(1.0, abs=2e-3)
    lifted = net * (1.0 + (2.0 * height.max() + 0.03) / 10.0)
    assert coverage(lifted, V, F)["area_fraction"] < 0.05
