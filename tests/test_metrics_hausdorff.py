"""Two-sided Hausdorff distance through pymeshlab (SPEC §7)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from dgpc_cli.metrics.hausdorff import hausdorff, net_triangles, surface_samples


def plane_net(m=11, n=11, size=(1.0, 1.0), z=0.0):
    u, v = np.meshgrid(np.linspace(0, size[0], m), np.linspace(0, size[1], n), indexing="ij")
    return np.stack([u, v, np.full_like(u, z)], axis=-1)


def rectangle(w, h, z=0.0):
    v = np.array([[0, 0, z], [w, 0, z], [w, h, z], [0, h, z]], float)
    return v, np.array([[0, 1, 2], [0, 2, 3]])


def uv_sphere(R, m=80, n=160):
    """Triangulated sphere without poles' duplicates, as (vertices, faces)."""
    p = np.linspace(0, np.pi, m + 1)[1:-1]
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    P, T = np.meshgrid(p, t, indexing="ij")
    ring = np.stack([np.sin(P) * np.cos(T), np.sin(P) * np.sin(T), np.cos(P)], -1).reshape(-1, 3)
    v = R * np.concatenate([ring, [[0, 0, 1], [0, 0, -1]]])
    idx = np.arange((m - 1) * n).reshape(m - 1, n)
    a, b = idx[:-1], idx[1:]
    a1, b1 = np.roll(a, -1, axis=1), np.roll(b, -1, axis=1)
    faces = [np.stack([a, b, b1], -1).reshape(-1, 3), np.stack([a, b1, a1], -1).reshape(-1, 3)]
    top, bottom = len(v) - 2, len(v) - 1
    faces.append(np.stack([np.full(n, top), idx[0], np.roll(idx[0], -1)], -1))
    faces.append(np.stack([np.full(n, bottom), np.roll(idx[-1], -1), idx[-1]], -1))
    return v, np.concatenate(faces)


def test_net_triangles():
    f = plane_net(3, 4)
    v, faces = net_triangles(f)
    assert v.shape == (12, 3) and faces.shape == (12, 3)
    assert np.array_equal(v[1 * 4 + 2], f[1, 2])
    # all triangles keep the orientation of the quads (normal +z for this net: e_u × e_v)
    tri = v[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert (normals[:, 2] > 0).all()
    area = 0.5 * np.linalg.norm(normals, axis=1).sum()
    assert area == pytest.approx(1.0)


def test_surface_samples_are_on_the_triangles():
    v, faces = rectangle(2.0, 1.0)
    pts = surface_samples(v, faces, target=50)
    assert np.array_equal(pts[:4], v)
    assert (pts[:, 2] == 0).all()
    assert pts[:, 0].min() >= 0 and pts[:, 0].max() <= 2 and pts[:, 1].max() <= 1
    assert len(pts) > 50
    assert np.array_equal(pts, surface_samples(v, faces, target=50))


def test_offset_plane_both_directions():
    res = hausdorff(plane_net(z=0.1), *rectangle(1.0, 1.0))
    for key in ("net_to_reference_max", "reference_to_net_max", "max", "net_to_reference_mean",
                "reference_to_net_mean", "mean"):
        assert res[key] == pytest.approx(0.1, rel=1e-6), key
    assert res["diagonal"] == pytest.approx(np.sqrt(2))
    assert res["relative"] == pytest.approx(0.1 / np.sqrt(2), rel=1e-6)
    json.dumps(res, allow_nan=False)


def test_asymmetric_coverage_is_seen_from_the_reference():
    # the net covers only half of the reference: net → reference 0, reference → net 1
    res = hausdorff(plane_net(size=(1.0, 1.0)), *rectangle(2.0, 1.0))
    assert res["net_to_reference_max"] <= 1e-6
    assert res["reference_to_net_max"] == pytest.approx(1.0, rel=1e-6)
    assert res["max"] == pytest.approx(1.0, rel=1e-6)
    assert res["relative"] == pytest.approx(1 / np.sqrt(5), rel=1e-6)
    # ... and the other way round
    res = hausdorff(plane_net(size=(2.0, 1.0)), *rectangle(1.0, 1.0))
    assert res["net_to_reference_max"] == pytest.approx(1.0, rel=1e-6)
    assert res["reference_to_net_max"] <= 1e-6


def test_far_surfaces_are_not_cut_off():
    # pymeshlab ignores samples beyond maxdist (default 50 % of the bbox); we must not
    res = hausdorff(plane_net(3, 3, z=25.0), *rectangle(1.0, 1.0))
    assert res["max"] == pytest.approx(25.0, rel=1e-6)
    assert res["n_samples_net"] > 9 and res["n_samples_reference"] > 4


def test_face_interiors_are_sampled():
    # a pyramid of height 0.3 over the unit square against a net of one flat quad: the net's
    # four vertices lie on the reference, only samples inside its faces see the gap; the
    # largest is at the quad's centre, 0.15/√0.34 from the pyramid's faces
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]], float)
    faces = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    res = hausdorff(plane_net(2, 2), v, faces)
    assert res["net_to_reference_max"] == pytest.approx(0.15 / np.sqrt(0.34), rel=1e-5)
    assert res["reference_to_net_max"] == pytest.approx(0.3, rel=1e-6)


def test_sphere_net_against_sphere_mesh_is_close_and_deterministic():
    R = 2.0
    p, t = np.meshgrid(np.linspace(0.3, 2.8, 21), np.linspace(0, 2 * np.pi, 41), indexing="ij")
    f = R * np.stack([np.sin(p) * np.cos(t), np.sin(p) * np.sin(t), np.cos(p)], axis=-1)
    v, faces = uv_sphere(R)
    res = hausdorff(f, v, faces)
    # the net's vertices are on the sphere; its chords sag at most R(1 − cos(Δ/2)) inside
    sag = R * (1 - np.cos(np.hypot(2.5 / 20, 2 * np.pi / 40) / 2))
    assert res["net_to_reference_max"] <= 1.2 * sag
    # the reference around the poles (φ < 0.3, φ > 2.8) is not covered by the net
    assert res["reference_to_net_max"] > 0.4
    assert res == hausdorff(f, v, faces)


def test_bad_reference_is_rejected():
    v, faces = rectangle(1.0, 1.0)
    with pytest.raises(ValueError, match="outside"):
        hausdorff(plane_net(), v, faces + 2)
    with pytest.raises(ValueError, match="triangles"):
        hausdorff(plane_net(), v, np.array([[0, 1, 2, 3]]))
    with pytest.raises(ValueError, match="non-finite"):
        hausdorff(plane_net(), np.full((4, 3), np.nan), faces)


def test_nothing_is_printed_on_stdout():
    code = ("import numpy as np\n"
            "from dgpc_cli.metrics.hausdorff import hausdorff\n"
            "u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), indexing='ij')\n"
            "f = np.stack([u, v, 0 * u + 0.1], -1)\n"
            "r = hausdorff(f, np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]]), [[0, 1, 2]])\n"
            "assert r['max'] > 0\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout == ""
