"""Issue 27, the default chain on an arched roof of about 40 × 39 m (two corners, an arch
edge, a curved ground edge, bumps and saddles; ``outline_meshes.arch_roof`` at full size, its
mesh at 0.6 m spacing): `init MESH` finds one net poor and makes patches by itself, each with
strips no wider than 2.4 m (``init --strip-width``'s default), and `optimize --mode fit`,
`planarize-strips --trim`, `unfold --stock-length 6` (joints inside a quad where two rulings
are more than 6 m apart) and `nest --sheet 6100x2500` take the patch set as they take one net
(nest: every member's boards together). Every stage exits 0, no fitted net folds, the trimmed
parts cover at least 97 % of the roof, no part is narrower than a quarter of its patch's mean
width, every board is at most 6 m and every one is placed on a sheet."""

import numpy as np
import pytest
from cli_helpers import dgpc, metrics
from outline_meshes import arch_roof, write
from shapely.geometry import Polygon
from test_default_chain import STOCK, mesh_area

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.patch_set import member_stems, read_patch_set
from dgpc_cli.io.sheets import read_sheets

#: The roof's scale and its mesh's spacing (m, before scaling).
SCALE, SPACING = 1.0, 0.6
SHEET = "6100x2500"


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    d = tmp_path_factory.mktemp("archchain")
    V, F = arch_roof(SPACING)
    mesh = write(d / "roof.obj", (SCALE * V, F))
    init = dgpc("init", mesh, "--units", "m", "-o", d / "n0")
    dgpc("optimize", d / "n0", "--mode", "fit", "-o", d / "n1")
    dgpc("planarize-strips", d / "n1", "--trim", "-o", d / "s")
    dgpc("unfold", d / "s", "--stock-length", STOCK, "-o", d / "f")
    dgpc("nest", d / "f", "--sheet", SHEET, "--no-preview", "-o", d / "sheets")
    return d, mesh, init.stderr


def test_init_makes_patches_by_itself(chain):
    d, _, stderr = chain
    assert len(read_patch_set(d / "n0")["data"]["members"]) >= 2
    assert "trying --patches auto" in stderr
    for name in ("n1", "s", "f"):
        assert [n for n, _ in member_stems(d / name)] == \
            [n for n, _ in member_stems(d / "n0")], name


def test_the_fitted_nets_do_not_fold(chain):
    d, _, _ = chain
    for _, stem in member_stems(d / "n1"):
        assert not metrics(stem)["edges"]["folded"], stem


def test_the_boards_cover_the_roof_and_fit_the_stock_and_the_sheets(chain):
    d, mesh, _ = chain
    parts = {f"{stem.name}:{p['id']}": p for _, stem in member_stems(d / "f")
             for p in read_flat(stem).parts}
    area = sum(Polygon(p["outline"]).area for p in parts.values())
    assert 0.97 * mesh_area(mesh) <= area <= 1.001 * mesh_area(mesh)
    for key, p in parts.items():
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9, key
    placed = sorted(q["part"] for q in read_sheets(d / "sheets").data["placements"])
    assert placed == sorted(parts)


def test_no_part_is_pinched(chain):
    """The narrowest part of each patch is at least a quarter of its patch's mean width."""
    d, _, _ = chain
    for _, stem in member_stems(d / "f"):
        narrowest = metrics(stem)["narrowest"]
        assert narrowest["ratio"] >= 0.25, (stem, narrowest)
