"""Several patches where one net is poor (issue "a real roof clad by the default command", item
6): ``init --patches 2`` cuts a mesh of two lobes along the valley between them; ``--patches
auto`` keeps one net where its strips vary in width at most 3x and splits where they vary
more; every patch net's strips trimmed to its patch cover that patch and stay inside it; the
split is recorded (why, the single net's width ratio, K, the cut curves) and drawn by
``report``; the artifacts are valid and byte-deterministic."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc
from outline_meshes import write
from patch_meshes import LOBE_OFFSET, LOBES_SIZE, two_lobes, vault

from dgpc_cli.io.mesh import ReferenceMesh, load_mesh
from dgpc_cli.io.net import read_net
from dgpc_cli.layout.patches import WIDTH_RATIO_LIMIT, width_ratio
from dgpc_cli.stages.strip_fabrication import fabrication_warnings
from dgpc_cli.surfaces.patches import cut_length, split

#: The options that make the single net run along the lobes (the spine), as a user would.
ALONG = ("--method", "geodesic", "--direction", "1,0,0", "--units", "m")


def _area(V, F):
    t = np.asarray(V)[np.asarray(F)]
    return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum()


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    d = tmp_path_factory.mktemp("patches")
    return d, write(d / "lobes.obj", two_lobes()), write(d / "vault.obj", vault())


def test_two_lobes_are_cut_along_the_valley():
    V, F = two_lobes()
    patches, cuts = split(V, F, 2)
    assert len(patches) == 2 and len(cuts) == 1
    (curve,) = cuts[0]["curves"]
    # the valley is the line x = 0 between the lobes at x = ±6 m, across the whole width
    assert np.abs(curve[:, 0]).max() < 0.05
    assert np.ptp(curve[:, 1]) == pytest.approx(LOBES_SIZE[1], abs=1e-9)
    # the patches are the two lobes, halves of the area, nothing lost or doubled
    areas = [p.area for p in patches]
    assert sum(areas) == pytest.approx(_area(V, F), rel=1e-9)
    assert areas[0] == pytest.approx(areas[1], rel=0.02)
    assert patches[0].vertices[:, 0].max() <= 1e-9 < patches[1].vertices[:, 0].max()
    centres = [p.vertices[p.faces].mean(axis=(0, 1)) for p in patches]
    assert centres[0][0] < -LOBE_OFFSET / 2 and centres[1][0] > LOBE_OFFSET / 2
    # each patch keeps the cut on its boundary
    assert all(len(p.cuts) == 1 for p in patches)
    # three patches: the largest half cut again; the middle patch has both cuts on its boundary
    three, cuts = split(V, F, 3)
    assert len(cuts) == 2 and [len(p.cuts) for p in three] == [1, 2, 1]
    assert sum(p.area for p in three) == pytest.approx(_area(V, F), rel=1e-9)


def test_cut_length_is_the_level_sets_length():
    """The measure the cut is chosen by: on a flat 10 × 4 rectangle the level x = c of φ = x is
    4 long, and a level cutting nothing is 0 long."""
    x, y = np.meshgrid(np.linspace(0, 10, 21), np.linspace(0, 4, 9), indexing="ij")
    V = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1)
    from outline_meshes import _grid_faces

    F = _grid_faces(20, 8)
    assert cut_length(V, F, V[:, 0], 3.3) == pytest.approx(4.0, rel=1e-12)
    assert cut_length(V, F, V[:, 0], 11.0) == 0.0


def test_width_ratio_counts_the_rows_on_the_reference(tmp_path):
    """A fan of straight lines on a flat square: strips widening 1 → 4 along them read 4x; the
    same net with its last rows off the plane (a net run past its reference) reads only the
    rows on it."""
    from outline_meshes import _grid_faces

    x, y = np.meshgrid(np.linspace(-1, 11, 25), np.linspace(-10, 10, 41), indexing="ij")
    mesh = ReferenceMesh(np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1),
                         _grid_faces(24, 40), tmp_path / "plane.obj", "")
    u = np.linspace(0, 10, 11)[:, None]
    v = np.linspace(-1, 1, 5)[None, :]
    f = np.stack(np.broadcast_arrays(u, v * (1 + 0.3 * u), 0 * u * v), -1)
    got = width_ratio(f, mesh)
    assert got["ratio"] == pytest.approx(4.0, rel=1e-9)
    lifted = f.copy()
    lifted[6:, :, 2] = 1.0
    assert width_ratio(lifted, mesh)["ratio"] == pytest.approx(2.5, rel=1e-9)


def test_patches_2_writes_one_net_per_lobe(meshes, tmp_path):
    d, lobes, _ = meshes
    r = dgpc("init", lobes, *ALONG, "--patches", 2, "-o", tmp_path / "a")
    paths = r.stdout.split()
    assert [p.split("/")[-1] for p in paths] == ["a.p1.json", "a.p2.json", "a.json"]
    paths = paths[:-1]                            # the nets; a.json is their patch set
    whole = load_mesh(lobes)
    total = 0.0
    for k, path in enumerate(paths, start=1):
        net = read_net(path)                      # validated against the schema
        record = net.data["patches"]
        assert record["count"] == 2 and record["name"] == f"p{k}"
        assert record["requested"] == 2 and record["reason"].startswith("--patches 2")
        assert record["single"]["width_ratio"] > WIDTH_RATIO_LIMIT
        (cut,) = record["cuts"]
        assert np.abs(np.asarray(cut["curves"][0])[:, 0]).max() < 0.05
        assert net.inputs["mesh"]["path"].endswith("lobes.obj")
        assert net.data["reference"]["path"] == f"a.p{k}.patch.obj"
        patch = load_mesh(tmp_path / f"a.p{k}.patch.obj")
        total += _area(patch.vertices, patch.faces)
        # the net lies on its own patch: its x keeps to that side of the valley, but for the
        # overhang the search gave it, which runs on over the other lobe (the whole mesh)
        side = np.sign(net.f[..., 0].mean())
        assert side == (-1 if k == 1 else 1)
        reach = net.extend * patch.bbox_diagonal
        assert (side * net.f[..., 0] >= -reach - 1e-9).all()
        if net.extend:
            assert net.data["surroundings"] == net.inputs["mesh"]
            assert (side * net.f[..., 0] < -0.5 * reach).any()
        assert net.metrics["coverage"]["area_fraction"] > 0.9
    assert total == pytest.approx(_area(whole.vertices, whole.faces), rel=1e-9)
    # deterministic: the same command into another folder as deep writes the same bytes
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    for name in ("one", "two"):
        dgpc("init", lobes, *ALONG, "--patches", 2, "-o", tmp_path / name / "a")
    for k in (1, 2):
        for suffix in ("json", "obj", "patch.obj"):
            assert (tmp_path / "one" / f"a.p{k}.{suffix}").read_bytes() == \
                (tmp_path / "two" / f"a.p{k}.{suffix}").read_bytes(), (k, suffix)


def test_auto_keeps_one_net_where_widths_vary_little(meshes, tmp_path):
    _, _, vault_obj = meshes
    r = dgpc("init", vault_obj, *ALONG, "--patches", "auto", "-o", tmp_path / "v")
    assert r.stdout.split() == [str(tmp_path / "v.json")]
    assert not list(tmp_path.glob("v.p*"))
    record = read_net(tmp_path / "v").data["patches"]
    assert record["count"] == 1 and record["requested"] == "auto"
    assert record["single"]["width_ratio"] <= WIDTH_RATIO_LIMIT
    assert "one patch" in record["reason"] and "one patch" in r.stderr


def test_auto_splits_where_widths_vary_more_than_3x(meshes, tmp_path):
    _, lobes, _ = meshes
    r = dgpc("init", lobes, *ALONG, "--patches", "auto", "-o", tmp_path / "l")
    assert [p.split("/")[-1] for p in r.stdout.split()] == ["l.p1.json", "l.p2.json",
                                                             "l.json"]
    for k in (1, 2):
        record = read_net(tmp_path / f"l.p{k}").data["patches"]
        assert record["single"]["width_ratio"] > WIDTH_RATIO_LIMIT
        assert record["count"] == 2 and "more than 3x" in record["reason"]
        # the split is what made the widths vary little: every patch at most 3x
        assert all(p["width_ratio"] <= WIDTH_RATIO_LIMIT for p in record["patches"])
    assert "2 patches" in r.stderr


def test_each_patch_trimmed_parts_cover_its_patch(meshes, tmp_path):
    """Nets run past their patch (--extend) and trimmed to it: the parts cover the patch (the
    area of the parts over the patch's, ≥ 99 %) and keep out of the neighbour's (≤ 100.1 %)."""
    _, lobes, _ = meshes
    dgpc("init", lobes, *ALONG, "--patches", 2, "--extend", 0.2, "-o", tmp_path / "e")
    for k in (1, 2):
        net = read_net(tmp_path / f"e.p{k}")
        assert net.extend > 0
        dgpc("planarize-strips", tmp_path / f"e.p{k}", "--trim", "-o", tmp_path / f"s{k}")
        fab = json.loads((tmp_path / f"s{k}.json").read_text())["metrics"]["fabrication"]
        patch = load_mesh(tmp_path / f"e.p{k}.patch.obj")
        assert fab["area_reference"] == "outline"
        assert fab["reference_area_m2"] == pytest.approx(_area(patch.vertices, patch.faces),
                                                      rel=1e-6)
        assert 0.99 <= fab["area_ratio"] <= 1.001, fab["area_ratio"]


def test_report_draws_the_cut_curves(meshes, tmp_path):
    _, lobes, vault_obj = meshes
    dgpc("init", lobes, *ALONG, "--patches", 2, "--extend", 0, "-o", tmp_path / "a")
    dgpc("report", tmp_path / "a.p1", "-o", tmp_path / "fig")
    assert (tmp_path / "fig-patches.png").stat().st_size > 0
    assert "cut curves" in (tmp_path / "fig-index.html").read_text() or \
        "red curves" in (tmp_path / "fig-index.html").read_text()
    dgpc("init", vault_obj, "--method", "geodesic", "--units", "m", "-o", tmp_path / "v")
    dgpc("report", tmp_path / "v", "-o", tmp_path / "vfig")
    assert not (tmp_path / "vfig-patches.png").exists()


def test_patches_figure_draws_the_curves():
    from dgpc_cli.report.patches import cut_segments

    curves = [[[0, 0, 0], [1, 0, 0], [2, 1, 0]], [[5, 5, 5], [6, 5, 5]]]
    segs = cut_segments(curves)
    assert segs.shape == (3, 2, 3)
    assert np.allclose(segs[1], [[1, 0, 0], [2, 1, 0]])


@pytest.mark.parametrize("args, message", [
    (("--patches", 0), "not 'auto' or a number of patches"),
    (("--patches", "some"), "not 'auto' or a number of patches"),
    (("--patches", 2, "--base", "b1"), "names a boundary curve of the whole mesh"),
])
def test_bad_patch_options(meshes, tmp_path, args, message):
    _, lobes, _ = meshes
    r = dgpc("init", lobes, "--method", "geodesic", *args, "-o", tmp_path / "x", expect=2)
    assert message in r.stderr
    assert not list(tmp_path.glob("x*"))


def test_patches_need_a_mesh(tmp_path):
    r = dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
             "--patches", 2, "-o", tmp_path / "x", expect=2)
    assert "--patches goes with REFERENCE and --method" in r.stderr


def test_end_gap_warning_takes_a_strip_trimmed_away():
    fab = {"max_end_gap_mm": 5.0, "area_ratio": 1.0,
           "per_strip": {"S-v00": {"end_gaps_mm": [5.0, 1.0]},
                         "S-v01": {"end_gaps_mm": [None, None]}}}
    (line,) = fabrication_warnings(fab)
    assert "(S-v00)" in line


def test_a_batch_refuses_patches_in_its_init(tmp_path):
    """A batch patch is one net: ``patches`` in a project's init table is refused, pointing to
    the patch meshes ``init --patches`` writes."""
    from dgpc_cli.batch.project import RESERVED

    assert "STEM.pK.patch.obj" in RESERVED["patches"]
    (tmp_path / "p.toml").write_text("[patches.a.init]\npatches = 2\n")
    r = dgpc("batch", tmp_path / "p.toml", "-o", tmp_path / "out", expect=1)
    assert "patches.a.init.patches: not in a project file" in r.stderr


def test_a_mesh_too_small_for_k_patches_is_one_line_exit_1(tmp_path):
    from outline_meshes import _grid_faces

    x, y = np.meshgrid(np.linspace(0, 4, 7), np.linspace(0, 3, 6), indexing="ij")
    V = np.stack([x.ravel(), y.ravel(), 0.1 * x.ravel() ** 2], 1)
    mesh = write(tmp_path / "small.obj", (V, _grid_faces(6, 5)))
    r = dgpc("init", mesh, "--method", "geodesic", "--cols", 3, "--patches", 12,
             "-o", tmp_path / "s", expect=1)
    assert "cannot cut the mesh into 12 patches" in r.stderr and "too small" in r.stderr
    assert r.stderr.count("\n") <= 3 and "Traceback" not in r.stderr


def test_existing_patch_nets_are_kept_without_force(meshes, tmp_path):
    """A second run without --force refuses before writing anything (exit 1, one line), and
    leaves the first run's files as they were; with --force it writes them again."""
    _, lobes, _ = meshes
    dgpc("init", lobes, *ALONG, "--patches", 2, "--extend", 0, "-o", tmp_path / "a")
    (tmp_path / "a.p1.json").unlink()
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    r = dgpc("init", lobes, *ALONG, "--patches", 2, "--extend", 0, "-o", tmp_path / "a", expect=1)
    # the patch set a.json, checked first
    assert "already exists; use --force" in r.stderr and "a.json" in r.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
    dgpc("init", lobes, *ALONG, "--patches", 2, "--extend", 0, "-o", tmp_path / "a", "--force")
    assert (tmp_path / "a.p1.json").is_file()
