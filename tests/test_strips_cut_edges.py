"""Cut edges of a shared-outline template (issue "Strips that build the design": one class per
patch, outlines identical to 0.01 mm): strips with their own rulings on two shared outline
curves, bent into space, are cut along the curves sampled at the same points, so their
developed outlines agree to round-off, and every sample lies in the plane of its quad."""

import numpy as np
import pytest

from dgpc_cli.stages.unfold import unfold_strips
from dgpc_cli.strips.congruence import align
from dgpc_cli.strips.cut_edges import (
    SAG_MM,
    curve_samples,
    curve_x,
    edges_between,
    inverse_bilinear,
    template_cut_edges,
)
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.template import bend_template
from dgpc_cli.strips.trim import strip_points

M, S = 9, 4
#: Two outline curves (mm): x = Σ c_k T_k((y − y0) / h), a strip 2 m long and 300 mm wide
#: whose sides bow by about 20 mm.
CURVES = (-1000.0, 1100.0, np.array([[0.0, 0.0, 20.0, 3.0], [300.0, 0.0, -15.0, 2.0]]))


def _developments():
    """S developments ``(S, M, 2, 2)`` with their own rulings on the shared curves, the ends
    shared: the ruling ends at y spaced unevenly, differently for each strip."""
    rng = np.random.default_rng(3)
    base = np.linspace(0.0, -2000.0, M)
    devs = []
    for _ in range(S):
        y = base.copy()
        y[1:-1] += rng.uniform(-60.0, 60.0, (M - 2))
        yb = base.copy()
        yb[1:-1] += rng.uniform(-60.0, 60.0, (M - 2))
        devs.append(np.stack([np.stack([curve_x(CURVES, y, 0), y], -1),
                              np.stack([curve_x(CURVES, yb, 1), yb], -1)], axis=1))
    return np.stack(devs)


def _bent(devs):
    """Exact bendings of the developments into space: each quad turned about its ruling
    towards a cylinder of radius 3 m (:func:`bend_template` onto the lifted strips)."""
    lifted = np.concatenate([devs, np.zeros(devs.shape[:-1] + (1,))], axis=-1)
    y = lifted[..., 1]
    lifted[..., 1] = 3000.0 * np.sin(y / 3000.0)
    lifted[..., 2] = 3000.0 * (1.0 - np.cos(y / 3000.0))
    return bend_template(devs, lifted[:, :, 0], lifted[:, :, 1])


@pytest.fixture(scope="module")
def bent():
    devs = _developments()
    A, B = _bent(devs)
    return devs, A, B, template_cut_edges(devs, CURVES)


def test_the_bending_is_exact_and_really_bent(bent):
    devs, A, B, _ = bent
    for s in range(S):
        d = develop_strip(A[s], B[s])
        assert align(d.A, d.B, devs[s, :, 0], devs[s, :, 1]).error <= 1e-8
    assert np.ptp(A[..., 2]) > 100.0


def test_cut_outlines_are_identical_and_polylines_are_not(bent):
    """The parts cut along the sampled curves agree to round-off; cut along their own ruling
    ends (the polylines A, B) they differ by the curves' sag, more than 0.01 mm."""
    _, A, B, cuts = bent
    devs = [develop_strip(a, b) for a, b in zip(A, B, strict=True)]
    edges = [edges_between(d.A, d.B, cut, 0, M - 1) for d, cut in zip(devs, cuts, strict=True)]
    assert all(len(e[0]) == len(edges[0][0]) for e in edges)
    assert max(align(*e, *edges[0]).error for e in edges) <= 1e-6
    assert max(align(d.A, d.B, devs[0].A, devs[0].B).error for d in devs) > 0.01


def test_samples_lie_on_the_curves_within_the_sag_and_in_their_quads_planes(bent):
    devs, A, B, cuts = bent
    ends = np.stack([devs[0, 0], devs[0, -1]])
    samples = curve_samples(CURVES, ends, M)
    for j in (0, 1):
        mid = 0.5 * (samples[j, 1:] + samples[j, :-1])
        assert np.abs(curve_x(CURVES, mid[:, 1], j) - mid[:, 0]).max() <= SAG_MM
    for s in range(S):
        for j, ts in enumerate(cuts[s]):
            # the development in the curves' frame maps them back onto the samples
            assert np.abs(strip_points(devs[s, :, 0], devs[s, :, 1], ts)
                          - samples[j, 1:-1]).max() <= 1e-8
            # in space: in the plane of the quad floor(t), at the distances from its corners
            # that the development has
            u = np.floor(ts[:, 0]).astype(int)
            p3 = strip_points(A[s], B[s], ts)
            p2 = samples[j, 1:-1]
            for c3, c2 in ((A[s][u], devs[s, u, 0]), (A[s][u + 1], devs[s, u + 1, 0]),
                           (B[s][u], devs[s, u, 1]), (B[s][u + 1], devs[s, u + 1, 1])):
                assert np.abs(np.linalg.norm(p3 - c3, axis=1)
                              - np.linalg.norm(p2 - c2, axis=1)).max() <= 1e-8
            n = np.cross(A[s][u + 1] - A[s][u], B[s][u] - A[s][u])
            n /= np.linalg.norm(n, axis=1)[:, None]
            assert np.abs(np.einsum("kj,kj->k", p3 - A[s][u], n)).max() <= 1e-8


def test_inverse_bilinear_round_trip():
    A = np.array([[0.0, 0.0], [100.0, 5.0], [210.0, 0.0]])
    B = np.array([[10.0, 50.0], [95.0, 60.0], [200.0, 48.0]])
    ts = np.array([[0.3, -0.01], [0.8, 1.02], [1.5, 0.5], [1.99, 0.0]])
    u = np.floor(ts[:, 0]).astype(int)
    p = strip_points(A, B, ts)
    back = inverse_bilinear(A, B, u, p, np.stack([np.full(4, 0.5), np.full(4, 0.5)], -1))
    assert back == pytest.approx(ts, abs=1e-12)


def test_unfold_cuts_along_the_edges_whole_and_in_boards(bent):
    """unfold: one class within 1e-6 mm with the cut edges (several without); boards cut at
    rulings keep the curved edges, their outlines starting and ending on the ruling ends."""
    _, A, B, cuts = bent
    geometry = list(zip(A, B, strict=True))
    ids = [f"S-v{v:02d}" for v in range(S)]
    records = [{"A": a, "B": b} for a, b in cuts]
    parts, classes, _ = unfold_strips(geometry, ids, list(range(S)), congruence_tol=0.01,
                                      cut_edges=records)
    assert len(classes) == 1 and classes[0]["max_deviation_mm"] <= 1e-6
    assert all("edges" in p and len(p["outline"]) > 2 * M for p in parts)
    _, plain, _ = unfold_strips(geometry, ids, list(range(S)), congruence_tol=0.01)
    assert len(plain) > 1
    parts, _, _ = unfold_strips(geometry, ids, list(range(S)), congruence_tol=0.01,
                                cut_edges=records, stock_length=900.0, stagger=0.0)
    assert all(len(p["edges"][0]) > p["rows"][1] - p["rows"][0] + 1 for p in parts)
    for p in parts:
        for g, e in zip(p["geodesics"], p["edges"], strict=True):
            assert np.asarray(e)[[0, -1]] == pytest.approx(np.asarray(g)[[0, -1]], abs=1e-12)


def _artifact(A, B, cuts):
    from dgpc_cli.io.strips import StripsArtifact

    records = [{"id": f"S-v{v:02d}", "v": v, "rows": M, "planarity": 0.0, "deviation": 0.0,
                "width": 300.0, "ruling_directions": np.tile([0.0, 0.0, 1.0], (M, 1)),
                "flat_rows": [False] * M, "params": np.zeros((M, 2)),
                "polish": {"applied": False}, "cut_edges": {"A": a, "B": b}}
               for v, (a, b) in enumerate(cuts)]
    return StripsArtifact(geometry=list(zip(A, B, strict=True)), records=records,
                          source_shape=(M, S + 1), units="mm")


def test_strips_artifact_keeps_the_cut_edges_and_rejects_them_beyond_the_ends(bent, tmp_path):
    from dgpc_cli.errors import DgpcError
    from dgpc_cli.io.atomic import write_files
    from dgpc_cli.io.strips import read_strips, strips_files

    _, A, B, cuts = bent
    write_files(strips_files(tmp_path / "s", _artifact(A, B, cuts)))
    back = read_strips(tmp_path / "s")
    for r, (a, b) in zip(back.records, cuts, strict=True):
        assert np.asarray(r["cut_edges"]["A"]) == pytest.approx(a, abs=0)
        assert np.asarray(r["cut_edges"]["B"]) == pytest.approx(b, abs=0)
    bad = [(a, b.copy()) for a, b in cuts]
    bad[1][1][0, 0] = M - 1.0
    write_files(strips_files(tmp_path / "bad", _artifact(A, B, bad)))
    with pytest.raises(DgpcError, match=r"strips\[1\]\.cut_edges\.B\[0\].*strictly between"):
        read_strips(tmp_path / "bad")


def test_no_cut_edges_when_a_boundary_turns_back(bent):
    """A development whose ruling ends do not run along the curves in order has no quad for
    its samples: no cut edges (the parts are cut along their polylines)."""
    devs = _developments()
    devs[2, [3, 4]] = devs[2, [4, 3]]
    assert template_cut_edges(devs, CURVES) is None
    assert template_cut_edges(_developments(), CURVES) is not None


def test_report_overlays_the_cut_outlines(bent):
    """The template figure's data (paper Fig. 18 bottom-right) measures and draws the outlines
    the parts are cut along: equal to round-off with cut edges, the curves' sag without."""
    from dgpc_cli.stages.strip_fabrication import figure_data

    _, A, B, cuts = bent
    f = np.concatenate([np.moveaxis(A, 0, 1), B[-1:].swapaxes(0, 1)], axis=1)   # (M, S+1, 3)
    art = _artifact(A, B, cuts)
    data = figure_data(art, f)
    assert data.template_error <= 1e-6
    assert all(len(a) == len(data.outlines[0][0]) > M for a, _ in data.outlines)
    for r in art.records:
        del r["cut_edges"]
    assert figure_data(art, f).template_error > 0.01
