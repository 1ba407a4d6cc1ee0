"""net_metrics: every SPEC §7 metric of a net as plain JSON."""

import json

import numpy as np
import pytest

from dgpc_cli.metrics import net_metrics
from dgpc_cli.metrics.hausdorff import net_triangles
from dgpc_cli.metrics.summary import jsonable


def sphere_net(R=2.0, m=21, n=15):
    p, t = np.meshgrid(np.linspace(0.3, 2.8, m), np.linspace(0, 2, n), indexing="ij")
    return R * np.stack([np.sin(p) * np.cos(t), np.sin(p) * np.sin(t), np.cos(p)], axis=-1)


BASE_KEYS = {"shape", "gpc_angle_defect_max", "orthogonality_max", "arclength_spread_max",
             "strip_width_spread_max", "ratio_spread_max", "jacobi_residual_max", "edges",
             "gaussian_curvature", "u_spread_max", "pleat_max", "crease_max", "parallel_departure"}


def test_plain_metrics_of_a_meridian_net():
    f = sphere_net()
    res = net_metrics(f)
    assert set(res) == BASE_KEYS
    json.dumps(res, allow_nan=False)
    assert res["shape"] == [21, 15]
    assert res["gpc_angle_defect_max"] <= 1e-12
    assert res["orthogonality_max"] <= 1e-12
    assert res["arclength_spread_max"] <= 1e-12
    assert res["strip_width_spread_max"] <= 1e-12
    assert res["ratio_spread_max"] <= 1e-12
    assert res["jacobi_residual_max"] > 1e-3          # a sphere is not developable
    assert res["u_spread_max"] <= 1e-12               # congruent meridian strips
    assert res["pleat_max"] <= 1e-3                   # smooth: a fourth difference
    assert res["parallel_departure"]["relative"] <= 1e-12    # parallels are circles
    assert set(res["edges"]) == {"min", "mean", "max", "min_ratio", "folded"}
    assert res["edges"]["folded"] is False
    K = res["gaussian_curvature"]
    assert K["min"] == pytest.approx(0.25, rel=1e-9) and K["max"] == pytest.approx(0.25, rel=1e-9)


def test_optional_metrics():
    f = sphere_net()
    rng = np.random.default_rng(5)
    noisy = f + 1e-3 * rng.standard_normal(f.shape)
    v, faces = net_triangles(f)          # the noise-free net as the reference mesh
    n = f.shape[1]
    res = net_metrics(noisy, axis="0,0,0,0,0,1", against=f, reference=(v, faces))
    json.dumps(res, allow_nan=False)
    assert set(res) == BASE_KEYS | {"clairaut", "strain", "hausdorff", "coverage"}
    assert res["gpc_angle_defect_max"] > 1e-4
    assert set(res["strain"]) == {"max", "mean"} and res["strain"]["max"] > 1e-4
    assert len(res["clairaut"]["per_geodesic"]["mean"]) == n - 2
    assert 1e-4 < res["hausdorff"]["max"] < 1e-2
    assert res["hausdorff"]["relative"] == pytest.approx(
        res["hausdorff"]["max"] / res["hausdorff"]["diagonal"])
    # scaling against the original: strain 2s everywhere
    res = net_metrics(1.01 * f, against=f, axis=(np.zeros(3), [0, 0, 1]))
    assert res["strain"]["max"] == pytest.approx(0.02, rel=1e-9)
    assert res["clairaut"]["max_mad_over_radius"] <= 1e-12


def test_small_net_gives_none_not_nan():
    f = np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0.5]]], float)
    res = net_metrics(f, axis="0,0,0,0,0,1")
    text = json.dumps(res, allow_nan=False)
    assert "NaN" not in text
    assert res["gpc_angle_defect_max"] is None and res["orthogonality_max"] is None
    assert res["jacobi_residual_max"] is None
    assert res["gaussian_curvature"] == {"min": None, "max": None, "mean": None}


def test_bad_inputs():
    with pytest.raises(ValueError, match="6 comma-separated"):
        net_metrics(sphere_net(), axis="0,0,1")
    with pytest.raises(ValueError, match="vertices, faces"):
        net_metrics(sphere_net(), reference=np.zeros((3, 3)))


def test_jsonable():
    out = jsonable({"a": np.float32(1.5), "b": (np.int64(2), np.nan), 3: np.array([1.0, np.inf]),
                    "c": np.bool_(True)})
    assert out == {"a": 1.5, "b": [2, None], "3": [1.0, None], "c": True}
    assert type(out["b"][0]) is int and type(out["c"]) is bool


def test_straight_rows_depart_by_their_distance_from_a_line():
    """A flat grid (every row a straight line: a circle of infinite radius) and one row bent
    off its line by 0.3 out of the plane."""
    from dgpc_cli.metrics.freeform import circle_departure, parallel_departure

    u, v = np.meshgrid(np.arange(4.0), np.arange(5.0), indexing="ij")
    f = np.stack([u, v, np.zeros_like(u)], axis=-1)
    assert np.allclose(circle_departure(f), 0.0, atol=1e-12)
    assert parallel_departure(f)["max"] <= 1e-12
    f[2, 2, 2] = 0.3                        # row 2 is no longer straight: a circle fits it
    d = circle_departure(f)
    assert np.allclose(d[[0, 1, 3]], 0.0, atol=1e-12) and 0 < d[2] < 0.3


def test_coverage_with_the_reference_tree_lent():
    """A ReferenceSurface already built answers coverage's vertex distances: the same figures
    as a tree of its own."""
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.metrics.coverage import coverage

    f = sphere_net()
    v, faces = net_triangles(f[1:-1])                        # a reference smaller than the net
    noisy = f + 1e-3 * np.random.default_rng(2).standard_normal(f.shape)
    own = coverage(noisy, v, faces)
    lent = coverage(noisy, v, faces, surface=ReferenceSurface(v, faces))
    assert own["vertex_distance_max"] > 1e-3
    assert lent == pytest.approx(own, rel=1e-12)
