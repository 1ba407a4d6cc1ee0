"""Joints inside a planar quad (issue "A real roof clad by the default command", item 5): where
no ruling of a strip lies within the stock length, `unfold --stock-length` cuts the board
straight across the quad, from the point at a fraction f of its side A to the point at the
same fraction of its side B. The quad being planar, both pieces stay planar and their flat
boards are exact developments of them.

Built on strips of a cone (every quad planar: its four corners lie in a plane through the
apex), rows spaced unevenly so that one quad is longer than the stock."""

import csv
import json

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.stages.unfold import unfold_strips
from dgpc_cli.strips.boards import knots, split_run, strip_between
from dgpc_cli.strips.develop import develop_strip, signed_area

STOCK = 6000.0                                          # mm
THETA = np.array([0.0, 0.1, 0.2, 0.3, 1.4, 1.5, 1.6, 1.7, 1.9, 2.0])
LONG = 3                                                # the quad from row 3 to row 4
IDS = [f"S-v{v:02d}" for v in range(3)]


def cone(k: int, turn: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Strip k of the cone: its rows on the generators at the angles THETA (+ ``turn``), side
    A at 8 m + 0.6 k from the apex, side B 0.6 m farther (mm)."""
    tilt = 0.6
    th = THETA + turn
    d = np.stack([np.cos(th) * np.cos(tilt), np.sin(th) * np.cos(tilt),
                  np.full_like(th, np.sin(tilt))], axis=-1)
    apex = np.array([0.0, 0.0, 5000.0])
    return apex + (8000.0 + 600.0 * k) * d, apex + (8600.0 + 600.0 * k) * d


def _lengths(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The edge lengths of a quad strip: rulings, both sides, both diagonals of every quad."""
    return np.concatenate([np.linalg.norm(B - A, axis=-1),
                           np.linalg.norm(np.diff(A, axis=0), axis=-1),
                           np.linalg.norm(np.diff(B, axis=0), axis=-1),
                           np.linalg.norm(A[1:] - B[:-1], axis=-1),
                           np.linalg.norm(B[1:] - A[:-1], axis=-1)])


def _planarity(A: np.ndarray, B: np.ndarray) -> float:
    """The largest distance of a quad's fourth corner from the plane of the other three, over
    the quad's size."""
    n = np.cross(B[:-1] - A[:-1], A[1:] - A[:-1])
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    off = np.abs(np.einsum("ui,ui->u", B[1:] - A[:-1], n))
    return float((off / np.linalg.norm(A[1:] - B[:-1], axis=-1)).max())


def _span(part: dict) -> tuple[float, float]:
    return tuple(part.get("row_span", part["rows"]))


@pytest.fixture(scope="module")
def geometry():
    return [cone(k) for k in range(3)]


def test_the_long_quad_is_longer_than_the_stock(geometry):
    A, B = geometry[0]
    assert np.linalg.norm(A[LONG + 1] - A[LONG]) > STOCK
    assert _planarity(A, B) < 1e-12


def test_boards_are_cut_inside_the_long_quad_and_are_exact_developments(geometry):
    parts, _, joints = unfold_strips(geometry, IDS, [0, 1, 2], stock_length=STOCK)
    whole, _, _ = unfold_strips(geometry, IDS, [0, 1, 2])
    for v, (A, B) in enumerate(geometry):
        boards = sorted((p for p in parts if p["strip"] == v), key=lambda p: p["board"])
        spans = [_span(p) for p in boards]
        assert spans[0][0] == 0 and spans[-1][1] == len(A) - 1
        assert all(s[1] == n[0] for s, n in zip(spans[:-1], spans[1:], strict=True))
        inside = [s[1] for s in spans[:-1] if s[1] != round(s[1])]
        assert inside and all(LONG < t < LONG + 1 for t in inside)      # in the long quad
        for p, (a, b) in zip(boards, spans, strict=True):
            outline = np.asarray(p["outline"])
            assert np.ptp(outline[:, 0]) <= STOCK + 1e-9                 # laid along its chord
            A3, B3 = strip_between(A, B, a, b)                           # the 3-D piece
            assert _planarity(A3, B3) < 1e-9
            ga, gb = (np.asarray(g) for g in p["geodesics"])
            assert _lengths(ga, gb) == pytest.approx(_lengths(A3, B3), rel=1e-9, abs=1e-9)
            assert [r for r in range(len(A)) if a < r < b] == [int(r) for r in knots(a, b)[1:-1]]
            assert len(p["score"]) == len(knots(a, b)) - 2               # rulings inside only
        # the joint's ends lie on the quad's sides, at the same fraction of both
        for t in inside:
            f = t - LONG
            for X in (A, B):
                p = strip_between(A, B, t, len(A) - 1)[0 if X is A else 1][0]
                assert p == pytest.approx(X[LONG] + f * (X[LONG + 1] - X[LONG]), abs=1e-9)
        area = sum(p["area"] for p in boards)
        assert area == pytest.approx(whole[v]["area"], rel=1e-9)
    rows = {(j["strip"], j["row"]) for j in joints}
    assert any(isinstance(r, float) and LONG < r < LONG + 1 for _, r in rows)


def test_joints_of_neighbours_keep_the_stagger_on_the_shared_geodesic(geometry, caplog):
    """Strip v's side B is strip v+1's side A: their joints there at least the stagger apart
    (a joint inside a quad where no ruling within the stock keeps it)."""
    stagger = 1500.0
    parts, _, joints = unfold_strips(geometry, IDS, [0, 1, 2], stock_length=STOCK,
                                     stagger=stagger)
    for v in range(2):
        A, B = geometry[v]
        sb = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(B, axis=0), axis=1))])
        mine = [np.interp(j["row"], np.arange(len(B)), sb) for j in joints
                if j["strip"] == IDS[v]]
        theirs = [np.interp(j["row"], np.arange(len(B)), sb) for j in joints
                  if j["strip"] == IDS[v + 1]]
        assert np.abs(np.subtract.outer(mine, theirs)).min() >= stagger - 1e-6
    assert "nearer than the stagger" not in caplog.text


def test_a_trimmed_part_is_cut_inside_the_long_quad(geometry):
    """A strip trimmed to an outline (its ends slanted): boards within the stock, a joint in
    the long quad, the boards' areas adding up to the part's."""
    ring = np.array([[0.3, 0.0], [8.6, 0.0], [8.2, 1.0], [0.1, 1.0]])
    trims = [{"parts": [{"id": IDS[k], "rows": [0, 9], "outline": ring.tolist()}]}
             for k in range(3)]
    parts, _, joints = unfold_strips(geometry, IDS, [0, 1, 2], stock_length=STOCK, trims=trims,
                                     source="test")
    whole, _, _ = unfold_strips(geometry, IDS, [0, 1, 2], trims=trims, source="test")
    for v in range(3):
        boards = [p for p in parts if p["strip"] == v]
        for p in boards:
            assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9
        assert sum(p["area"] for p in boards) == pytest.approx(whole[v]["area"], rel=1e-9)
        rows = [j["row"] for j in joints if j["strip"] == IDS[v]]
        assert any(isinstance(r, float) and LONG < r < LONG + 1 for r in rows)
    entire = [p for p in parts if not p.get("trimmed")]
    assert entire                                      # a board of whole quads between joints
    for p in entire:
        a, b = _span(p)
        A3, B3 = strip_between(*geometry[p["strip"]], a, b)
        ga, gb = (np.asarray(g) for g in p["geodesics"])
        assert _lengths(ga, gb) == pytest.approx(_lengths(A3, B3), rel=1e-9, abs=1e-9)


def test_strips_of_one_template_are_cut_at_the_same_place_inside_the_quad():
    """Copies of one strip (the cone strip turned about its axis): the template's cut inside
    the long quad is the same on every strip, so the boards of a pattern stay copies."""
    geometry = [cone(0, turn) for turn in (0.0, 2.2, 4.4)]
    parts, classes, joints = unfold_strips(geometry, IDS, [0, 1, 2], stock_length=STOCK,
                                           congruence_tol=0.01, template=True)
    cuts = [j["cut"] for j in joints]
    inside = [c for c in cuts if LONG < c["A"][0] < LONG + 1]
    assert inside
    for c in inside:
        assert c["A"][0] == pytest.approx(c["B"][0], abs=1e-9)        # the same fraction
        assert c["A"][1] == pytest.approx(0.0, abs=1e-9)
        assert c["B"][1] == pytest.approx(1.0, abs=1e-9)
    per_strip = {v: np.array([j["cut"]["along"] for j in joints if j["strip"] == IDS[v]])
                 for v in range(3)}
    assert per_strip[0] == pytest.approx(per_strip[2], abs=1e-9)
    n_boards = {v: sum(p["strip"] == v for p in parts) for v in range(3)}
    assert len(classes) == n_boards[0] + n_boards[1]
    assert max(c["max_deviation_mm"] for c in classes) <= 0.01
    for p in parts:
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= STOCK + 1e-9
    area = sum(p["area"] for p in parts if p["strip"] == 0)
    assert area == pytest.approx(signed_area(develop_strip(*geometry[0]).outline), rel=1e-9)


def test_unfold_records_fractional_rows(geometry, tmp_path):
    """`dgpc unfold --stock-length` exits 0 on the strips; the flat artifact (checked against
    its schema when read) records the boards' fractional rows, and the cut list names them."""
    m = len(THETA)
    records = [{"id": IDS[v], "v": v, "rows": m, "planarity": 0.0, "deviation": 0.0,
                "width": 600.0, "ruling_directions": np.tile([0.0, 0.0, 1.0], (m, 1)),
                "flat_rows": [False] * m, "params": np.zeros((m, 2)),
                "polish": {"applied": False}} for v in range(3)]
    art = StripsArtifact(geometry=geometry, records=records, source_shape=(m, 4), units="mm")
    write_files(strips_files(tmp_path / "s", art))
    dgpc("unfold", tmp_path / "s", "--stock-length", "6m", "-o", tmp_path / "f")
    flat = read_flat(tmp_path / "f")
    spans = [p["row_span"] for p in flat.parts if "row_span" in p]
    assert spans and all(LONG < t < LONG + 1 for s in spans for t in s if t != round(t))
    assert any(isinstance(j["row"], float) for j in flat.joints)
    with open(tmp_path / "f.assembly.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    starts = [float(r["row_start"]) for r in rows]
    assert any(LONG < s < LONG + 1 for s in starts)
    doc = json.loads((tmp_path / "f.json").read_text())
    part = next(p for p in doc["data"]["parts"] if "row_span" in p)
    part["row_span"] = [part["row_span"][1], part["row_span"][0]]
    (tmp_path / "f.json").write_text(json.dumps(doc))
    with pytest.raises(DgpcError, match="row_span"):
        read_flat(tmp_path / "f")


def _run(rows, stock, forbidden=(), stagger=0.0, relax=False):
    """Joints of a straight strip of unit width whose rulings lie at the arc lengths ``rows``
    (a board's extent: its length)."""
    positions = np.asarray(rows, float)

    def extent(a, b):
        return float(np.interp(b, np.arange(len(rows)), positions)
                     - np.interp(a, np.arange(len(rows)), positions))

    m = len(rows)
    return split_run(extent, 0, m - 1, list(range(1, m - 1)), stock,
                     np.asarray(forbidden, float), stagger, positions, "S-v01", relax)


def test_no_sliver_is_left_before_a_long_quad():
    """Rulings at 0, 1, 10, 11 with a stock of 6: the farthest ruling within the stock (1)
    would leave a board of 1 before the long quad; the joint goes inside it, at 6."""
    joints = _run([0.0, 1.0, 10.0, 11.0], 6.0)
    cuts = np.interp([0, *joints, 3], np.arange(4), [0.0, 1.0, 10.0, 11.0])
    assert np.diff(cuts).max() <= 6.0 + 1e-9
    assert cuts[1] == pytest.approx(6.0, abs=1e-9)            # inside the quad 1 … 2
    assert len(joints) == 1 and 1 < joints[0] < 2


def test_a_joint_inside_a_quad_keeps_the_stagger():
    """The neighbour's joint at 5.5: the farthest cut within the stock (6) is nearer than the
    stagger 2, so the joint moves back to 3.5, inside the long quad."""
    joints = _run([0.0, 1.0, 10.0, 11.0], 6.0, forbidden=[5.5], stagger=2.0)
    cuts = np.interp([0, *joints, 3], np.arange(4), [0.0, 1.0, 10.0, 11.0])
    assert cuts[1] == pytest.approx(3.5, abs=1e-9)
    assert np.diff(cuts).max() <= 6.0 + 1e-9
    # a stagger no cut can keep: an error, or with the default stagger a warning
    with pytest.raises(DgpcError, match="keeps"):
        _run([0.0, 8.0, 9.0], 6.0, forbidden=[5.0, 2.0], stagger=4.0)
    joints = _run([0.0, 8.0, 9.0], 6.0, forbidden=[5.0, 2.0], stagger=4.0, relax=True)
    assert joints == pytest.approx([0.75], abs=1e-9)           # as far as the stock allows


def test_strips_with_cut_edges_are_cut_inside_quads_along_their_edges():
    """Strips of a shared-outline template cut one by one (each its own rulings and the
    template's curves as cut edges), a stock shorter than some of their quads: the boards'
    outlines follow the cut edges to where they cross the joint, within the stock (measured
    along the edges), and add up to the strip."""
    from test_template_boards import COLUMNS, CURVES, _bent, _developments

    from dgpc_cli.strips.cut_edges import template_cut_edges

    devs = np.concatenate([_developments(), _developments()[::-1]])
    A, B = _bent(devs)
    cuts = [{"A": a, "B": b} for a, b in template_cut_edges(devs, CURVES)]
    geometry, ids = list(zip(A, B, strict=True)), [f"S-v{v:02d}" for v in COLUMNS]
    stock = 450.0
    assert np.linalg.norm(np.diff(A[0], axis=0), axis=1).max() + 300.0 > stock
    parts, _, _ = unfold_strips(geometry, ids, COLUMNS, congruence_tol=0.01, stock_length=stock,
                                cut_edges=cuts)
    whole, _, _ = unfold_strips(geometry, ids, COLUMNS, congruence_tol=0.01, cut_edges=cuts)
    assert sum("row_span" in p for p in parts) > len(COLUMNS)
    for p in parts:
        assert np.ptp(np.asarray(p["outline"])[:, 0]) <= stock + 1e-9
    for w in whole:
        area = sum(p["area"] for p in parts if p["strip"] == w["strip"])
        assert area == pytest.approx(w["area"], rel=1e-7)
