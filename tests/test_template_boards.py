"""Boards of a template (issue "Strips that build the design", item 4): with `--stock-length`
the strips of one template are cut at the same lines of the template, in at most two joint
patterns alternating strip by strip, staggered along the shared geodesics, so their boards are
copies (within 0.01 mm) of the boards of the two patterns. Built on a shared-outline template
whose strips each have their own rulings (the joints then need not lie on rulings)."""

from collections import defaultdict

import numpy as np
import pytest
from cli_helpers import dgpc
from test_strips_cut_edges import CURVES, M, S, _bent, _developments

from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.stages.unfold import unfold_strips
from dgpc_cli.strips.cut_edges import template_cut_edges
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.trim import strip_points

STOCK, STAGGER = 900.0, 200.0            # mm: strips of 2 m, three boards each
COLUMNS = list(range(2 * S))             # eight strips: four of each pattern


@pytest.fixture(scope="module")
def net():
    """Eight strips of one shared-outline template (two sets of the built four, each strip its
    own rulings), bent into space, their cut-edge records."""
    devs = np.concatenate([_developments(), _developments()[::-1]])
    A, B = _bent(devs)
    cuts = template_cut_edges(devs, CURVES)
    return list(zip(A, B, strict=True)), [{"A": a, "B": b} for a, b in cuts]


def _unfold(net, template=True, stagger=STAGGER):
    geometry, cuts = net
    return unfold_strips(geometry, [f"S-v{v:02d}" for v in COLUMNS], COLUMNS,
                         congruence_tol=0.01, stock_length=STOCK, stagger=stagger,
                         cut_edges=cuts, template=template)


def _patterns(joints):
    out = defaultdict(list)
    for j in joints:
        out[int(j["strip"][3:])].append(j["cut"]["along"])
    return [np.asarray(out[v]) for v in COLUMNS]


def test_boards_of_a_template_are_two_alternating_patterns_of_copies(net):
    parts, classes, joints = _unfold(net)
    patterns = _patterns(joints)
    assert all(len(p) >= 2 for p in patterns)                     # three boards or more
    for v in range(2, len(COLUMNS)):
        assert patterns[v] == pytest.approx(patterns[v - 2], abs=0)
    assert patterns[0].shape != patterns[1].shape or not np.allclose(patterns[0], patterns[1])
    # staggered on every shared geodesic: strip v's side B against strip v+1's side A
    for v in range(len(COLUMNS) - 1):
        gap = np.abs(patterns[v][:, 1, None] - patterns[v + 1][None, :, 0]).min()
        assert gap >= STAGGER - 1e-9
    # the boards are the boards of the two patterns: one class per board position, copies
    # within 0.01 mm, each class the same board of the strips of one pattern
    assert len(classes) == len(patterns[0]) + len(patterns[1]) + 2
    by_id = {p["id"]: p for p in parts}
    for c in classes:
        assert c["max_deviation_mm"] <= 0.01
        members = [by_id[i] for i in c["members"]]
        assert len({(p["board"], p["strip"] % 2) for p in members}) == 1
        assert c["quantity"] == len(COLUMNS) // 2
    # each board within the stock (laid along its chord), the boards make up the strip
    for p in parts:
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9
    whole, _, _ = unfold_strips(net[0], [f"S-v{v:02d}" for v in COLUMNS], COLUMNS,
                                congruence_tol=0.01, cut_edges=net[1])
    for w in whole:
        area = sum(p["area"] for p in parts if p["strip"] == w["strip"])
        assert area == pytest.approx(w["area"], rel=1e-9)


def test_a_cut_is_the_same_template_line_on_every_strip_not_a_ruling(net):
    """The cut's ends, recorded in each strip's (t, s), lie at the same places of the developed
    template (their distances from the first ruling's ends agree to 1e-6 mm), most not on a
    ruling; the score lines are the strip's own rulings clipped to the board."""
    geometry, _ = net
    parts, _, joints = _unfold(net)
    devs = [develop_strip(A, B) for A, B in geometry]
    seen = defaultdict(list)
    for j in joints:
        v = int(j["strip"][3:])
        d = devs[v]
        ends = strip_points(d.A, d.B, np.array([j["cut"]["A"], j["cut"]["B"]]))
        key = (v % 2, tuple(np.round(j["cut"]["along"], 6)))
        seen[key].append(np.linalg.norm(ends[:, None] - np.stack([d.A[0], d.B[0]])[None],
                                        axis=-1).ravel())
        assert j["row"] == pytest.approx(np.mean([j["cut"]["A"][0], j["cut"]["B"][0]]), abs=0.5)
    assert all(len(v) == S for v in seen.values())
    for dist in seen.values():
        assert np.ptp(np.asarray(dist), axis=0).max() <= 1e-6
    t = np.array([[j["cut"]["A"][0], j["cut"]["B"][0]] for j in joints])
    assert np.mean(np.abs(t - np.round(t)) > 1e-3) > 0.5
    for p in parts:
        for line in p["score"]:
            assert len(line) == 2


def test_strips_cut_one_by_one_give_many_classes(net):
    """Without the template (strips planarized one by one) every strip is cut at its own
    rulings: its boards are not copies, nor are its joints those of the other strips."""
    parts, classes, joints = _unfold(net, template=False)
    assert len(classes) > len(COLUMNS)
    assert all("cut" not in j for j in joints)
    assert all(j["row"] == int(j["row"]) for j in joints)


def test_unfold_records_the_template_cuts(net, tmp_path):
    """`dgpc unfold --stock-length` on a strips artifact of one template: the flat artifact
    (checked against its schema when read) records each board's two end cuts and each joint's
    cut, in the artifact's unit."""
    geometry, cuts = net
    m = geometry[0][0].shape[0]
    assert m == M
    records = [{"id": f"S-v{v:02d}", "v": v, "rows": m, "planarity": 0.0, "deviation": 0.0,
                "width": 300.0, "ruling_directions": np.tile([0.0, 0.0, 1.0], (m, 1)),
                "flat_rows": [False] * m, "params": np.zeros((m, 2)),
                "polish": {"applied": False}, "cut_edges": c} for v, c in zip(COLUMNS, cuts,
                                                                            strict=True)]
    art = StripsArtifact(geometry=geometry, records=records, source_shape=(m, len(COLUMNS) + 1),
                         units="mm", template={"variant": "shared-outline", "start": "per-strip",
                                                   "status": "converged", "iterations": 1,
                                                   "A": _developments()[0, :, 0],
                                                   "B": _developments()[0, :, 1]})
    write_files(strips_files(tmp_path / "s", art))
    dgpc("unfold", tmp_path / "s", "--stock-length", "0.9m", "--stagger", "200mm",
         "-o", tmp_path / "f")
    flat = read_flat(tmp_path / "f")
    assert len(flat.classes) <= 8
    assert all(len(p["cuts"]) == 2 for p in flat.parts)
    assert all("cut" in j for j in flat.joints)
    first = {p["strip"]: p["cuts"][0]["along"] for p in flat.parts if p["board"] == 2}
    assert first[0] != first[1] and first[0] == first[2]


def test_strips_sharing_the_template_vertices_are_cut_at_its_rulings():
    """Shared vertices (no cut edges): the template's cuts are its rulings, so every joint lies
    on a score line, and the boards are still copies of the two patterns' boards."""
    devs = np.repeat(_developments()[:1], 6, axis=0)
    A, B = _bent(devs)
    columns = list(range(6))
    parts, classes, joints = unfold_strips(list(zip(A, B, strict=True)),
                                           [f"S-v{v:02d}" for v in columns], columns,
                                           congruence_tol=0.01, stock_length=STOCK,
                                           stagger=STAGGER, template=True)
    ends = np.array([[j["cut"]["A"], j["cut"]["B"]] for j in joints])       # (k, 2, 2)
    assert ends[..., 0] == pytest.approx(np.round(ends[..., 0]), abs=1e-9)
    assert ends[:, :, 1] == pytest.approx(np.tile([0.0, 1.0], (len(joints), 1)), abs=1e-9)
    assert [j["row"] for j in joints] == [int(round(t)) for t in ends[:, 0, 0]]
    per_strip = defaultdict(int)
    for p in parts:
        per_strip[p["strip"]] += 1
    assert len(classes) == per_strip[0] + per_strip[1]
    assert max(c["max_deviation_mm"] for c in classes) <= 0.01


def test_a_cut_in_space_is_the_template_line_bent_at_the_rulings(net):
    """The cut's path (its ends and ruling crossings in the strip's (t, s)) on the 3-D strip is
    as long as the straight cut of the template, and it really bends (the strip is curved)."""
    geometry, _ = net
    _, _, joints = _unfold(net)
    bent = 0.0
    for j in joints:
        A, B = geometry[int(j["strip"][3:])]
        d = develop_strip(A, B)
        path = np.asarray(j["cut"]["path"])
        assert path[[0, -1]] == pytest.approx(np.array([j["cut"]["A"], j["cut"]["B"]]), abs=0)
        assert path[1:-1, 0] == pytest.approx(np.round(path[1:-1, 0]), abs=0)
        p2, p3 = strip_points(d.A, d.B, path), strip_points(A, B, path)
        straight = np.linalg.norm(p2[-1] - p2[0])
        assert np.linalg.norm(np.diff(p3, axis=0), axis=1).sum() == pytest.approx(straight,
                                                                                    abs=1e-6)
        # in the development the path is the straight line
        e, w = (p2[-1] - p2[0]) / straight, p2[1:-1] - p2[0]
        off = w[:, 0] * e[1] - w[:, 1] * e[0]
        assert np.abs(off).max(initial=0.0) <= 1e-6
        bent = max(bent, straight - np.linalg.norm(p3[-1] - p3[0]))
    assert bent > 1e-3
