"""Imports (issue: "closed quad rings are refused", "extract-mold refuses a float32 net"): a
surface of revolution meshed all round comes in cut at a seam, and a net written with 7
significant digits goes through extract-mold at its default tolerance."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.net import read_net
from dgpc_cli.layout.quads import cut_ring, init_from_quads
from dgpc_cli.surfaces.profiles import profile_from_spec
from dgpc_cli.surfaces.revolution import revolution_net


def ring_obj(path, m=9, around=16, seed=3, digits=None):
    """A closed ring of quads (m rows, ``around`` vertices per row, no duplicate seam) of the
    built-in cone, vertex ids shuffled; returns the ring's vertices ``(m, around, 3)``."""
    f = revolution_net(profile_from_spec("cone"), m, around + 1, span_deg=360.0)[:, :-1]
    perm = np.random.default_rng(seed).permutation(m * around)     # file id of grid vertex
    vid = perm.reshape(m, around)
    nxt = np.roll(vid, -1, axis=1)
    quads = np.stack([vid[:-1], vid[1:], nxt[1:], nxt[:-1]], -1).reshape(-1, 4)
    V = np.empty((m * around, 3))
    V[perm] = f.reshape(-1, 3)
    fmt = (lambda x: f"{x:.{digits}g}") if digits else repr
    lines = [f"v {fmt(a)} {fmt(b)} {fmt(c)}" for a, b, c in V.tolist()]
    lines += ["f " + " ".join(str(i + 1) for i in q) for q in quads.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return f


def test_a_closed_ring_is_cut_at_a_seam(tmp_path):
    f = ring_obj(tmp_path / "ring.obj")
    net = init_from_quads(tmp_path / "ring.obj")
    m, n = net.shape
    assert (m, n) == (9, 17)                          # the seam column twice
    assert np.array_equal(net.f[:, 0], net.f[:, -1])
    seam = net.data["init"]["seam"]
    assert seam["closed"] and seam["line"] == "column" and len(seam["file_vertices"]) == 9
    # the meridians (geodesics) are the u-lines (rows at one height), every vertex is there
    assert np.abs(np.diff(net.f[:, :, 2], axis=1)).max() < 1e-12
    got = {tuple(np.round(p, 9)) for p in net.f[:, :-1].reshape(-1, 3).tolist()}
    assert got == {tuple(np.round(p, 9)) for p in f.reshape(-1, 3).tolist()}
    dv = np.linalg.norm(np.diff(net.f, axis=1), axis=-1)
    assert (np.ptp(dv, axis=1) <= 1e-9 * dv.max()).all()   # equal steps round each row,
    #                                                           the seam included


def test_a_ring_goes_through_init_and_extract_mold(tmp_path):
    ring_obj(tmp_path / "ring.obj")
    dgpc("init", "--from-quads", tmp_path / "ring.obj", "-o", tmp_path / "net")
    assert read_net(tmp_path / "net").data["init"]["seam"]["line"] == "column"
    dgpc("extract-mold", tmp_path / "net", "-o", tmp_path / "mold")
    mold = json.loads((tmp_path / "mold.json").read_text())
    assert mold["data"]["segments"] == 16                      # one full turn: n − 1
    assert mold["data"]["angle_step_deg"] == pytest.approx(22.5)
    assert mold["metrics"]["isometry_error_max"] <= 1e-9


def test_a_mesh_closed_all_round_is_refused():
    # a torus of 4 × 4 quads: no boundary at all
    vid = np.arange(16).reshape(4, 4)
    quads = np.stack([vid, np.roll(vid, -1, 0), np.roll(np.roll(vid, -1, 0), -1, 1),
                      np.roll(vid, -1, 1)], -1).reshape(-1, 4)
    with pytest.raises(DgpcError, match="closed all round"):
        cut_ring(quads, 16, "torus.obj")


def test_a_float32_revolution_net_passes_extract_mold_at_the_default_tolerance(tmp_path):
    """The authors' surface-of-revolution nets carry 7 significant digits (float32)."""
    f = revolution_net(profile_from_spec("bowling-pin"), 21, 13, span_deg=120.0)
    lines = [f"v {a:.7g} {b:.7g} {c:.7g}" for a, b, c in f.reshape(-1, 3).tolist()]
    vid = np.arange(21 * 13).reshape(21, 13) + 1
    quads = np.stack([vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]], -1)
    lines += ["f " + " ".join(map(str, q)) for q in quads.reshape(-1, 4).tolist()]
    (tmp_path / "pin-f32.obj").write_text("\n".join(lines) + "\n")
    dgpc("init", "--from-quads", tmp_path / "pin-f32.obj", "-o", tmp_path / "pin32")
    rounded = read_net(tmp_path / "pin32").f
    assert 0 < np.abs(rounded - f).max() <= 1e-6 * np.abs(f).max()
    r = dgpc("extract-mold", tmp_path / "pin32", "-o", tmp_path / "mold")
    assert (tmp_path / "mold.json").exists() and "Error" not in r.stderr
    # the tolerance it used (twice --max-strain) is recorded
    assert json.loads((tmp_path / "mold.json").read_text())["parameters"]["revolution_tol"] == 6e-4
