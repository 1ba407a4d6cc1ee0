"""Fabrication metrics of a strips artifact (SPEC §6 planarize-strips, §7; paper §6.2.4): end
gaps, deviation from the net, seams, ruling turns, side ratios, planarity and areas of its
strips (``strips.fabrication``), in mm, degrees and m², each key named with its unit, for
``planarize-strips`` to record and ``dgpc inspect`` to recompute from the artifact's geometry
and its net."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.strips.fabrication import measure_strips, part_end_gaps, summary

log = logging.getLogger(__name__)

#: Warn when a strip ends farther than this (mm) from the net's edge row (issue "Strips that
#: build the design": end gaps ≤ 1 mm) ...
END_GAP_WARN = 1.0
#: ... or when the strips' area differs from the net's (or the outline's) by more than this
#: share (the parts add up to the design's area within 0.1 %).
AREA_WARN = 1e-3
#: ... or when a strip deviates from its net strip by more than this share of the mean strip
#: width (≤ 1.5 %), or a seam steps by more than this share (≤ 1 %).
DEVIATION_WARN = 0.015
SEAM_STEP_WARN = 0.01
#: The targets by figure (``max_<key>_relative`` of ``metrics.fabrication``).
TARGETS = {"deviation": DEVIATION_WARN, "seam_step": SEAM_STEP_WARN}


def missed_targets(fab: dict) -> list[str]:
    """The keys of :data:`TARGETS` whose figure in ``metrics.fabrication`` ``fab`` exceeds its
    target (a figure that cannot be measured, None or NaN, misses nothing)."""
    return [key for key, limit in TARGETS.items()
            if (v := fab.get(f"max_{key}_relative")) is not None and v == v and v > limit]


def fabrication_warnings(fab: dict) -> list[str]:
    """One line per way the strips of ``metrics.fabrication`` fail to build the design: end
    gaps above :data:`END_GAP_WARN`, a deviation or seam step beyond :data:`DEVIATION_WARN` or
    :data:`SEAM_STEP_WARN` of the mean width, an area off by more than :data:`AREA_WARN`."""
    out = []
    gap, ratio = fab["max_end_gap_mm"], fab["area_ratio"]
    if gap is not None and gap == gap and gap > END_GAP_WARN:
        # a strip dropped by the trim (wholly beyond the outline) has no end gaps
        worst = max(fab["per_strip"], key=lambda i: max(
            (abs(g) for g in fab["per_strip"][i]["end_gaps_mm"] if g is not None), default=-1.0))
        out.append(f"strips end up to {gap:.4g} mm from the net's edge rows ({worst}): built "
                   "as cut, the design has gaps along its edges")
    what = {"deviation": "deviate from the net", "seam_step": "step at their seams"}
    for key in missed_targets(fab):
        out.append(f"the strips {what[key]} by up to {fab[f'max_{key}_mm']:.3g} mm "
                   f"({100 * fab[f'max_{key}_relative']:.2f} % of the mean strip width, "
                   f"target {100 * TARGETS[key]:g} %)")
    if ratio is not None and abs(ratio - 1.0) > AREA_WARN:
        out.append(f"the strips' area is {100 * ratio:.2f} % of the {fab['area_reference']}'s "
                   f"({fab['area_m2']:.4g} of {fab['reference_area_m2']:.4g} m²)")
    return out


def fabrication_metrics(f: np.ndarray, units: str, records: list[dict], geometry: list,
                        reference=None, *, refine: int = 1) -> dict:
    """``metrics.fabrication`` of the strips ``geometry[i] = (A, B)`` with the JSON
    ``records[i]`` (``id``, ``v``, and ``trim`` for a trimmed strip) on the net ``f (m, n, 3)``,
    all in ``units``; ``reference`` (a ``core.reference.ReferenceSurface`` in ``units``) the
    outline the trimmed strips were clipped to (their end gaps are measured to it, their
    areas against its area). Strips of ``refine`` rulings per net row (``planarize-strips
    --refine``) are measured against the net refined as they were fitted
    (:func:`~dgpc_cli.strips.refine.refine_rows`: its geodesics cubic between the net's
    vertices); ``net_quads_max_deviation_mm`` and ``_relative`` then give their deviation from
    the net's own (bilinear) quads too, which cut under the curved geodesics by their sag."""
    from dgpc_cli.strips.cut_edges import edges_between
    from dgpc_cli.strips.develop import develop_strip, signed_area
    from dgpc_cli.strips.fabrication import net_quads_deviation
    from dgpc_cli.strips.refine import refine_rows
    from dgpc_cli.strips.trim import part_area

    coarse = np.asarray(f, float)
    f = refine_rows(coarse, refine)           # what strips of ``refine`` rows were fitted to

    ids = [r["id"] for r in records]
    measures = measure_strips(f, [(r["v"], A, B) for r, (A, B) in
                                  zip(records, geometry, strict=True)])
    part_gaps, part_areas, outline_area = {}, {}, None
    trimmed = [(r, A, B) for r, (A, B) in zip(records, geometry, strict=True) if "trim" in r]
    for r, (A, B) in zip(records, geometry, strict=True):
        if "cut_edges" in r and "trim" not in r:      # cut along a template's curved edges
            dev = develop_strip(A, B)
            a, b = edges_between(dev.A, dev.B, (r["cut_edges"]["A"], r["cut_edges"]["B"]), 0,
                                 len(A) - 1)
            part_areas[r["id"]] = [abs(signed_area(np.concatenate([a, b[::-1]])))]
    if trimmed and reference is not None:
        for r, A, B in trimmed:
            rings = [np.asarray(p["outline"], float) for p in r["trim"]["parts"]]
            dev = develop_strip(A, B)
            part_gaps[r["id"]] = [part_end_gaps(A, B, ring, reference) for ring in rings]
            part_areas[r["id"]] = [part_area(dev.A, dev.B, ring) for ring in rings]
        tri = reference.vertices[reference.faces]
        outline_area = float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0],
                                                           tri[:, 2] - tri[:, 0]), axis=-1).sum())
    out = summary(ids, measures, mm_per_unit=mm_per_unit(units), part_gaps=part_gaps,
                  part_areas=part_areas, outline_area=outline_area)
    if refine > 1:
        worst = net_quads_deviation(coarse, [(r["v"], A, B) for r, (A, B) in
                                             zip(records, geometry, strict=True)])
        out["net_quads_max_deviation_mm"] = worst * mm_per_unit(units)
        out["net_quads_max_deviation_relative"] = (out["net_quads_max_deviation_mm"]
                                                   / out["mean_width_mm"])
        out["refine"] = refine
    return out


def recorded_net(art, json_path: Path):
    """``(net, path)``: the net a strips artifact ``art`` (read from ``json_path``) records as
    ``inputs.net``, if it is there unchanged and matches the strips (units, grid); else None,
    with a warning."""
    from dgpc_cli.io.artifact import recorded_file
    from dgpc_cli.io.net import read_net

    try:
        net_path = recorded_file(art.inputs.get("net"), json_path, "inputs.net")
    except DgpcError as err:
        log.warning("%s; no fabrication metrics from the geometry", err)
        return None
    net = read_net(net_path)
    if net.units != art.units or net.shape != tuple(art.source_shape):
        log.warning("%s: its net %s differs (units or grid); no fabrication metrics from the "
                    "geometry", json_path, net_path)
        return None
    return net, net_path


def inspect_strips(json_path: Path) -> dict:
    """The metrics of the strips artifact ``json_path``: its strips' own from their records,
    ``fabrication`` recomputed from its geometry and the net it records (the recorded one when
    that net is not there or changed, with a warning)."""
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.io.strips import read_strips
    from dgpc_cli.stages.inspect import recorded_reference
    from dgpc_cli.strips.planarize import strips_metrics

    art = read_strips(json_path)
    metrics = strips_metrics(art.records, art.units)
    if "fabrication" in art.metrics:
        metrics["fabrication"] = art.metrics["fabrication"]
    found = recorded_net(art, json_path)
    if found is None:
        return metrics
    net, net_path = found
    reference = None
    if any("trim" in r for r in art.records):
        mesh = recorded_reference(net, net_path)
        reference = ReferenceSurface.from_mesh(mesh) if mesh is not None else None
    metrics["fabrication"] = fabrication_metrics(net.f, art.units, art.records, art.geometry,
                                                 reference,
                                                 refine=art.parameters.get("refine", 1))
    return metrics


@dataclass
class FigureData:
    """What the figures after paper Fig. 18 draw (``report.strips``): the developed strips
    ``(id, A, B)`` in mm aligned on the first (the template) and the largest outline
    distance from it ``template_error`` (mm); per strip the deviation per quad (mm); the
    seams ``(X, step)``: each shared geodesic (strip v's B, in the artifact's unit) with the
    step at its vertices (mm); the mean strip width (mm); ``outlines`` the edges every
    developed strip is cut along ``(A', B')``, aligned as ``developed`` (a shared-outline
    template's curves, :mod:`dgpc_cli.strips.cut_edges`; A and B themselves without), which
    ``template_error`` measures."""

    developed: list
    template_error: float
    deviation: list
    seams: list
    width: float
    outlines: list | None = None


def figure_data(art, f: np.ndarray) -> FigureData:
    """:class:`FigureData` of the strips artifact ``art`` on its net ``f`` (both in
    ``art.units``)."""
    from dgpc_cli.io.units import to_mm
    from dgpc_cli.strips.congruence import align
    from dgpc_cli.strips.cut_edges import edges_between
    from dgpc_cli.strips.develop import develop_strip
    from dgpc_cli.strips.refine import refine_rows

    k = mm_per_unit(art.units)
    f = refine_rows(f, art.parameters.get("refine", 1))       # what the strips were fitted to
    measures = measure_strips(f, [(r["v"], A, B) for r, (A, B) in
                                  zip(art.records, art.geometry, strict=True)])
    devs = [develop_strip(to_mm(A, art.units), to_mm(B, art.units)) for A, B in art.geometry]
    edges = [(dev.A, dev.B) if "cut_edges" not in r else
             edges_between(dev.A, dev.B, (r["cut_edges"]["A"], r["cut_edges"]["B"]), 0,
                           len(dev.A) - 1) for r, dev in zip(art.records, devs, strict=True)]
    developed, outlines, error = [], [], 0.0
    for r, dev, edge in zip(art.records, devs, edges, strict=True):
        al = align(*edge, *edges[0])
        developed.append((r["id"], al.apply(dev.A), al.apply(dev.B)))
        outlines.append(tuple(al.apply(e) for e in edge))
        error = max(error, al.error)
    seams = [(np.asarray(B, float), s.seams[s.v + 1][0] * k)
             for s, (_, B) in zip(measures, art.geometry, strict=True) if s.v + 1 in s.seams]
    return FigureData(developed=developed, template_error=error,
                      deviation=[s.deviation * k for s in measures], seams=seams,
                      width=float(np.mean([s.width for s in measures])) * k,
                      outlines=outlines)
