"""Fabrication figures of a net being edited (``dgpc edit``).

Settled, they are the pipeline's own: the strips ``planarize-strips`` makes with its defaults
(:func:`~dgpc_cli.stages.planarize_run.planarized`: one template where the net qualifies,
``--refine auto``), the templates ``unfold`` groups them into with its defaults
(:func:`~dgpc_cli.stages.unfold.unfold_strips`, congruence within 0.5 mm), their deviation
from the net and seam steps (``metrics.fabrication``), and the mold ``extract-mold`` finds.

While a handle moves they are a live estimate warm-started from the last strips
(:func:`live_figures`): every strip whose net strip moved keeps its flat shape (its
development, the template's for a template) and is bent anew onto the moved net at the same
places along its geodesics (:func:`~dgpc_cli.strips.template.bend_template`); the templates
and their quantities are the last ones, the deviation and seam steps those of the bent
strips. The pipeline's figures replace them when the net settles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.io.units import from_mm, to_mm
from dgpc_cli.mold.extract import extract_mold
from dgpc_cli.stages.planarize_run import PlanarizeOptions, planarized
from dgpc_cli.stages.strip_fabrication import missed_targets
from dgpc_cli.stages.unfold import CONGRUENCE_TOL_MM, unfold_strips
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.fabrication import net_normals, seam_pair
from dgpc_cli.strips.quality import quad_deviation
from dgpc_cli.strips.refine import refine_rows
from dgpc_cli.strips.template import bend_template, closest_on_polylines

#: A strip whose net strip moved by less than this fraction of its width since the last
#: figures is not bent anew (the drag did not touch it).
TOUCHED = 1e-9


@dataclass
class StripsState:
    """The strips behind the last figures, in mm: ``A, B (S, k, 3)`` on the net ``f`` as
    refined for them (``refine`` rulings per net row), each strip's development ``(S, k, 2,
    2)`` (its flat shape), where its vertices sit along its two geodesics (``sA, sB (S, k)``:
    segment index + fraction), its records (``id``, ``v``, ``cut_edges``) and the figures
    that do not change while it bends (strips, method, templates and quantities)."""

    f: np.ndarray
    refine: int
    A: np.ndarray
    B: np.ndarray
    developments: np.ndarray
    sA: np.ndarray
    sB: np.ndarray
    records: list
    fixed: dict
    #: Per strip its largest deviation from its net strip, per seam (strip s, s+1) its
    #: largest step, in mm; the strips' widths (mean v-edge, mm).
    deviation: np.ndarray | None = None
    seam_step: np.ndarray | None = None
    widths: np.ndarray | None = None


def _geodesics(f: np.ndarray, columns: list[int]) -> tuple[np.ndarray, np.ndarray]:
    cols = np.asarray(columns)
    return np.moveaxis(f[:, cols], 1, 0), np.moveaxis(f[:, cols + 1], 1, 0)


def _measure(state: StripsState, touched: np.ndarray) -> dict:
    """The deviation and seam step of the strips of ``state`` on its net ``state.f``,
    measured anew for the strips ``touched`` and the seams beside them (the others kept), by
    the measures ``metrics.fabrication`` takes (:mod:`dgpc_cli.strips.fabrication`): the
    largest of each over the mean strip width."""
    columns = [r["v"] for r in state.records]
    P, Q = _geodesics(state.f, columns)
    S = len(columns)
    if state.deviation is None:
        state.deviation, state.seam_step = np.zeros(S), np.zeros(max(S - 1, 0))
    state.widths = np.linalg.norm(Q - P, axis=-1).mean(axis=1)
    for i in touched:
        state.deviation[i] = float(np.max(quad_deviation(state.A[i], state.B[i], P[i], Q[i])))
    seams = sorted({j for i in touched for j in (i - 1, i) if 0 <= j < S - 1
                    and columns[j + 1] == columns[j] + 1})
    normals = net_normals(state.f) if seams else None
    for j in seams:
        one, other = seam_pair(state.f, columns[j], state.B[j], state.A[j + 1], normals)
        state.seam_step[j] = max(float(one[0].max()), float(other[0].max()))
    width = float(state.widths.mean())
    deviation = float(state.deviation.max()) / width
    seam = float(state.seam_step.max()) / width if state.seam_step.size else None
    fab = {"max_deviation_relative": deviation, "max_seam_step_relative": seam}
    return {**state.fixed, "deviation": deviation, "seam_step": seam,
            "missed": missed_targets(fab)}


def pipeline_figures(f_mm: np.ndarray, units: str) -> tuple[dict, StripsState | None]:
    """The strips' figures of ``planarize-strips`` and ``unfold`` with their defaults for the
    net ``f_mm (m, n, 3)`` (mm; ``units`` its artifact's unit), and the state the live
    figures start from (None where the strips failed: the figures then hold ``error``)."""
    f_mm = np.asarray(f_mm, dtype=float)
    n = f_mm.shape[1]
    columns = list(range(n - 1))
    try:
        done = planarized(NetArtifact(f=from_mm(f_mm, units), units=units), columns,
                          PlanarizeOptions())
        art = done.art
        geometry = [(to_mm(A, units), to_mm(B, units)) for A, B in art.geometry]
        refine = int(art.parameters.get("refine", 1))
        template = art.template is not None and "rejected" not in art.template
        _, classes, _ = unfold_strips(
            geometry, [r["id"] for r in art.records], [r["v"] for r in art.records],
            congruence_tol=CONGRUENCE_TOL_MM, cut_edges=[r.get("cut_edges")
                                                         for r in art.records],
            template=template, refine=refine)
    except DgpcError as err:
        return {"error": err.reason}, None
    fine = refine_rows(f_mm, refine)
    A = np.stack([g[0] for g in geometry])
    B = np.stack([g[1] for g in geometry])
    P, Q = _geodesics(fine, [r["v"] for r in art.records])
    devs = [develop_strip(a, b) for a, b in zip(A, B, strict=True)]
    fab = art.metrics["fabrication"]
    state = StripsState(
        f=fine, refine=refine, A=A, B=B,
        developments=np.stack([np.stack([d.A, d.B], axis=1) for d in devs]),
        sA=closest_on_polylines(A, P)[2], sB=closest_on_polylines(B, Q)[2],
        records=[{k: r[k] for k in ("id", "v", "cut_edges") if k in r} for r in art.records],
        fixed={"source": "pipeline", "strips": len(geometry),
               "method": art.parameters["method"], "refine": refine,
               "templates": len(classes), "quantities": [c["quantity"] for c in classes]})
    figures = {**state.fixed, "deviation": fab.get("max_deviation_relative"),
               "seam_step": fab.get("max_seam_step_relative"), "missed": missed_targets(fab)}
    return figures, state


def _at(polylines: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points of ``polylines (S, k, 3)`` at the parameters ``s (S, j)`` (segment + fraction)."""
    i = np.clip(np.floor(s).astype(int), 0, polylines.shape[1] - 2)
    t = (s - i)[..., None]
    a = np.take_along_axis(polylines, i[..., None], 1)
    b = np.take_along_axis(polylines, i[..., None] + 1, 1)
    return (1 - t) * a + t * b


def live_figures(state: StripsState, f_mm: np.ndarray) -> tuple[dict, int]:
    """The figures of the strips of ``state`` carried onto the moved net ``f_mm`` (mm): each
    strip whose net strip moved (by more than :data:`TOUCHED` of its width) bent anew, its
    own development onto its vertices each moved as its foot on its geodesic moved
    (:func:`~dgpc_cli.strips.template.bend_template`); ``state`` then holds the bent strips
    (the next event starts from them). Returns the figures (``source`` ``live``) and the
    number of strips bent."""
    fine = refine_rows(np.asarray(f_mm, dtype=float), state.refine)
    columns = [r["v"] for r in state.records]
    P, Q = _geodesics(fine, columns)
    P0, Q0 = _geodesics(state.f, columns)
    width = np.linalg.norm(Q0 - P0, axis=-1).mean(axis=1)
    moved = np.maximum(np.abs(P - P0).max(axis=(1, 2)), np.abs(Q - Q0).max(axis=(1, 2)))
    touched = np.flatnonzero(moved > TOUCHED * width)
    if touched.size:
        # each vertex moved as the foot of it on its geodesic moved (a strip's vertices lie
        # off the geodesic by its deviation: kept), then the strip's own flat shape bent there
        t, sA, sB = touched, state.sA[touched], state.sB[touched]
        A, B = bend_template(state.developments[t],
                             state.A[t] + _at(P[t], sA) - _at(P0[t], sA),
                             state.B[t] + _at(Q[t], sB) - _at(Q0[t], sB))
        state.A[touched], state.B[touched] = A, B
    state.f = fine
    bent = int(touched.size)
    if state.deviation is None:              # the first event measures every strip
        touched = np.arange(len(columns))
    return {**_measure(state, touched), "source": "live"}, bent


def mold_figures(f_mm: np.ndarray, units: str) -> dict:
    """The mold ``extract-mold`` finds for the net (one surface of revolution: its pieces
    and their lengths in the net's unit, its radii) and the largest strain of a panel
    against it; ``{"error": …}`` where there is none."""
    try:
        mold = extract_mold([("net", from_mm(np.asarray(f_mm, dtype=float), units))])
    except DgpcError as err:
        return {"error": str(err)}
    figures = mold.metrics()
    return {"pieces": [{"id": p.id, "rows": [p.start, p.stop], "length": p.length}
                       for p in mold.pieces],
            "segments": figures["segments"],
            "radius": [figures["radius_min"], figures["radius_max"]],
            "strain_max": figures["isometry_error_max"]}


def fabrication_figures(f_mm: np.ndarray, units: str) -> tuple[dict, StripsState | None]:
    """``({"strips": …, "mold": …}, state)``: the pipeline's figures of the settled net
    (:func:`pipeline_figures`, :func:`mold_figures`) and the live figures' start."""
    strips, state = pipeline_figures(f_mm, units)
    return {"strips": strips, "mold": mold_figures(f_mm, units)}, state
