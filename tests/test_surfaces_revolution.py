"""Nets and reference meshes of surfaces of revolution (SPEC §5, paper Fig. 11)."""

import json

import numpy as np
import pytest

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.errors import DgpcError
from dgpc_cli.surfaces.profiles import BUILTIN_PROFILES, Profile, builtin_profile, resample
from dgpc_cli.surfaces.revolution import (
    AXIS,
    MIN_ALONG,
    default_along,
    revolution_mesh,
    revolution_net,
    surface_record,
)

# Largest distance of a chord of the dense sphere polyline from the sphere:
# 5·(1 − cos(Δφ/2)), Δφ = 82°/2000.
SPHERE_SAG = 5.0 * (1.0 - np.cos(np.radians(82.0 / 2000) / 2))


def _theta(f):
    return np.arctan2(f[..., 1], f[..., 0])


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


# nets --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("m, n", [(2, 2), (3, 5), (21, 21), (40, 7)])
def test_net_shape_and_rows_on_the_profile(m, n):
    p = builtin_profile("bowling-pin")
    f = revolution_net(p, m, n, span_deg=120.0, twist=0.7)
    assert f.shape == (m, n, 3)
    assert np.all(np.isfinite(f))
    r, h, _ = resample(p, m)
    np.testing.assert_allclose(np.hypot(f[..., 0], f[..., 1]), np.repeat(r[:, None], n, 1),
                               rtol=1e-14)
    np.testing.assert_array_equal(f[..., 2], np.repeat(h[:, None], n, 1))


def test_sphere_net_lies_on_the_sphere():
    f = revolution_net(builtin_profile("sphere"), 21, 21, span_deg=90.0, twist=0.4)
    dist = np.linalg.norm(f, axis=-1)
    assert SPHERE_SAG < 4e-7
    np.testing.assert_allclose(dist, 5.0, rtol=0, atol=SPHERE_SAG + 1e-13)
    # first row on the equator, last row 8° from the pole
    np.testing.assert_array_equal(f[0, :, 2], 0.0)
    polar = np.degrees(np.arccos(f[-1, :, 2] / dist[-1]))
    np.testing.assert_allclose(polar, 8.0, atol=1e-10)


def test_untwisted_net_has_meridians_as_u_lines():
    f = revolution_net(builtin_profile("catenoid"), 15, 9, span_deg=90.0)
    theta = _theta(f)
    # every u-line lies in one plane through the z axis ...
    np.testing.assert_allclose(theta - theta[:1], 0.0, atol=1e-14)
    normal = np.stack([-np.sin(theta[0]), np.cos(theta[0]), np.zeros(9)], axis=-1)  # (n, 3)
    np.testing.assert_allclose(np.einsum("uvk,vk->uv", f, normal), 0.0, atol=1e-14)
    # ... at equally spaced angles, centred on the x axis, spanning 90°
    np.testing.assert_allclose(theta[0], np.radians(np.linspace(-45.0, 45.0, 9)), atol=1e-14)


def test_twisted_net_rotates_the_last_row_by_the_twist():
    p = builtin_profile("bowling-pin")
    twist = 1.1
    f0 = revolution_net(p, 25, 11, span_deg=60.0)
    f = revolution_net(p, 25, 11, span_deg=60.0, twist=twist)
    theta = _theta(f)
    np.testing.assert_allclose(_wrap(theta[-1] - theta[0]), twist, atol=1e-13)
    np.testing.assert_allclose(f[0], f0[0], atol=1e-14)  # the first row does not move
    # the shear is linear in arc length: row u turns by twist·s_u/s_total
    _, _, s = resample(p, 25)
    np.testing.assert_allclose(_wrap(theta - _theta(f0)), np.repeat((twist * s / s[-1])[:, None],
                               11, 1), atol=1e-13)
    # so the u-lines are not meridians any more
    assert np.ptp(theta[:, 5]) == pytest.approx(twist, abs=1e-13)


def test_full_span_closes_the_ring():
    f = revolution_net(builtin_profile("cylinder"), 4, 13, span_deg=360.0)
    np.testing.assert_allclose(f[:, 0], f[:, -1], atol=1e-14)
    np.testing.assert_allclose(np.diff(_theta(f[:, :-1]), axis=1) % (2 * np.pi),
                               np.pi / 6, atol=1e-13)


@pytest.mark.parametrize("span", [0.0, -10.0, 360.5, np.nan])
def test_net_rejects_bad_span(span):
    with pytest.raises(DgpcError, match="span"):
        revolution_net(builtin_profile("cone"), 5, 5, span_deg=span)


def test_net_rejects_bad_sizes_and_twist():
    with pytest.raises(ValueError):
        revolution_net(builtin_profile("cone"), 1, 5)
    with pytest.raises(DgpcError, match="twist"):
        revolution_net(builtin_profile("cone"), 5, 5, twist=np.inf)


# meshes ------------------------------------------------------------------------------------------


def _edge_use(faces):
    """Directed edges of all triangles, shape (3t, 2)."""
    return np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])


@pytest.mark.parametrize("around, along", [(3, 2), (8, 5), (36, 50)])
def test_mesh_counts_and_closed_seam(around, along):
    v, faces = revolution_mesh(builtin_profile("catenoid"), around=around, along=along)
    assert v.shape == (along * around, 3) and v.dtype == np.float64
    assert faces.shape == (2 * (along - 1) * around, 3) and faces.dtype == np.int64
    assert faces.min() == 0 and faces.max() == along * around - 1
    # every vertex is used, no two coincide (the seam is welded)
    assert np.unique(faces).size == len(v)
    assert np.unique(np.round(v, 9), axis=0).shape[0] == len(v)
    # no degenerate triangles
    assert np.all((faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2])
                  & (faces[:, 2] != faces[:, 0]))


def test_mesh_boundary_is_the_two_end_circles_and_winding_is_consistent():
    p = builtin_profile("bowling-pin")
    around, along = 48, 30
    v, faces = revolution_mesh(p, around=around, along=along)
    directed = _edge_use(faces)
    # consistent orientation: no directed edge is used twice
    assert np.unique(directed, axis=0).shape[0] == len(directed)
    undirected, count = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    assert set(count) == {1, 2}
    boundary = undirected[count == 1]
    assert len(boundary) == 2 * around
    rows = boundary // around
    assert np.all(rows[:, 0] == rows[:, 1])
    assert sorted(set(rows[:, 0])) == [0, along - 1]
    # Euler characteristic of an annulus
    n_edges = len(undirected)
    assert len(v) - n_edges + len(faces) == 0


def test_mesh_vertices_lie_on_the_surface():
    for name in ("bowling-pin", "catenoid", "cone"):
        p = builtin_profile(name)  # h increases along these profiles: r(h) is a function
        v, _ = revolution_mesh(p, around=64)
        r = np.hypot(v[:, 0], v[:, 1])
        np.testing.assert_allclose(r, np.interp(v[:, 2], p.h, p.r), rtol=1e-12)
    v, _ = revolution_mesh(builtin_profile("sphere-zone"), around=64)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 5.0, atol=1e-6)
    v, _ = revolution_mesh(builtin_profile("cylinder"), around=64)
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 1]), 2.0, rtol=1e-14)


def test_mesh_is_the_full_ring_net_without_its_seam_column():
    p = builtin_profile("sphere")
    v, _ = revolution_mesh(p, around=40, along=25)
    f = revolution_net(p, 25, 41, span_deg=360.0)
    np.testing.assert_array_equal(v, f[:, :-1].reshape(-1, 3))


def test_mesh_orientation_matches_the_net_quads():
    p = builtin_profile("bowling-pin")
    around, along = 60, 80
    v, faces = revolution_mesh(p, around=around, along=along)
    tri = v[faces]
    n_mesh = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    # net quad (u,v),(u+1,v),(u+1,v+1),(u,v+1): normal from its diagonals, one per quad
    f = revolution_net(p, along, around + 1, span_deg=360.0)
    n_quad = np.cross(f[1:, 1:] - f[:-1, :-1], f[:-1, 1:] - f[1:, :-1])    # (along-1, around, 3)
    n_quad = np.repeat(n_quad.reshape(-1, 1, 3), 2, axis=1).reshape(-1, 3)
    assert np.all(np.einsum("ij,ij->i", n_mesh, n_quad) > 0)
    # normals are (−h', r') in the (r, h) plane: toward the axis for this upward profile
    centroid = tri.mean(axis=1)
    radial = centroid * [1.0, 1.0, 0.0]
    assert np.all(np.einsum("ij,ij->i", n_mesh, radial) < 0)
    # reversing the profile reverses the normals: outward
    down = Profile("down", p.r[::-1], p.h[::-1])
    v2, faces2 = revolution_mesh(down, around=around, along=along)
    tri2 = v2[faces2]
    n2 = np.cross(tri2[:, 1] - tri2[:, 0], tri2[:, 2] - tri2[:, 0])
    assert np.all(np.einsum("ij,ij->i", n2, tri2.mean(axis=1) * [1.0, 1.0, 0.0]) > 0)


def test_default_along_is_fine():
    for name in BUILTIN_PROFILES:
        p = builtin_profile(name)
        along = default_along(p)
        assert along >= MIN_ALONG
        v, faces = revolution_mesh(p)
        assert len(v) == 360 * along
        assert len(faces) == 2 * (along - 1) * 360
    # the bowling pin's meridian spacing is about its widest parallel's spacing
    pin = builtin_profile("bowling-pin")
    step = pin.length / (default_along(pin) - 1)
    assert step <= 2 * np.pi * 6.05 / 360


def test_mesh_rejects_bad_sizes():
    with pytest.raises(ValueError):
        revolution_mesh(builtin_profile("cone"), around=2)
    with pytest.raises(ValueError):
        revolution_mesh(builtin_profile("cone"), along=1)


# record ------------------------------------------------------------------------------------------


def test_surface_record_is_json():
    p = builtin_profile("bowling-pin")
    record = surface_record(p, 90, 0.5)
    assert json.loads(json.dumps(record)) == record
    assert record["type"] == "revolution"
    assert record["profile"] == "bowling-pin"
    assert record["builtin"] is True
    assert record["span_deg"] == 90.0 and record["twist"] == 0.5
    assert record["axis"] == {"point": [0.0, 0.0, 0.0], "direction": [0.0, 0.0, 1.0]}
    assert tuple(record["axis"]["point"] + record["axis"]["direction"]) == AXIS
    assert "r" not in record and "h" not in record


def test_surface_record_of_a_csv_profile():
    record = surface_record(Profile("shapes/vase.csv", [1.0, 2.0], [0.0, 1.0]), 360.0, 0.0)
    assert record["profile"] == "shapes/vase.csv" and record["builtin"] is False
    assert record["profile_length"] == pytest.approx(np.sqrt(2.0))


def test_net_grid_matches_the_layout_conventions():
    # u-edges follow the meridians: for a cylinder they are vertical, v-edges horizontal
    layout = NetLayout(7, 5)
    f = revolution_net(builtin_profile("cylinder"), layout.m, layout.n, span_deg=80.0)
    d = layout.edge_vectors(f)
    n_eu = (layout.m - 1) * layout.n
    np.testing.assert_allclose(d[:n_eu, :2], 0.0, atol=1e-15)
    np.testing.assert_allclose(d[:n_eu, 2], 1.0, rtol=1e-14)
    np.testing.assert_allclose(d[n_eu:, 2], 0.0, atol=1e-15)
