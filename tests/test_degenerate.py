"""Degenerate nets (issue: "no folded or collapsed net goes on silently"): the check that says
what is wrong and where, and the fabrication stages that refuse such a net with one line."""

import numpy as np
import pytest
from cli_helpers import dgpc
from test_mesh_inputs import one_line_error

from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import NetArtifact, write_net
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.metrics.degenerate import degeneracies, index_ranges
from dgpc_cli.surfaces.profiles import profile_from_spec
from dgpc_cli.surfaces.revolution import revolution_net


def plane(m=7, n=6, h=1.0):
    u, v = np.meshgrid(np.arange(m) * h, np.arange(n) * h, indexing="ij")
    return np.stack([u, v, np.zeros_like(u)], axis=-1)


def folded(m=9, n=6, at=4):
    """A plane grid folded back over itself at row ``at`` (a sharp crease of 180°, as a
    pleated or over-extended net has)."""
    f = plane(m, n)
    f[at + 1:, :, 0] = 2 * f[at, 0, 0] - f[at + 1:, :, 0]
    f[at + 1:, :, 2] = 0.05 * np.arange(1, m - at)[:, None]   # lifted a little: not coplanar
    return f


def test_index_ranges():
    assert index_ranges([8, 0, 1, 2, 5, 7, 2]) == "0-2, 5, 7-8"
    assert index_ranges([]) == "none"


def test_a_smooth_net_is_sound():
    f = revolution_net(profile_from_spec("sphere"), 11, 9, span_deg=120.0)
    found = degeneracies(f)
    assert not found and found.message() == ""
    assert found.gpc_defect_max < 1e-9 and found.edge_ratio_min > 0.1
    assert found.bad_quads.shape == (10, 8)


def test_collapsed_rows_are_named():
    """The issue's collapsed net: every edge between rows 0 and 1 of length 0."""
    f = revolution_net(profile_from_spec("cone"), 8, 12, span_deg=90.0)
    f[0] = f[1]
    found = degeneracies(f)
    assert found.any
    assert found.short_u.tolist() == [[0, v] for v in range(12)]
    assert len(found.short_v) == 0
    assert found.bad_quads[0].all() and not found.bad_quads[2:].any()
    assert found.edge_ratio_min == 0.0
    msg = found.message()
    assert "12 edges shorter than 0.001" in msg and "rows 0-1" in msg and "columns 0-11" in msg
    assert found.record()["short_edges"] == 12 and 0 in found.record()["rows"]


def test_a_fold_is_found_at_its_crease():
    found = degeneracies(folded(), gpc_limit=None)
    assert found.any and len(found.short_u) == 0
    rows = set(found.flipped[:, 0].tolist())
    assert rows == {3, 4}                          # the quads either side of the crease
    assert "folded or flipped" in found.message() and "rows 3-5" in found.message()


def test_a_quad_folded_over_itself():
    f = plane(4, 4)
    f[2, 2] = [0.5, 0.5, 0.0]                      # the corner pulled across the diagonal
    found = degeneracies(f, gpc_limit=None)
    assert [1, 1] in found.flipped.tolist()


def test_a_large_gpc_defect_is_degenerate_a_small_one_is_not():
    f = plane(7, 7)
    f[3, 3] += [0.0, 0.02, 0.0]                    # defect ≈ 0.04 rad
    assert not degeneracies(f)
    f[3, 3] += [0.0, 0.2, 0.0]                     # ≈ 0.4 rad
    found = degeneracies(f)
    assert found.any and [3, 3] in found.gpc.tolist()
    assert found.gpc_defect_max > 0.3
    assert not found.flipped.size and not found.short_u.size
    assert "gpc angle defect" in found.message()
    assert not degeneracies(f, gpc_limit=None)


def test_laths_refuse_a_folded_net(tmp_path):
    write_net(tmp_path / "a", NetArtifact(f=folded()))
    g = plane(9, 6)[:, :, [1, 0, 2]]
    write_net(tmp_path / "b", NetArtifact(f=g))
    r = dgpc("laths", tmp_path / "a", tmp_path / "b", "-o", tmp_path / "l", expect=1)
    one_line_error(r, "a.json", "degenerate", "rows 3-5")
    assert not list(tmp_path.glob("l.*"))
    # the same pair unfolded is fine
    write_net(tmp_path / "a2", NetArtifact(f=plane(9, 6)))
    dgpc("laths", tmp_path / "a2", tmp_path / "b", "-o", tmp_path / "l")


def test_extract_mold_refuses_a_collapsed_net(tmp_path):
    f = revolution_net(profile_from_spec("cone"), 8, 12, span_deg=90.0)
    write_net(tmp_path / "ok", NetArtifact(f=f))
    dgpc("extract-mold", tmp_path / "ok", "-o", tmp_path / "mold")
    f[0] = f[1]
    write_net(tmp_path / "bad", NetArtifact(f=f))
    r = dgpc("extract-mold", tmp_path / "bad", "-o", tmp_path / "mold2", expect=1)
    one_line_error(r, "bad.json", "rows 0-1", "shorter than")
    assert not list(tmp_path.glob("mold2*"))


def test_planarize_strips_refuses_a_folded_net(tmp_path):
    write_net(tmp_path / "n", NetArtifact(f=folded()))
    r = dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s", expect=1)
    one_line_error(r, "n.json", "folded")
    assert not list(tmp_path.glob("s.*"))


@pytest.mark.parametrize("bad", ["collapsed", "folded"])
def test_unfold_refuses_a_degenerate_strip(tmp_path, bad):
    A = np.stack([np.arange(6.0), np.zeros(6), np.zeros(6)], 1)
    B = A + [0.0, 1.0, 0.0]
    sound = (A - [0, 1, 0], B - [0, 1, 0])
    if bad == "collapsed":
        B[2] = A[2]
    else:
        A[4:, 0] = 2 * A[3, 0] - A[4:, 0]
        B[4:, 0] = 2 * B[3, 0] - B[4:, 0]
        A[4:, 2] = B[4:, 2] = 0.1
    records = [{"id": f"S-v0{i}", "v": i, "rows": 6, "planarity": 0.0, "deviation": 0.0,
                "width": 1.0, "ruling_directions": np.tile([0.0, 1, 0], (6, 1)).tolist(),
                "flat_rows": [True] * 6, "params": [[float(u), 0.0] for u in range(6)],
                "polish": {"applied": False}} for i in range(2)]
    art = StripsArtifact(geometry=[sound, (A, B)], records=records,
                         source_shape=(6, 3))
    write_files(strips_files(tmp_path / "s", art))
    r = dgpc("unfold", tmp_path / "s", "-o", tmp_path / "flat", expect=1)
    one_line_error(r, "s.json", "S-v01", bad, "rows")
    assert not list(tmp_path.glob("flat*"))


@pytest.mark.parametrize("mode", ["revolution", "isometric"])
def test_a_collapsed_optimize_is_degenerate_not_converged(tmp_path, mode):
    """Handles that pull row 1 of a catenoid net onto row 0: the solver meets every hard term
    (R ~ 1e-11), and the net it writes has collapsed u-edges between rows 0 and 1 — state
    ``degenerate``, exit 3, the rows named, never ``converged``."""
    import json

    from dgpc_cli.io.net import read_net

    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 6,
         "--span", 120, "-o", tmp_path / "c0")
    f = read_net(tmp_path / "c0").f
    handles = [{"index": [u, v], "target": f[0, v].tolist()} for u in (0, 1) for v in range(6)]
    (tmp_path / "h.json").write_text(json.dumps({"handles": handles}))
    r = dgpc("optimize", tmp_path / "c0", "--mode", mode, "--handles", tmp_path / "h.json",
             "-o", tmp_path / "c1", expect=3)
    one_line_error(r, "c1.json", "degenerate", "rows 0-1", "shorter than")
    out = read_net(tmp_path / "c1")
    assert out.status["state"] == "degenerate"
    lu = np.linalg.norm(np.diff(out.f, axis=0), axis=-1)
    assert lu[0].max() <= 1e-3 * lu[1:].mean()                 # the collapse it names is real
