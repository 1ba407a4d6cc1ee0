"""Score lines of the template DXFs (issue "Strips that build the design", item 4: nothing
silent, a cuttable border that misleads is a defect): the strips of a shared-outline template
share their outline but each has its own rulings, so a shop that cut every copy from one class
DXF would score the representative's lines on every copy. Every copy's score lines, in the DXF
the cut list names for it and mapped back by the class's alignment, are that copy's own
developed rulings within 0.01 mm; classes whose copies' score lines coincide keep one DXF."""

import csv

import ezdxf
import numpy as np
import pytest
import shapely
from cli_helpers import dgpc
from dxf_checks import check_cam_ready
from shapely.geometry import MultiLineString
from test_strips_cut_edges import _bent, _developments

from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.strips.cut_edges import template_cut_edges
from dgpc_cli.strips.develop import develop_strip

#: Part of every segment between the points a Hausdorff distance is taken at.
DENSIFY = 0.02


def _strips(d, devs, shared_outline=True):
    """A strips artifact (mm) in ``d`` of the developments ``devs (S, m, 2, 2)`` bent into
    space: a shared-outline template (each strip cut along the shared curves) or, without
    cut edges, strips sharing the template's vertices."""
    from test_strips_cut_edges import CURVES

    A, B = _bent(devs)
    cuts = template_cut_edges(devs, CURVES) if shared_outline else [None] * len(A)
    m = A.shape[1]
    records = [{"id": f"S-v{v:02d}", "v": v, "rows": m, "planarity": 0.0, "deviation": 0.0,
                "width": 300.0, "ruling_directions": np.tile([0.0, 0.0, 1.0], (m, 1)),
                "flat_rows": [False] * m, "params": np.zeros((m, 2)),
                "polish": {"applied": False},
                **({} if c is None else {"cut_edges": {"A": c[0], "B": c[1]}})}
               for v, c in enumerate(cuts)]
    art = StripsArtifact(
        geometry=list(zip(A, B, strict=True)), records=records,
        source_shape=(m, len(A) + 1), units="mm",
        template={"variant": "shared-outline" if shared_outline else "shared-vertices",
                  "start": "per-strip", "status": "converged", "iterations": 1,
                  "A": devs[0, :, 0], "B": devs[0, :, 1]})
    write_files(strips_files(d / "s", art))
    return A, B


@pytest.fixture(scope="module")
def shared_outline(tmp_path_factory):
    """Four strips of one shared-outline template, each its own rulings, unfolded whole and
    into boards of 0.9 m."""
    d = tmp_path_factory.mktemp("score")
    A, B = _strips(d, _developments())
    dgpc("unfold", d / "s", "-o", d / "flat")
    dgpc("unfold", d / "s", "--stock-length", "0.9m", "--stagger", "200mm", "-o", d / "boards")
    return d, A, B


def _files_of_copies(d, stem):
    """Cut list rows by class, and part id -> the DXF the cut list names for that copy: the
    class's one file, or (one per copy) the file of each copy, in the order of ``parts``."""
    rows = list(csv.DictReader((d / f"{stem}.parts.csv").open()))
    out = {}
    for r in rows:
        files, parts = r["dxf"].split(), r["parts"].split()
        assert len(files) in (1, len(parts))
        out.update(zip(parts, files * len(parts) if len(files) == 1 else files, strict=True))
    return {r["class"]: r for r in rows}, out


def _layer_lines(path, layer):
    msp = ezdxf.readfile(path).modelspace()
    return [np.array(e.get_points("xy"), float)
            for e in msp.query(f"LWPOLYLINE[layer=='{layer}']")]


def _mapped_back(lines, part, rep):
    """DXF coordinates of a copy (its class's frame, the representative's lower-left corner
    at the origin) mapped back into the copy's own flat frame (mm)."""
    R = np.asarray(part["alignment"]["matrix"], float)
    t = np.asarray(part["alignment"]["translation"], float)
    low = np.asarray(rep["outline"], float).min(axis=0)
    return [(np.asarray(x) + low - t) @ R for x in lines]


def _distance(a, b):
    """Symmetric Hausdorff distance (mm) between two sets of polylines."""
    if not a or not b:
        return 0.0 if not a and not b else np.inf
    return float(shapely.hausdorff_distance(MultiLineString([x.tolist() for x in a]),
                                            MultiLineString([x.tolist() for x in b]),
                                            densify=DENSIFY))


def _check_every_copy(d, stem, own_rulings):
    """Every copy's score lines in its DXF, mapped back, are its own rulings within 0.01 mm
    (and its cut outline its own outline); returns the cut list rows."""
    flat = read_flat(d / stem)
    rows, files = _files_of_copies(d, stem)
    reps = {c["id"]: flat.part(c["representative"]) for c in flat.classes}
    for p in flat.parts:
        path = d / files[p["id"]]
        assert not ezdxf.readfile(path).audit().has_errors
        assert check_cam_ready(path)["CUT:LWPOLYLINE"] == 1
        (cut,) = _mapped_back(_layer_lines(path, "CUT"), p, reps[p["class"]])
        assert _distance([cut], [np.asarray(p["outline"], float)]) <= 0.01
        score = _mapped_back(_layer_lines(path, "SCORE"), p, reps[p["class"]])
        mine = own_rulings(p)
        assert len(score) == len(mine)
        assert _distance(score, mine) <= 0.01, (p["id"], files[p["id"]])
    return flat, rows


def test_every_copy_of_a_shared_outline_template_scores_its_own_rulings(shared_outline):
    d, A, B = shared_outline
    devs = [develop_strip(a, b) for a, b in zip(A, B, strict=True)]

    def own(p):                            # the strip developed anew: its interior rulings
        return list(devs[p["strip"]].rulings)

    flat, rows = _check_every_copy(d, "flat", own)
    assert len(flat.classes) == 1 and flat.classes[0]["quantity"] == 4
    # the copies really differ in their score lines: one DXF per copy, said in the cut list
    (row,) = rows.values()
    assert row["score_lines"] == "per copy"
    assert row["dxf"].split() == [f"flat.C01.{i}.dxf" for i in row["parts"].split()]
    assert flat.classes[0]["score_lines"] == "per copy"
    assert flat.classes[0]["score_deviation_mm"] > 1.0
    assert not (d / "flat.C01.dxf").exists()
    # the copies' outlines are one template: identical cuts in every file
    cuts = [_layer_lines(d / f, "CUT")[0] for f in row["dxf"].split()]
    assert max(np.abs(c - cuts[0]).max() for c in cuts) <= 1e-6
    # labelled with the copy's id (as on a sheet) and its class
    for pid, f in zip(row["parts"].split(), row["dxf"].split(), strict=True):
        texts = [t.dxf.text for t in ezdxf.readfile(d / f).modelspace().query("TEXT")]
        assert texts[0] == pid and texts[1].startswith("C01 ")


def test_every_board_of_a_template_scores_its_own_rulings(shared_outline):
    """With --stock-length the boards of a template are cut at the same template lines (copies
    of two patterns' boards), each with its strip's own rulings clipped to it."""
    d, _, _ = shared_outline
    flat, rows = _check_every_copy(d, "boards",
                                   lambda p: [np.asarray(x, float) for x in p["score"]])
    assert any(int(r["quantity"]) > 1 and r["score_lines"] == "per copy"
               for r in rows.values())


def test_copies_with_the_same_score_lines_keep_one_dxf(tmp_path):
    """Strips sharing the template's vertices (the same rulings on every copy): one DXF for
    the class, score lines shared."""
    devs = np.repeat(_developments()[:1], 3, axis=0)
    A, B = _strips(tmp_path, devs, shared_outline=False)
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "flat")
    own = [develop_strip(a, b) for a, b in zip(A, B, strict=True)]
    flat, rows = _check_every_copy(tmp_path, "flat", lambda p: list(own[p["strip"]].rulings))
    (row,) = rows.values()
    assert (row["quantity"], row["score_lines"], row["dxf"]) == ("3", "shared", "flat.C01.dxf")
    assert flat.classes[0]["score_deviation_mm"] <= 1e-6


def test_score_lines_coincide_within_the_congruence_tolerance_only():
    """A class's copies share their score lines when each copy's, aligned onto the template,
    lies within the tolerance of the template's: a ruling moved 0.3 mm along the part is
    shared at 0.5 mm, one moved 0.6 mm (or missing) is not."""
    from dgpc_cli.stages.unfold import with_score_lines

    def part(pid, shift, rulings=2):
        score = [np.array([[100.0 * (k + 1) + shift, 0.0], [100.0 * (k + 1), 50.0]])
                 for k in range(rulings)]
        return {"id": pid, "score": score,
                "alignment": {"matrix": np.eye(2), "translation": np.zeros(2)}}

    cls = {"id": "C01", "representative": "S-v00", "quantity": 2, "members": ["S-v00", "S-v01"]}
    for copy, want in ((part("S-v01", 0.3), "shared"), (part("S-v01", 0.6), "per copy"),
                       (part("S-v01", 0.0, rulings=1), "per copy")):
        (got,) = with_score_lines([part("S-v00", 0.0), copy], [cls], 0.5)
        assert got["score_lines"] == want
    # the copy's alignment is applied: the template's slanted rulings turned by 180° about
    # (150, 25) are the same score lines, not (unaligned, they lie 20 mm from the template's)
    slanted = part("S-v00", 20.0)
    turned = {**part("S-v01", 0.0), "score": [[300.0, 50.0] - x for x in slanted["score"]],
              "alignment": {"matrix": -np.eye(2), "translation": np.array([300.0, 50.0])}}
    (got,) = with_score_lines([slanted, turned], [cls], 0.5)
    assert got["score_lines"] == "shared" and got["score_deviation_mm"] <= 1e-9
    unaligned = {**turned, "alignment": part("S-v01", 0.0)["alignment"]}
    (got,) = with_score_lines([slanted, unaligned], [cls], 0.5)
    assert got["score_lines"] == "per copy" and got["score_deviation_mm"] >= 19.0
