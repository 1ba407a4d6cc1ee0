"""A patch's net runs past the patch onto the whole mesh around it (``init --patches``:
``geodesics.extension.surrounded``), not onto the patch's own tangent-plane continuation, which
folds at the patch's concave corners and leaves the surface across a cut: on the arched roof of
two corners (tests/outline_meshes.py) the patch that holds the apse is clad to 97 % and more
only so."""

from pathlib import Path

import numpy as np
import pytest
from outline_meshes import arch_roof

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.geodesics.extension import surrounded
from dgpc_cli.io.mesh import ReferenceMesh, clean_mesh
from dgpc_cli.layout.search import EXTEND_BELOW, search
from dgpc_cli.stages.init import quick_fitter
from dgpc_cli.surfaces.patches import split


@pytest.fixture(scope="module")
def roof_patches():
    V, F = arch_roof()
    whole = ReferenceMesh(V, F, Path("roof.obj"), "0")
    patches, _ = split(V, F, 2)
    out = []
    for k, p in enumerate(patches):
        pv, pf = clean_mesh(p.vertices, p.faces)
        out.append(ReferenceMesh(pv, pf, Path(f"roof.p{k + 1}.patch.obj"), str(k)))
    return whole, sorted(out, key=lambda m: -len(m.faces))


def test_the_surroundings_are_the_whole_mesh_within_reach_of_the_patch(roof_patches):
    whole, (big, small) = roof_patches
    fraction = 0.1
    reach = fraction * small.bbox_diagonal
    around = surrounded(small, whole, fraction)
    assert surrounded(small, whole, 0.0) is small
    # it holds the patch ...
    on = ReferenceSurface(around.vertices, around.faces)
    P = small.vertices
    assert np.linalg.norm(P - on.closest(P)[0], axis=1).max() < 1e-9 * whole.bbox_diagonal
    # ... and reaches about as far past it as asked, no further than a face beyond
    foot, _ = ReferenceSurface(small.vertices, small.faces).closest(around.vertices)
    away = np.linalg.norm(around.vertices - foot, axis=1)
    assert 0.9 * reach < away.max() < reach + 2.0
    # across the cut it is the whole mesh itself (the other patch), not a tangent plane
    over_big = ReferenceSurface(big.vertices, big.faces)
    Q = around.vertices[away > 0.5 * reach]
    q_on_big = np.linalg.norm(Q - over_big.closest(Q)[0], axis=1) < 1e-9 * whole.bbox_diagonal
    assert q_on_big.sum() > 50


def test_the_apse_patch_is_clad_only_with_the_overhang_onto_its_surroundings(roof_patches):
    whole, (apse, _) = roof_patches
    onto_whole = search(apse, fit=quick_fitter, cols=21, surroundings=whole)
    own = search(apse, fit=quick_fitter, cols=21)
    assert onto_whole.chosen.quick["coverage"] >= EXTEND_BELOW
    assert not onto_whole.chosen.quick["folded"]
    assert onto_whole.chosen.quick["narrowest"] > 0.25
    assert own.chosen.quick["coverage"] < EXTEND_BELOW
    assert onto_whole.extend > own.extend       # the own continuation folds sooner
