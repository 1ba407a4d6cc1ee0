"""Real reference meshes (issue "cover the whole surface, clad it to its edge"): on a roof with
one curved and three straight edges and on a dome cut by a plane, the default init and a fit
cover nearly all of the surface with a sound net; a net run past the roof and fitted meets
the paper's gridshell figure (Fig. 14: reference-to-net Hausdorff ≤ 1.2e-3 of the diagonal);
its strips trimmed to the roof's outline develop into parts that clad all of it."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc, metrics
from outline_meshes import clipped_dome, roof, write

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.fitting.optimize import RELEASE_R
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.metrics.degenerate import degeneracies


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    d = tmp_path_factory.mktemp("outline")
    return {"roof": write(d / "roof.obj", roof()),
            "dome": write(d / "dome.obj", clipped_dome())}


@pytest.fixture(scope="module", params=["roof", "dome"])
def fitted(request, meshes):
    mesh = meshes[request.param]
    stem = mesh.with_suffix("")
    r = dgpc("init", mesh, "--method", "geodesic", "-o", f"{stem}-0")
    # fitted to a triangle mesh, R settles near 1e-9 (closest points hop between facets), as
    # in the gridshell pipeline
    dgpc("optimize", f"{stem}-0", "--mode", "fit", "--tol", 1e-8, "-o", f"{stem}-fit")
    return request.param, mesh, stem, r.stderr


def test_default_init_and_fit_cover_the_surface_with_a_sound_net(fitted):
    name, mesh, stem, stderr = fitted
    init = read_net(f"{stem}-0")
    choice = init.data["init"]["choice"]
    # it said what it chose and how much it covers, on stderr and in the artifact
    assert f"covering {100 * choice['coverage']:.1f} %" in stderr
    assert choice["chosen"] in stderr
    tried = [t for t in choice["tried"] if "coverage" in t]
    assert len(choice["tried"]) >= 4 and choice["coverage"] >= max(
        t["coverage"] for t in tried) - 0.005
    m0, m1 = metrics(f"{stem}-0"), metrics(f"{stem}-fit")
    assert m0["coverage"]["area_fraction"] >= 0.95
    assert m1["coverage"]["area_fraction"] >= 0.95                  # the fit keeps it
    assert m1["coverage"]["area_fraction"] >= m0["coverage"]["area_fraction"] - 0.005
    fit = read_net(f"{stem}-fit")
    assert fit.status["state"] == "converged"
    assert not degeneracies(fit.f) and not degeneracies(init.f)
    assert m1["gpc_angle_defect_max"] <= 1e-6
    # what the fit guarantees on a triangle mesh: the approximation within --tol, or, where
    # the closest points hop between facets and the fit stalls below RELEASE_R, the net
    # projected onto its other hard terms (approximation then listed as soft), every vertex
    # moved at most RELEASE_MOVE mean edges: the approximation stays below RELEASE_R (the roof
    # stalls at 1.8e-7 on one CPU, below 1e-8 on another)
    if "approximation" in fit.parameters["soft"]:
        assert m1["residuals"]["approximation"] <= RELEASE_R
    else:
        assert m1["residuals"]["approximation"] <= 1e-8


def test_the_dome_default_is_not_the_folded_section(meshes):
    """The section along the longest principal axis gives geodesics that meet at the poles of
    the dome (on its rim): folded rows; the default's geodesics run from the cut arc (the arc
    itself or the section parallel to it) and it says so."""
    stem = meshes["dome"].with_suffix("")
    dgpc("init", meshes["dome"], "--method", "geodesic", "-o", f"{stem}-auto")
    init = read_net(f"{stem}-auto")
    choice = init.data["init"]["choice"]
    assert choice["chosen"] in ("boundary b2", "along the second extent")
    assert choice["coverage"] >= 0.97
    r = dgpc("init", meshes["dome"], "--method", "geodesic", "--base", "section",
             "-o", f"{stem}-section")
    assert "degenerate" in r.stderr and "shrunk" in r.stderr
    section = read_net(f"{stem}-section")
    assert section.data["init"]["shrunk"]["degenerate"]["degenerate"]
    assert not degeneracies(section.f)


def mesh_area(mesh) -> float:
    V, F = mesh.vertices, mesh.faces
    return float(0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]),
                                      axis=1).sum())


@pytest.fixture(scope="module")
def extended(meshes):
    mesh = meshes["roof"]
    stem = mesh.with_suffix("")
    dgpc("init", mesh, "--method", "geodesic", "--extend", 0.1, "-o", f"{stem}-e0")
    dgpc("optimize", f"{stem}-e0", "--mode", "fit", "--tol", 1e-8, "-o", f"{stem}-e")
    return stem


def test_an_extended_roof_net_fits_to_the_gridshell_figure(extended):
    m = metrics(f"{extended}-e")
    h = m["hausdorff"]
    assert m["coverage"]["area_fraction"] == pytest.approx(1.0, abs=1e-9)
    assert h["reference_to_net_max"] <= 1.2e-3 * h["diagonal"]
    net = read_net(f"{extended}-e")
    assert net.status["state"] == "converged" and not degeneracies(net.f)
    assert m["gpc_angle_defect_max"] <= 1e-6


def test_trimmed_strips_clad_the_whole_roof(extended, meshes):
    dgpc("planarize-strips", f"{extended}-e", "--trim", "-o", f"{extended}-s")
    dgpc("unfold", f"{extended}-s", "-o", f"{extended}-flat")
    mesh = load_mesh(meshes["roof"])
    area = mesh_area(mesh)
    flat = json.loads((extended.parent / f"{extended.name}-flat.json").read_text())
    assert flat["metrics"]["max_strain"] <= 1e-9                     # planar quads
    k = mm_per_unit(flat["data"]["units"])
    area_m2 = area * k * k * 1e-6
    total = flat["metrics"]["total_area_m2"]
    assert 0.98 * area_m2 <= total <= 1.001 * area_m2
    assert all(p.get("trimmed") for p in flat["data"]["parts"])
    # its OBJ (outlines and score lines, not quad strips) reads back against the JSON
    assert len(read_flat(f"{extended}-flat").parts) == len(flat["data"]["parts"])
    # the end cuts follow the outline: every cut point (inside the strip's width) lies on the
    # roof's boundary, within a small fraction of the strip width. Not a figure the last bits
    # leave alone: 0.44 % of the width with MKL's AVX-512 code path, 2.4 % with its AVX2 path
    # (the planar strips lie within 1.5 % of the width of the net); 5 % holds both with a
    # margin of two
    strips = read_strips(f"{extended}-s")
    surface = ReferenceSurface.from_mesh(mesh)
    worst = 0.0
    for record in strips.records:
        for part in record["trim"]["parts"]:
            ts = np.asarray(part["outline"])
            cut = (ts[:, 1] > 1e-9) & (ts[:, 1] < 1 - 1e-9)
            if cut.any():
                p = np.asarray(part["outline_3d"])[cut]
                foot, _ = surface.closest_on_boundary(p)
                worst = max(worst, float(np.linalg.norm(p - foot, axis=1).max())
                            / record["width"])
    assert worst <= 0.05
    # the fabrication metrics measure the trimmed parts: against the outline, the parts'
    # ends lie on it and their area is the flat parts' (m², from the net's unit)
    fab = strips.metrics["fabrication"]
    assert fab["area_reference"] == "outline"
    assert fab["area_m2"] == pytest.approx(total, rel=1e-9)
    assert fab["reference_area_m2"] == pytest.approx(area_m2, rel=1e-9)
    assert fab["max_end_gap_mm"] <= 0.02 * fab["mean_width_mm"]


def test_trimmed_strips_clad_the_whole_clipped_dome(meshes):
    """The dome run past its rim (0.3 of its diagonal: at 0.1 the net's corners stay inside
    the curved rim) and fitted covers all of it; its strips trimmed to the outline (the ground
    circle and the cut arc) develop into parts that add up to its area."""
    mesh = meshes["dome"]
    stem = mesh.with_suffix("")
    dgpc("init", mesh, "--method", "geodesic", "--extend", 0.3, "-o", f"{stem}-e0")
    dgpc("optimize", f"{stem}-e0", "--mode", "fit", "--tol", 1e-8, "-o", f"{stem}-e")
    net = read_net(f"{stem}-e")
    assert net.status["state"] == "converged" and not degeneracies(net.f)
    assert metrics(f"{stem}-e")["coverage"]["area_fraction"] >= 0.999
    dgpc("planarize-strips", f"{stem}-e", "--trim", "-o", f"{stem}-s")
    dgpc("unfold", f"{stem}-s", "-o", f"{stem}-flat")
    flat = json.loads((stem.parent / f"{stem.name}-flat.json").read_text())
    assert flat["metrics"]["max_strain"] <= 1e-9
    k = mm_per_unit(flat["data"]["units"])
    area = mesh_area(load_mesh(mesh)) * k * k * 1e-6
    assert 0.98 * area <= flat["metrics"]["total_area_m2"] <= 1.001 * area
