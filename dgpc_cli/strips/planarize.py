"""``dgpc planarize-strips``: geodesic strips as discrete developable strips of planar quads
(paper §6.2.4, Fig. 18 middle-right; SPEC §6)."""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from shapely.geometry import Polygon
from shapely.ops import unary_union

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.units import from_mm, mm_per_unit
from dgpc_cli.strips import strip_id
from dgpc_cli.strips.crossing import folded_inside
from dgpc_cli.strips.cut_edges import template_cut_edges
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.pinch import PINCH, row_widths, unpinched, widest_section
from dgpc_cli.strips.polish import polish_strip
from dgpc_cli.strips.quality import deviation, planarity_defect, strip_width
from dgpc_cli.strips.refine import refine_rows as refine_rows  # the CLI's --refine
from dgpc_cli.strips.rulings import (
    cut_rulings,
    cut_tangents,
    limit_obliqueness,
    ruling_directions,
    strip_boundaries,
    strip_normals,
)
from dgpc_cli.strips.template import (
    MAX_RULING_TURN,
    RULING_FAIRNESS,
    SEAM_WEIGHT,
    TemplateFit,
    TemplateProblem,
    bend_template,
    closest_on_polylines,
    start_template,
)
from dgpc_cli.strips.trim import TrimPart, part_area, part_length, strip_points, trim_strip

log = logging.getLogger(__name__)

#: Rows whose strip normals turn by less than this (radians per row) count as flat (§6.2.4).
FLAT_ANGLE = 1e-6
#: Rulings cut the boundary geodesics at most this many rows from their v-edge.
MAX_SHIFT = 0.45
#: Quads with a planarity defect above this after the ruling construction get polished.
POLISH_ABOVE = 1e-10
#: Per-strip strips whose quads agree to this fraction of the width are one template already.
CONGRUENT = 1e-9
#: Factors of the ruling fairness tried in turn until a template fit keeps its rulings in order.
FAIRNESS_STEPS = (1.0, 10.0, 100.0)
#: The template fits tried (variant, start), the best kept. The shared outline from both
#: starts: the per-strip strips suit a net whose strips twist (a dragged cylinder: 5.4 % of the
#: width, 15 % from the net's own strips), the net's own strips one whose per-strip rulings
#: swing across parabolic rows (a bowling pin: 2.3 %, 4.5 % from the per-strip strips, whose
#: developments differ by a third of the width); shared vertices from the net's own strips.
TEMPLATE_FITS = (("shared-outline", "per-strip"), ("shared-outline", "net"),
                 ("shared-vertices", "net"))
#: A template whose largest deviation from the net exceeds the per-strip strips' by more than
#: this share of the width is not used (the strips stay on their own, with a warning).
TEMPLATE_MARGIN = 0.01
#: ``--trim`` drops parts shorter than this many quads along the strip.
MIN_PART_QUADS = 1.0


@dataclass
class PlanarStrip:
    """One strip between the u-lines v and v+1 as planar quads ``A_u, A_(u+1), B_(u+1), B_u``.

    ``A, B (m, 3)`` lie on the boundary geodesics v and v+1; the rulings are the segments
    ``A_u B_u``. ``directions (m, 3)`` are the estimated ruling directions (N × N₁, averaged
    across flat rows), ``flat (m,)`` marks those rows, ``limited (m,)`` the rows whose ruling
    was turned towards the v-edge (too oblique for the quad strip), ``params (m, 2)`` the
    parameters of the construction's A, B on the original polylines (row index + fraction;
    the polish then lets them slide), ``rulings_ordered`` whether consecutive rulings keep
    their order along both geodesics (no crossing). ``planarity`` is the
    largest diagonal distance over mean diagonal length, ``deviation`` the largest distance
    from the original strip over its ``width`` (mean v-edge length).
    """

    id: str
    v: int
    A: np.ndarray
    B: np.ndarray
    directions: np.ndarray
    flat: np.ndarray
    limited: np.ndarray
    params: np.ndarray
    planarity: float
    deviation: float
    width: float
    construction_planarity: float
    polish: dict
    rulings_ordered: bool
    #: A shared-outline template's cut edges: the interior samples ``(ts_A, ts_B)`` of its
    #: outline curves in the strip's ``(t, s)`` (:mod:`dgpc_cli.strips.cut_edges`); None where
    #: the parts are cut along the polylines A and B.
    cut_edges: tuple | None = None

    def in_units(self, units: str) -> PlanarStrip:
        """The strip computed in mm with its geometry, width and polish residual (a length)
        in ``units``."""
        k = mm_per_unit(units)
        polish = {**self.polish, **({"R": self.polish["R"] / k} if "R" in self.polish else {})}
        return dataclasses.replace(self, A=from_mm(self.A, units), B=from_mm(self.B, units),
                                   width=self.width / k, polish=polish)

    def record(self) -> dict:
        """The JSON record of the strip (its geometry goes to the OBJ)."""
        return {"id": self.id, "v": self.v, "rows": int(self.A.shape[0]),
                "planarity": self.planarity, "deviation": self.deviation, "width": self.width,
                "construction_planarity": self.construction_planarity,
                "rulings_ordered": self.rulings_ordered,
                "ruling_directions": self.directions, "flat_rows": self.flat.tolist(),
                "limited_rows": self.limited.tolist(),
                "params": self.params, "polish": self.polish,
                **({} if self.cut_edges is None else
                   {"cut_edges": {"A": self.cut_edges[0], "B": self.cut_edges[1]}})}


def parse_strip_range(text: str | None, n: int) -> list[int]:
    """The strips ``V0..V1`` (both included) of ``--strips V0:V1`` for a net with n columns
    (strips 0..n−2); all strips for None. DgpcError naming ``--strips`` if out of range."""
    last = n - 2
    if text is None:
        return list(range(n - 1))
    lo, sep, hi = text.partition(":")
    try:
        v0 = int(lo) if lo.strip() else 0
        v1 = int(hi) if sep and hi.strip() else (last if sep else v0)
    except ValueError:
        raise DgpcError(f"{text!r} is not V0:V1 (two strip indices)", source="--strips") from None
    if not (0 <= v0 <= v1 <= last):
        raise DgpcError(f"{text!r} is outside the net's strips 0:{last} (the net has {n} "
                        f"u-lines, so {n - 1} strips)", source="--strips")
    return list(range(v0, v1 + 1))


def _forward(X: np.ndarray, curve: np.ndarray) -> bool:
    """Whether every segment of the new boundary ``X (m, 3)`` runs forward along the original
    one ``curve (m, 3)`` (positive projection on the corresponding original segment)."""
    return bool(np.all(np.einsum("ij,ij->i", np.diff(X, axis=0), np.diff(curve, axis=0)) > 0))


def planarize_strips(f: np.ndarray, columns: list[int], *, flat_angle: float = FLAT_ANGLE,
                     polish_above: float = POLISH_ABOVE, max_shift: float = MAX_SHIFT,
                     progress: Callable[[int], None] | None = None) -> list[PlanarStrip]:
    """Planar-quad strips for the strips ``columns`` of the net ``f (m, n, 3)`` (§6.2.4).

    Rulings from neighbouring normals N × N₁ (averaged across flat parts; turned towards the
    v-edge where they would cut more than ``max_shift`` rows away), ruling planes cut with
    the boundary geodesics, then a guided-projection polish of strips whose quads stay measurably
    non-planar (defect above ``polish_above``).
    """
    f = np.asarray(f, dtype=float)
    n = f.shape[1]
    P, Q = strip_boundaries(f, columns)
    normals = strip_normals(P, Q)
    directions, flat = ruling_directions(P, Q, normals, flat_angle)
    directions, limited = limit_obliqueness(P, Q, directions, normals, max_shift)
    A, B, params = cut_rulings(P, Q, directions, normals)
    out = []
    for i, v in enumerate(columns):
        a, b = A[i], B[i]
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            raise DgpcError(f"strip {strip_id(v, n)}: a ruling plane does not cut the boundary "
                            "geodesics (degenerate strip)", source="net")
        before = float(np.max(planarity_defect(a, b)))
        polish = {"applied": False}
        if before > polish_above:
            result = polish_strip(a, b, P[i], Q[i], cut_tangents(P[i], Q[i], params[i]))
            a, b = result.A, result.B
            polish = {"applied": True, "status": result.status,
                      "iterations": result.iterations, "R": result.R}
            log.debug("%s: polish %s after %d iterations", strip_id(v, n), result.status,
                      result.iterations)
        width = strip_width(P[i], Q[i])
        strip = PlanarStrip(
            id=strip_id(v, n), v=int(v), A=a, B=b, directions=directions[i], flat=flat[i],
            limited=limited[i],
            params=params[i], planarity=float(np.max(planarity_defect(a, b))),
            deviation=deviation(a, b, P[i], Q[i]) / width, width=width,
            construction_planarity=before, polish=polish,
            rulings_ordered=_forward(a, P[i]) and _forward(b, Q[i]))
        if not strip.rulings_ordered:    # said once the strips are final (crossed_strips):
            # these may only start a template fit, or fold beyond a trim outline
            log.debug("%s: rulings cross (their cuts with the geodesics are out of order)",
                      strip.id)
        out.append(strip)
        if progress is not None:
            progress(1)
    return out


def template_qualifies(f: np.ndarray, columns: list[int]) -> str | None:
    """None when the strips ``columns`` of the net ``f (m, n, 3)`` can share one template, else
    why not (one line): the net must pass ``extract-mold``'s own check (isometric to a surface
    of revolution: equation (5), every panel on its mold patch) and its strips must be equally
    wide (7) (strips of unequal widths c_j d(u) are not congruent)."""
    from dgpc_cli.mold.extract import DEFAULT_TOL, extract_mold
    from dgpc_cli.mold.profile import column_factors, net_widths

    try:
        extract_mold([("the net", f)])
    except DgpcError as exc:
        return exc.reason
    wd = net_widths(f)
    c = column_factors(wd.w, wd.d)[columns]
    spread = float((c.max() - c.min()) / c.mean())
    if spread > DEFAULT_TOL:
        return (f"its strips are not equally wide (widths differ by {spread:.2e} relative, "
                f"more than {DEFAULT_TOL:g}), so they are not congruent")
    return None


def _template_ordered(template: np.ndarray) -> bool:
    """Whether the quads of a ``template (m, 2, 2)`` keep their rulings in order: both
    boundaries run forward (along the chord from the first ruling's midpoint to the last's)
    and every quad turns the same way (the cross product of its diagonals keeps its sign), so
    no two rulings cross. Its exact bendings keep every quad's shape, hence the same order."""
    a, b = template[:, 0], template[:, 1]
    chord = 0.5 * (a[-1] + b[-1] - a[0] - b[0])
    forward = all(bool(np.all(np.diff(X, axis=0) @ chord > 0)) for X in (a, b))
    d1, d2 = b[1:] - a[:-1], a[1:] - b[:-1]
    turn = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    return forward and bool(np.all(turn > 0) or np.all(turn < 0))


def _congruent(A: np.ndarray, B: np.ndarray, width: float) -> bool:
    """Whether the planar strips ``A, B (S, m, 3)`` are congruent to the first one with the same
    vertices, within ``CONGRUENT`` × ``width`` (every edge, ruling and diagonal of every quad)."""
    def lengths(a, b):
        return np.concatenate([np.linalg.norm(np.diff(a, axis=-2), axis=-1),
                               np.linalg.norm(np.diff(b, axis=-2), axis=-1),
                               np.linalg.norm(b - a, axis=-1),
                               np.linalg.norm(b[..., 1:, :] - a[..., :-1, :], axis=-1),
                               np.linalg.norm(a[..., 1:, :] - b[..., :-1, :], axis=-1)], axis=-1)

    return bool(np.abs(lengths(A, B) - lengths(A[:1], B[:1])).max() <= CONGRUENT * width)


def _worst_deviation(A, B, P, Q) -> float:
    """The largest deviation of the strips ``A, B`` from the net strips ``P, Q (S, m, 3)``
    over their widths."""
    return max(deviation(a, b, p, q) / strip_width(p, q)
               for a, b, p, q in zip(A, B, P, Q, strict=True))


def template_strips(f: np.ndarray, strips: list[PlanarStrip], units: str, *,
                    seam_weight: float = SEAM_WEIGHT, ruling_fairness: float = RULING_FAIRNESS,
                    max_ruling_turn: float = MAX_RULING_TURN, margin: float = TEMPLATE_MARGIN
                    ) -> tuple[list[PlanarStrip] | None, dict]:
    """The planar strips ``strips`` (per-strip, of the net ``f`` in mm) replaced by exact
    bendings of one template (:mod:`dgpc_cli.strips.template`), and the template's record
    (variant, start, fit outcome, its 2-D boundaries in ``units``, the deviations tried).

    The fits of :data:`TEMPLATE_FITS` (variants shared vertices and shared outline, starts the
    per-strip strips and the net's own strips with rulings on the v-edges) share one
    :class:`~dgpc_cli.strips.template.TemplateProblem` (one setup); the fit that stays
    closest to the net (largest deviation) is kept. Strips that are congruent already (a
    surface of revolution) are rebuilt from the first one's development without a fit
    (status ``congruent``). Fits whose template folds (rulings that cross) are refused; the
    ruling fairness is raised tenfold until one keeps them in order (:data:`FAIRNESS_STEPS`).
    The fits hold the seams with ``seam_weight``; when none of them keeps within ``margin``
    (below), they are tried again without the seam term (closer to the net, seams that step
    more) and the closest of all is kept. Without such a fit, or when the best one deviates
    from the net by more than ``margin`` of the width beyond the per-strip strips, returns
    ``(None, record)``, the record's ``rejected`` saying why.
    """
    f = np.asarray(f, dtype=float)
    columns = [s.v for s in strips]
    cols = np.asarray(columns)
    P, Q = np.moveaxis(f[:, cols], 1, 0), np.moveaxis(f[:, cols + 1], 1, 0)
    starts = {"per-strip": (np.stack([s.A for s in strips]), np.stack([s.B for s in strips])),
              "net": (P, Q)}
    per_strip = _worst_deviation(*starts["per-strip"], P, Q)
    best, tried = None, []
    if _congruent(*starts["per-strip"], min(s.width for s in strips)):
        # a surface of revolution: the per-strip strips are one template already
        A0, B0 = starts["per-strip"]
        template = start_template(A0[:1], B0[:1])
        A1, B1 = bend_template(template, A0, B0)
        fit = TemplateFit(A=A1, B=B1, template=template, variant="shared-vertices",
                          status="congruent", iterations=0, R=0.0)
        best = (0.0, "per-strip", fit, 0.0, 0.0)
        starts = {}
    # the seam term first; without it only if no fit with it keeps within the margin
    seams = (seam_weight, 0.0) if seam_weight > 0 else (seam_weight,)
    for seam in seams if starts else ():
        if best is not None and best[0] <= per_strip + margin:
            break
        for factor in FAIRNESS_STEPS:
            shared = TemplateProblem.build(f, columns, seam_weight=seam,
                                           ruling_fairness=ruling_fairness * factor,
                                           max_ruling_turn=max_ruling_turn)
            problems = {v: shared.with_variant(v) for v in {v for v, _ in TEMPLATE_FITS}}
            for (variant, name), (A0, B0) in ((k, starts[k[1]]) for k in TEMPLATE_FITS):
                fit = problems[variant].fit(A0, B0)
                worst = _worst_deviation(fit.A, fit.B, P, Q)
                ordered = all(_template_ordered(t) for t in (
                    fit.developments if fit.developments is not None else [fit.template]))
                tried.append({"variant": fit.variant, "start": name, "seam_weight": seam,
                              "ruling_fairness": ruling_fairness * factor,
                              "deviation": worst, "rulings_ordered": ordered})
                log.debug("template fit (%s) from the %s start, seam weight %g, ruling "
                          "fairness %g: largest deviation %.3g of the width, rulings %s",
                          fit.variant, name, seam, ruling_fairness * factor, worst,
                          "in order" if ordered else "crossing")
                if ordered and (best is None or worst < best[0]):
                    best = (worst, name, fit, ruling_fairness * factor, seam)
            if any(t["rulings_ordered"] and t["seam_weight"] == seam for t in tried):
                break
    record = {"per_strip_deviation": per_strip, "tried": tried}
    if best is None:
        return None, {**record, "rejected": "every template fit crossed its rulings (folded "
                      "quads)"}
    worst, start, fit, fairness, seam = best
    if worst > per_strip + margin:
        return None, {**record, "rejected": (
            f"the best template deviates from the net by {100 * worst:.2f} % of the strip "
            f"width, the strips on their own by {100 * per_strip:.2f} % (more than "
            f"{100 * margin:g} % apart)")}
    _, _, sA = closest_on_polylines(fit.A, P)
    _, _, sB = closest_on_polylines(fit.B, Q)
    cuts = (None if fit.outline is None or fit.developments is None else
            template_cut_edges(fit.developments, fit.outline))
    if fit.outline is not None and cuts is None:
        log.warning("planarize-strips: a strip's ruling ends do not follow the template's "
                    "outline curves in order; the parts are cut along their polylines")
    out = []
    for i, strip in enumerate(strips):
        a, b = fit.A[i], fit.B[i]
        out.append(dataclasses.replace(
            strip, A=a, B=b, params=np.stack([sA[i], sB[i]], axis=-1),
            planarity=float(np.max(planarity_defect(a, b))),
            deviation=deviation(a, b, P[i], Q[i]) / strip.width,
            rulings_ordered=True, cut_edges=None if cuts is None else cuts[i]))
    record = {"variant": fit.variant, "start": start, "seam_weight": seam,
              "ruling_fairness": fairness,
              "max_ruling_turn": max_ruling_turn,
              "status": fit.status, "iterations": fit.iterations,
              "A": from_mm(fit.template[:, 0], units), "B": from_mm(fit.template[:, 1], units),
              **record}
    return out, record


def strips_metrics(records: list[dict], units: str = "mm") -> dict:
    """Metrics of SPEC §7 for a strips artifact from its strips' records
    (:meth:`PlanarStrip.record`, in ``units``): planarity and deviation per strip and worst,
    each key named with its unit: ``deviation_relative`` the largest distance from the net
    strip over the strip's width, ``planarity_diagonal_relative`` the largest diagonal distance
    over the quad's mean diagonal, ``width_mm`` (their lengths in mm are in ``fabrication``)."""
    k = mm_per_unit(units)
    return {
        "n_strips": len(records),
        "max_planarity_diagonal_relative": max(r["planarity"] for r in records),
        "max_deviation_relative": max(r["deviation"] for r in records),
        "polished": sum(bool(r["polish"].get("applied")) for r in records),
        "per_strip": {r["id"]: {"planarity_diagonal_relative": r["planarity"],
                                "deviation_relative": r["deviation"],
                                "width_mm": r["width"] * k,
                                "flat_rows": int(np.sum(r["flat_rows"])),
                                "limited_rows": int(np.sum(r["limited_rows"]))}
                      for r in records},
    }


def _trimmed(strip, dev, parts: list[TrimPart], least: float
             ) -> tuple[list[TrimPart], list[dict]]:
    """Of the ``parts`` of one strip inside the reference's outline (``dev`` the strip's
    development), the pieces kept, and the records of what is dropped (its ``rows``,
    ``quads``, ``area`` and ``reason``: ``pinched`` where the strip is narrower than
    ``least``, ``sliver`` for a piece nowhere as wide, ``short`` for one shorter than one
    quad)."""
    widths = row_widths(strip.A, strip.B)
    kept, dropped = [], []

    def drop(ring, reason):
        t = TrimPart(np.asarray(ring, float))
        dropped.append({"rows": list(t.t_range), "quads": t.quads, "reason": reason,
                        "area": part_area(dev.A, dev.B, t.outline)})

    for part in parts:
        pieces = unpinched(part.outline, widths, least)
        whole = part_area(dev.A, dev.B, part.outline)
        lost = whole - sum(part_area(dev.A, dev.B, r) for r in pieces)
        if lost > 1e-9 * whole:
            rest = Polygon(part.outline).difference(unary_union([Polygon(r) for r in pieces]))
            dropped.append({"rows": [rest.bounds[0], rest.bounds[2]],
                            "quads": rest.bounds[2] - rest.bounds[0], "reason": "pinched",
                            "area": lost})
        for ring in pieces:
            piece = TrimPart(ring)
            if piece.quads < MIN_PART_QUADS:
                drop(ring, "short")
            elif widest_section(ring, widths) < least:
                drop(ring, "sliver")
            else:
                kept.append(piece)
    return kept, dropped


#: What a note says of a dropped part, by its reason.
DROPPED = {"short": "a part {quads:.2f} quads long ({where}) dropped, shorter than one quad",
           "sliver": "a part {quads:.2f} quads long ({where}) dropped, narrower everywhere "
                     "than {pinch:g} of the parts' mean width"}


def trim_records(strips: list[PlanarStrip], reference) -> tuple[list[dict], list[str]]:
    """``planarize-strips --trim``: for every strip the parts inside the outline of
    ``reference`` (``strips.trim``) as JSON records — id (the strip's id, with a letter when
    the outline cuts the strip into several parts), outline in ``(t, s)`` and in 3-D, the rows
    it spans — and what is dropped (``_trimmed``: the rows where a strip pinches below
    :data:`~dgpc_cli.strips.pinch.PINCH` of the parts' mean width (their area over their
    length), slivers, parts shorter than one quad, each with the area it leaves bare); plus
    one note per part dropped, one for the pinched ends and one of the whole area left bare."""
    found = [(s, develop_strip(s.A, s.B), trim_strip(s.A, s.B, reference)) for s in strips]
    length = sum(part_length(s.A, s.B, p.outline) for s, _, parts in found for p in parts)
    area = sum(part_area(d.A, d.B, p.outline) for _, d, parts in found for p in parts)
    least = PINCH * area / length if length > 0 else 0.0      # the parts' mean width
    tri = reference.vertices[reference.faces]
    outline_area = float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0],
                                                       tri[:, 2] - tri[:, 0]), axis=-1).sum())
    notes, records, pinched = [], [], []
    for strip, dev, parts in found:
        kept, dropped = _trimmed(strip, dev, parts, least)
        for d in dropped:
            if d["reason"] == "pinched":
                pinched.append((strip.id, d["area"]))
                continue
            where = (f"rows {d['rows'][0]:.2f}-{d['rows'][1]:.2f}, "
                     f"{100 * d['area'] / outline_area:.2g} % of the reference's area")
            notes.append(f"{strip.id}: " + DROPPED[d["reason"]].format(
                quads=d["quads"], where=where, pinch=PINCH))
        if not kept and not dropped:
            notes.append(f"{strip.id}: entirely beyond the reference's outline, dropped")
        letters = len(kept) > 1
        records.append({
            "parts": [{"id": strip.id + (chr(ord("a") + k) if letters else ""),
                       "outline": p.outline,
                       "outline_3d": strip_points(strip.A, strip.B, p.outline),
                       "rows": [int(np.floor(p.t_range[0])), int(np.ceil(p.t_range[1]))]}
                      for k, p in enumerate(kept)],
            "dropped": dropped})
    if not any(r["parts"] for r in records):
        raise DgpcError("no strip reaches inside the reference's outline", source="--trim")
    if pinched:
        notes.append(f"{', '.join(i for i, _ in pinched)}: the ends where the strip is "
                     f"narrower than {PINCH:g} of the parts' mean width cut off ("
                     f"{100 * sum(a for _, a in pinched) / outline_area:.2g} % of the "
                     "reference's area)")
    dropped = [d["area"] for r in records for d in r["dropped"]]
    if len(dropped) > max(1, len(pinched)):
        notes.append(f"trim: the {len(dropped)} dropped parts leave "
                     f"{100 * sum(dropped) / outline_area:.2f} % of the reference's area bare")
    log.info("trim: %d parts kept, %d dropped", sum(len(r["parts"]) for r in records),
             sum(len(r["dropped"]) for r in records))
    return records, notes


def crossed_strips(strips: list[PlanarStrip], records: list[dict], f) -> list[str]:
    """The ids of the strips whose rulings cross (``rulings_ordered`` false), cut from the net
    ``f (m, n, 3)`` (the strips' unit); of trimmed strips (``records[i]["trim"]``) only those
    with a fold inside a part kept: one beyond the outline is cut away with it."""
    f = np.asarray(f, float)
    out = []
    for strip, record in zip(strips, records, strict=True):
        if strip.rulings_ordered:
            continue
        trim = record.get("trim")
        if trim is not None and not folded_inside(
                strip.A, strip.B, f[:, strip.v], f[:, strip.v + 1],
                [p["outline"] for p in trim["parts"]]):
            log.info("%s: its rulings cross only beyond the outline, cut away", strip.id)
            continue
        out.append(strip.id)
    return out
