"""``dgpc unfold``: develop planar-quad strips into the plane, optionally cut them into boards of
stock length, and group the parts into congruence classes (paper §6.2.4, Fig. 18 bottom; SPEC
§6, §7, §8).

The stage computes in millimetres (:mod:`dgpc_cli.io.units`): :func:`unfold_strips` takes the
strips in mm and returns records in mm; :func:`records_in_units` turns them into the flat
artifact's unit.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.length import Span
from dgpc_cli.io.units import from_mm, mm_per_unit
from dgpc_cli.nesting.template import copy_drawing, template_drawing
from dgpc_cli.strips.boards import (
    Board,
    at_rows,
    cumulative,
    edge_path,
    fractional,
    knots,
    snapped,
    split_boards,
    strip_between,
)
from dgpc_cli.strips.congruence import Alignment, congruence_classes, kabsch, outline_points
from dgpc_cli.strips.cut_edges import edges_between
from dgpc_cli.strips.develop import Development, develop_strip, signed_area
from dgpc_cli.strips.pinch import PINCH
from dgpc_cli.strips.refine import net_rows
from dgpc_cli.strips.score_lines import aligned, score_distance
from dgpc_cli.strips.template_boards import board_geometry, cut_params, cut_path, template_patterns
from dgpc_cli.strips.trim import developed_part, strip_points
from dgpc_cli.strips.trimmed_boards import board_ring, split_trimmed, whole

log = logging.getLogger(__name__)

#: Default congruence tolerance (mm): the largest point distance of two congruent parts
#: optimally aligned (SPEC §6 unfold).
CONGRUENCE_TOL_MM = 0.5
#: Default stagger of the joints of neighbouring strips, as a fraction of the stock length.
STAGGER_FRACTION = 0.25


def part_widths(A: np.ndarray, B: np.ndarray) -> tuple[float, float]:
    """Least and largest width of a developed part ``A, B (m, 2)``: the distances of the
    vertices of each boundary geodesic from the other one."""
    a, b = LineString(A), LineString(B)
    d = np.concatenate([shapely.distance(shapely.points(A), b),
                        shapely.distance(shapely.points(B), a)])
    return float(d.min()), float(d.max())


def board_record(d: Development, name: str, column: int, number: int, rows: list[float],
                 positions: list[float]) -> dict:
    """The part record (without class and alignment) of the developed strip or board ``d``
    from row ``rows[0]`` to ``rows[1]``; with cut edges (a shared-outline template) its
    ``edges`` too, the outline and the widths taken along them. Where a joint cuts it inside a
    quad (a fractional row), ``rows`` are the net rows it reaches into and ``row_span`` the
    fractional rows of its ends (:func:`row_span`)."""
    return {"id": name, "strip": int(column), "board": int(number),
            **row_span(*rows), "positions": [float(x) for x in positions],
            "outline": d.outline, "score": d.rulings, "label": d.label_point,
            "geodesics": [d.A, d.B], "straightness": d.straightness, "strain": d.strain,
            "length": d.length, "width": list(part_widths(*d.cut_edges)),
            "area": signed_area(d.outline),
            **({} if d.edges is None else {"edges": list(d.edges)})}


def row_span(a: float, b: float) -> dict:
    """``rows``: the net rows ``[floor(a), ceil(b)]`` a part from row ``a`` to row ``b``
    reaches into; and where an end is fractional (a joint inside the planar quad ``u`` at the
    fraction ``f`` of its sides: row ``u + f``) ``row_span``, ``[a, b]``."""
    a, b = snapped(a), snapped(b)
    out = {"rows": [int(np.floor(a)), int(np.ceil(b))]}
    if fractional(a) or fractional(b):
        out["row_span"] = [float(a), float(b)]
    return out


def in_net_rows(parts: list[dict], joints: list[dict], refine: int) -> None:
    """The parts' ``rows``, ``row_span`` and the joints' ``row`` of strips of ``refine``
    rulings per net row (``planarize-strips --refine``), counted in the strips' own rows,
    turned into the net's rows in place: strip row ``t`` is net row ``t / refine``
    (:func:`~dgpc_cli.strips.refine.net_rows`), so an end on a ruling between two net rows is
    a fractional net row (``row_span``) and the end marks (``R<row>``), cut lists and
    assembly name net rows whatever the refinement. A part whose ``rows`` are those it
    reaches into (trimmed, or a template board cut off the rulings: ``cuts`` without
    ``row_span``) keeps whole rows, the net rows it reaches into. The ``(t, s)`` of outlines
    and cuts stay in the strip's own rows (they locate points on its geometry)."""
    if refine == 1:
        return
    for p in parts:
        if (p.get("trimmed") or "cuts" in p) and "row_span" not in p:
            a, b = net_rows(p["rows"], refine)
            p["rows"] = [int(np.floor(snapped(a))), int(np.ceil(snapped(b)))]
            continue
        a, b = net_rows(p.get("row_span", p["rows"]), refine)
        p.pop("row_span", None)
        p.update(row_span(a, b))
    for j in joints:
        j["row"] = joint_row(snapped(float(net_rows(j["row"], refine))))


def with_cut_edges(d: Development, cut: dict | None, r0: float, r1: float,
                   m: int | None = None) -> Development:
    """The development ``d`` of the rows ``r0..r1`` of a strip of ``m`` rows (fractional at a
    joint inside a quad: :func:`~dgpc_cli.strips.boards.strip_between`) with the strip's cut
    edges ``cut`` (its record's ``cut_edges``: the interior samples ``A``, ``B`` in the strip's
    ``(t, s)``, :mod:`dgpc_cli.strips.cut_edges`) over those rows; ``d`` itself without. At a
    fractional end the cut edge starts where it crosses the joint's line (``t`` = that row,
    :func:`~dgpc_cli.strips.boards.edge_path`), at a whole row at the strip's vertex, as the
    strip's own cut edges do."""
    if cut is None:
        return d
    samples = [np.asarray(cut[k], float).reshape(-1, 2) for k in ("A", "B")]
    if fractional(r0) or fractional(r1):
        T = knots(r0, r1)
        paths = [edge_path(e, r0, r1) for e in full_edges(cut, m)]
        return dataclasses.replace(d, edges=tuple(
            strip_points(d.A, d.B, np.column_stack([np.interp(p[:, 0], T, np.arange(len(T))),
                                                    p[:, 1]])) for p in paths))
    shifted = [ts - [r0, 0.0] for ts in samples]
    return dataclasses.replace(d, edges=edges_between(d.A, d.B, shifted, 0, int(r1 - r0)))


def full_edges(cut: dict, m: int) -> list[np.ndarray]:
    """A strip's cut edges (its record's ``cut_edges``) as polylines in its ``(t, s)`` from the
    vertex at row 0 to the vertex at row ``m − 1``, A then B."""
    return [np.concatenate([[[0.0, side]], np.asarray(cut[k], float).reshape(-1, 2),
                            [[m - 1.0, side]]]) for side, k in enumerate(("A", "B"))]


def _boards(geometry: list, devs: list[Development], ids: list[str], columns: list[int],
            stock_length: float | None, stagger: float | None,
            cut_edges: list | None = None) -> list[Board]:
    """Every part as a board: one per strip without a stock length."""
    if stock_length is None:
        return [Board(i, 1, 0, d.A.shape[0] - 1) for i, d in enumerate(devs)]
    relax = stagger is None
    stagger = STAGGER_FRACTION * stock_length if stagger is None else stagger
    cuts = [None if c is None else full_edges(c, len(A))
            for c, (A, _) in zip(cut_edges or [None] * len(devs), geometry, strict=True)]
    return [b for boards in split_boards(devs, geometry, columns, ids, stock_length, stagger,
                                         relax, cuts) for b in boards]


def unfold_strips(geometry: list, ids: list[str], columns: list[int], *,
                  congruence_tol: float = CONGRUENCE_TOL_MM, mirror_ok: bool = False,
                  stock_length: float | None = None, stagger: float | None = None,
                  source: str | None = None, trims: list | None = None,
                  cut_edges: list | None = None, template: bool = False, refine: int = 1
                  ) -> tuple[list[dict], list[dict], list[dict]]:
    """Develop every strip ``(A, B)`` of ``geometry`` (mm), cut it into boards no longer than
    ``stock_length`` (mm; None: whole strips) at rulings, or straight across a planar quad where
    none fits (:mod:`dgpc_cli.strips.boards`), with joints ``stagger`` apart (default a quarter
    of the stock, kept where the joints allow, with a warning where they do not), and
    classify the parts within ``congruence_tol`` (mm); every class then says whether its
    copies share the template's score lines (:func:`with_score_lines`).

    Returns the part records, class records and joint records of the flat artifact (see
    :mod:`dgpc_cli.io.flat`), in mm. DgpcError (naming ``source``) when a developed outline
    crosses itself: a cutter cannot cut it. ``trims[i]`` (``planarize-strips --trim``), when
    given, lists the parts of strip i inside the reference's outline (records with ``id`` and
    ``outline`` in the strip's ``(t, s)``): those are developed instead of the whole strip,
    each its own congruence class (their end cuts follow the outline); they are not cut into
    boards. ``cut_edges[i]`` (a shared-outline template's ``cut_edges`` record), when given,
    are the edges strip i is cut along instead of its polylines A and B
    (:func:`with_cut_edges`): its outline, widths and congruence follow them. ``template``:
    the strips are bendings of one template (``planarize-strips``' ``template`` record); with a
    stock length every strip is then cut at the same lines of the template, in two alternating
    joint patterns (:func:`template_boards`). ``refine``: the strips have that many rulings per
    net row (``planarize-strips --refine``); the records' rows are the net's
    (:func:`in_net_rows`).
    """
    check_stock(geometry, stock_length)
    parts, classes, joints = _unfold_parts(geometry, ids, columns, congruence_tol, mirror_ok,
                                           stock_length, stagger, source, trims, cut_edges,
                                           template)
    in_net_rows(parts, joints, refine)
    return parts, with_score_lines(parts, classes, congruence_tol), joints


def check_stock(geometry: list, stock_length: float | None) -> None:
    """Refuse a ``stock_length`` (mm) shorter than the strips ``geometry`` (mm) are wide: its
    boards would be wider than long, thousands of them (a unit slip, ``2.5mm`` for 2.5 m)."""
    if stock_length is None or not stock_length > 0:
        return
    widest = max(float(np.linalg.norm(np.asarray(B, float) - np.asarray(A, float),
                                      axis=-1).max()) for A, B in geometry)
    if stock_length < widest:
        raise DgpcError(f"{stock_length:g} mm is shorter than the strips are wide (up to "
                        f"{widest:.0f} mm): every board would be wider than long; check its "
                        "unit (2.5m, 2500mm)", source="--stock-length")


def with_score_lines(parts: list[dict], classes: list[dict], tol: float) -> list[dict]:
    """The class records with ``score_lines``: ``shared`` when every copy's score lines,
    carried onto the representative by the copy's alignment, lie within ``tol`` (mm) of the
    representative's (:func:`~dgpc_cli.strips.score_lines.score_distance`), else ``per copy``
    (a shared-outline template: each strip its own rulings); and ``score_deviation_mm``, the
    largest such distance (``parts`` in mm)."""
    by_id = {p["id"]: p for p in parts}
    out = []
    for c in classes:
        rep = by_id[c["representative"]]["score"]
        far = max(score_distance(aligned(by_id[m]["score"], by_id[m]["alignment"]["matrix"],
                                         by_id[m]["alignment"]["translation"]), rep)
                  for m in c["members"])
        out.append({**c, "score_lines": "shared" if far <= tol else "per copy",
                    "score_deviation_mm": far if np.isfinite(far) else None})
    return out


def _unfold_parts(geometry, ids, columns, congruence_tol, mirror_ok, stock_length, stagger,
                  source, trims, cut_edges, template):
    """:func:`unfold_strips` before the score lines are compared."""
    cut_edges = cut_edges or [None] * len(geometry)
    devs = [with_cut_edges(develop_strip(A, B), cut, 0, len(A) - 1)
            for (A, B), cut in zip(geometry, cut_edges, strict=True)]
    if trims is not None and any(t is not None for t in trims):
        if stock_length is not None:
            return trimmed_boards(geometry, devs, ids, columns, trims, congruence_tol,
                                  mirror_ok, stock_length, stagger, source)
        return _unfold_trimmed(geometry, devs, ids, columns, trims, congruence_tol, mirror_ok,
                               source, cut_edges)
    folded = [ids[i] for i, d in enumerate(devs) if not Polygon(d.outline).is_valid]
    if folded:
        raise DgpcError(f"the developed outline of {', '.join(folded)} crosses itself (its "
                        "rulings cross; planarize-strips reports them in status.rulings_cross)",
                        source=source)
    if template and stock_length is not None and len(devs) > 1:
        try:
            if one_template(devs, congruence_tol):
                return template_boards(devs, ids, columns, congruence_tol, mirror_ok,
                                       stock_length, stagger, cut_edges)
        except ValueError as exc:        # a cut's end not reached in its quad
            log.warning("a template cut could not be placed on a strip (%s)", exc)
        log.warning("the strips of the template are not copies within %.3g mm: their boards "
                    "are cut at their own rulings", congruence_tol)
    boards = _boards(geometry, devs, ids, columns, stock_length, stagger, cut_edges)
    split = stock_length is not None
    names = [f"{ids[b.strip]}.{b.number}" if split else ids[b.strip] for b in boards]
    pieces = [with_cut_edges(develop_strip(*strip_between(*geometry[b.strip], b.start,
                                                          b.stop)),
                             cut_edges[b.strip], b.start, b.stop, len(geometry[b.strip][0]))
              if split else devs[b.strip]
              for b in boards]
    classes = congruence_classes([d.cut_edges for d in pieces], congruence_tol,
                                 [(columns[b.strip], b.number, names[i])
                                  for i, b in enumerate(boards)], mirror_ok=mirror_ok)
    along = [0.5 * (cumulative(np.asarray(A, float)) + cumulative(np.asarray(B, float)))
             for A, B in geometry]
    parts: list[dict] = [{} for _ in pieces]
    class_records = []
    for cls in classes:
        rep_len = pieces[cls.representative].length
        for i, al in zip(cls.members, cls.alignments, strict=True):
            d, b = pieces[i], boards[i]
            parts[i] = {**board_record(d, names[i], columns[b.strip], b.number,
                                       [b.start, b.stop],
                                       at_rows(along[b.strip], [b.start, b.stop])),
                        "class": cls.id, "alignment": al.record(rep_len)}
        class_records.append(class_record(cls.id, names[cls.representative],
                                          [names[i] for i in cls.members],
                                          [al.error for al in cls.alignments], rep_len))
    joints = [{"strip": ids[b.strip], "row": joint_row(b.stop),
               "position": parts[i]["positions"][1],
               "parts": [names[i], names[i + 1]]}
              for i, b in enumerate(boards[:-1]) if boards[i + 1].strip == b.strip]
    log.info("%d parts in %d congruence classes, %d joints", len(parts), len(class_records),
             len(joints))
    return parts, class_records, joints


def joint_row(t: float) -> int | float:
    """A joint record's ``row``: the ruling's row, or (a joint inside the planar quad ``u`` at
    the fraction ``f`` of its sides) the fractional row ``u + f``."""
    return float(t) if fractional(t) else int(round(t))


def one_template(devs: list[Development], tol: float) -> bool:
    """Whether the developed strips ``devs`` (cut along their cut edges) are copies of the first
    within ``tol`` (mm), edge A on edge A: the strips of one template."""
    k = 4 * max(d.A.shape[0] for d in devs)
    ref = outline_points(*devs[0].cut_edges, k)
    for d in devs[1:]:
        X = outline_points(*d.cut_edges, k)
        R, t = kabsch(X, ref, False)
        if np.max(np.linalg.norm(X @ R.T + t - ref, axis=1)) > tol:
            return False
    return True


def template_boards(devs: list[Development], ids: list[str], columns: list[int],
                    congruence_tol: float, mirror_ok: bool, stock_length: float,
                    stagger: float | None, cut_edges: list
                    ) -> tuple[list[dict], list[dict], list[dict]]:
    """:func:`unfold_strips` with a stock length for the strips of one template (mm): every
    strip cut at the template's lines of its column's joint pattern
    (:mod:`dgpc_cli.strips.template_boards`; at the template's rulings where the strips share
    its vertices). A part's ``cuts`` records its two end cuts: their template positions along
    edges A and B, the ``(t, s)`` of their ends on the strip and their ``path`` in ``(t, s)``
    (:func:`~dgpc_cli.strips.template_boards.cut_path`); ``rows`` the net rows it
    reaches into; ``positions`` the mean template position of its end cuts; a joint's ``row``
    the ruling nearest its cut."""
    stagger = STAGGER_FRACTION * stock_length if stagger is None else stagger
    on_rulings = all(c is None for c in cut_edges)
    first = int(np.argmin(columns))
    patterns = template_patterns(devs[first], on_rulings, stock_length, stagger,
                                 len(devs) > 2, ids[first])
    parts, edges, keys, ends = [], [], [], []
    for i in sorted(range(len(devs)), key=lambda i: columns[i]):
        d = devs[i]
        along = patterns[(int(columns[i]) - int(columns[first])) % 2].along
        ts = cut_params(d, along)
        for k in range(len(along) - 1):
            g = board_geometry(d, along[k], along[k + 1], ts[k], ts[k + 1])
            name = f"{ids[i]}.{k + 1}"
            t0, t1 = snapped(ts[k, :, 0].min()), snapped(ts[k + 1, :, 0].max())
            span = ({"row_span": [t0, t1]} if on_rulings and (fractional(t0) or fractional(t1))
                    else {})
            parts.append({"id": name, "strip": int(columns[i]), "board": k + 1,
                          "rows": [int(np.floor(t0)), int(np.ceil(t1))], **span,
                          "positions": [float(along[k].mean()), float(along[k + 1].mean())],
                          "cuts": [{"along": along[j].tolist(), "A": ts[j, 0].tolist(),
                                    "B": ts[j, 1].tolist(),
                                    "path": cut_path(d, ts[j]).tolist()} for j in (k, k + 1)],
                          "outline": g["outline"], "score": g["score"], "label": g["label"],
                          "geodesics": list(g["geodesics"]), "edges": list(g["edges"]),
                          "straightness": g["straightness"], "strain": d.strain,
                          "length": g["length"], "width": list(part_widths(*g["edges"])),
                          "area": signed_area(g["outline"])})
            edges.append(g["edges"])
            keys.append((int(columns[i]), k + 1, name))
            ends.append((i, float(ts[k + 1, :, 0].mean())))
    classes = congruence_classes(edges, congruence_tol, keys, mirror_ok=mirror_ok)
    class_records = []
    for cls in classes:
        rep_len = parts[cls.representative]["length"]
        for n, al in zip(cls.members, cls.alignments, strict=True):
            parts[n].update({"class": cls.id, "alignment": al.record(rep_len)})
        class_records.append(class_record(cls.id, parts[cls.representative]["id"],
                                          [parts[n]["id"] for n in cls.members],
                                          [al.error for al in cls.alignments], rep_len))
    joints = [{"strip": ids[i], "row": (joint_row(t) if on_rulings else
                                        min(max(int(round(t)), 1), devs[i].A.shape[0] - 2)),
               "position": parts[n]["positions"][1], "cut": parts[n]["cuts"][1],
               "parts": [parts[n]["id"], parts[n + 1]["id"]]}
              for n, (i, t) in enumerate(ends[:-1]) if ends[n + 1][0] == i]
    log.info("%d boards of the template in %d congruence classes (two joint patterns of %d and "
             "%d boards), %d joints", len(parts), len(class_records),
             len(patterns[0].along) - 1, len(patterns[1].along) - 1, len(joints))
    return parts, class_records, joints


def class_record(cid: str, representative: str, members: list[str], errors: list[float],
                 rep_length: float) -> dict:
    """A class of the flat artifact, its members' alignment errors and its representative's
    length in mm."""
    return {"id": cid, "representative": representative, "quantity": len(members),
            "members": members, "max_error": max(errors),
            "max_relative_error": max(errors) / rep_length, "max_deviation_mm": max(errors)}


#: A part shorter than this (mm) is a slip of a unit, not a part (unfold warns).
MIN_PART_MM = 10.0


def longest_strip_mm(geometry: list) -> float:
    """The length of the longest of the strips ``geometry`` (mm): the mean of its two
    boundary polylines' lengths."""
    return max(0.5 * (float(cumulative(np.asarray(A, float))[-1]) +
                      float(cumulative(np.asarray(B, float))[-1])) for A, B in geometry)


def strip_widths_mm(geometry: list) -> tuple[float, float]:
    """The mean and the largest width of the strips ``geometry`` (mm): the distances between
    their two boundary polylines row by row."""
    widths = np.concatenate([np.linalg.norm(np.asarray(B, float) - np.asarray(A, float),
                                            axis=-1) for A, B in geometry])
    return float(widths.mean()), float(widths.max())


#: The largest congruence tolerance a plain number may give, as a share of the parts' width.
CONGRUENCE_SHARE = 0.01


def checked_lengths(geometry: list, units: str, congruence_tol, stock_length, stagger
                    ) -> tuple[float, float | None, float | None]:
    """``--congruence-tol``, ``--stock-length`` and ``--stagger`` (
    :class:`~dgpc_cli.io.length.Length`; the last two may be None) in mm, held to the rule of
    every length (:meth:`~dgpc_cli.io.length.Length.check`: OptionSlip, a usage error, where
    a length is beyond the limit or a plain number, in the strips' unit ``units``, lies outside
    its plausible span): a congruence tolerance within :data:`CONGRUENCE_SHARE` of the parts'
    mean width, a stock length longer than the widest part and no longer than the longest
    strip, a stagger no longer than the stock length. The stagger's default (``stagger``
    None) is :data:`STAGGER_FRACTION` of the stock length."""
    k, whose = mm_per_unit(units), "the strips'"
    mean, widest = strip_widths_mm(geometry)
    tol_mm = congruence_tol.check("--congruence-tol", units, Span(
        0.0, CONGRUENCE_SHARE * mean, "congruence tolerance", low_open=True,
        high_text=f"{100 * CONGRUENCE_SHARE:g} % of the parts' mean width "
                  f"({CONGRUENCE_SHARE * mean:.3g} mm)"), whose)
    if stock_length is None:
        return tol_mm, None, None
    longest = longest_strip_mm(geometry)
    stock_mm = stock_length.check("--stock-length", units, Span(
        widest, longest, "stock length", low_open=True,
        low_text=f"the widest part ({widest / k:.4g} {units})",
        high_text=f"every strip's length (the longest is {longest / k:.4g} {units}: "
                  "nothing to cut)"), whose)
    if stagger is None:
        return tol_mm, stock_mm, STAGGER_FRACTION * stock_mm
    return tol_mm, stock_mm, stagger.check("--stagger", units, Span(
        0.0, stock_mm, "stagger", high_text=f"the stock length ({stock_length.said(units)})"),
        whose)


def scale_warnings(parts: list[dict], geometry: list, units: str, stock_length) -> list[str]:
    """One-line warnings on an implausible scale (issue: no silent unit traps): a part
    shorter than :data:`MIN_PART_MM`, or a ``stock_length`` (a
    :class:`~dgpc_cli.io.length.Length`, or None) longer than every strip: nothing to cut (only
    with its unit: a plain number that long is a usage error, :func:`checked_lengths`). ``parts``
    are the records of :func:`unfold_strips` and ``geometry`` the strips, both in mm."""
    out = []
    shortest = min(parts, key=lambda p: p["length"])
    if shortest["length"] < MIN_PART_MM:
        out.append(f"part {shortest['id']} is {shortest['length']:.3g} mm long, under "
                   f"{MIN_PART_MM:g} mm: the strips are in {units}; if the design is in metres, "
                   "make the net with `init --units m`")
    if stock_length is not None:
        longest = longest_strip_mm(geometry)
        if stock_length.to_mm(units) > longest:
            out.append(f"--stock-length {stock_length.said(units)} is longer than every strip "
                       f"(the longest is {longest / mm_per_unit(units):.4g} {units}): nothing "
                       "is cut into boards")
    return out


def template_dxfs(parts: list[dict], classes: list[dict], label_style: str = "text"
                  ) -> dict[str, bytes]:
    """The template DXFs (:mod:`dgpc_cli.nesting.template`) from the records of
    :func:`unfold_strips` (mm), labelled in ``label_style``, by name: ``C01`` the
    representative of a class whose copies share their score lines, labelled with the class,
    its quantity and its copies' ids; ``C01.S-v03`` one copy of a class whose copies each have
    their own score lines (``score_lines`` ``per copy``), one per copy in the order of its
    members, each on the representative's outline with the copy's own score lines."""
    by_id = {p["id"]: p for p in parts}
    out = {}
    for c in classes:
        rep = by_id[c["representative"]]
        if c.get("score_lines") != "per copy":
            out[c["id"]] = template_drawing(rep, c, label_style).to_bytes(
                f"template {c['id']}")
            continue
        for m in c["members"]:
            out[f"{c['id']}.{m}"] = copy_drawing(by_id[m], rep, c, label_style).to_bytes(
                f"template {c['id']}, copy {m}")
    return out


def records_in_units(parts: list[dict], classes: list[dict], joints: list[dict], units: str
                     ) -> tuple[list[dict], list[dict], list[dict]]:
    """The records of :func:`unfold_strips` (mm) with their lengths in ``units``: geometry
    stored exactly (:func:`~dgpc_cli.io.units.from_mm`), lengths divided, areas too."""
    k = mm_per_unit(units)

    def geometry(x):
        return from_mm(np.asarray(x, float), units)

    out = []
    for p in parts:
        al = p["alignment"]
        out.append({
            **p, "positions": [x / k for x in p["positions"]],
            "outline": geometry(p["outline"]),
            "score": [geometry(line) for line in p["score"]],
            "label": geometry(p["label"]), "geodesics": [geometry(g) for g in p["geodesics"]],
            **({"edges": [geometry(g) for g in p["edges"]]} if "edges" in p else {}),
            **({"cuts": [cut_in_units(c, k) for c in p["cuts"]]} if "cuts" in p else {}),
            "length": p["length"] / k, "width": [w / k for w in p["width"]],
            "area": p["area"] / k**2,
            "alignment": {**al, "translation": np.asarray(al["translation"]) / k,
                          "error": al["error"] / k}})
    return (out, [{**c, "max_error": c["max_error"] / k} for c in classes],
            [{**j, "position": j["position"] / k,
              **({"cut": cut_in_units(j["cut"], k)} if "cut" in j else {})} for j in joints])


def cut_in_units(cut: dict, k: float) -> dict:
    """A template cut record (:func:`template_boards`) with its positions divided by ``k``."""
    return {**cut, "along": [x / k for x in cut["along"]]}


def cuttable_part(A: np.ndarray, B: np.ndarray, ring: np.ndarray, name: str, source) -> dict:
    """The part of the developed strip ``A, B`` inside ``ring`` (the strip's ``(t, s)``,
    :func:`~dgpc_cli.strips.trim.developed_part`); DgpcError naming ``name`` and ``source``
    when its outline crosses itself (no cutter can cut it)."""
    part = developed_part(A, B, ring)
    if not Polygon(part["outline"]).is_valid:
        raise DgpcError(f"the developed outline of {name} crosses itself", source=source)
    return part


def _unfold_trimmed(geometry, devs, ids, columns, trims, congruence_tol, mirror_ok, source,
                    cut_edges):
    """:func:`unfold_strips` for strips clipped to the reference's outline (mm)."""
    whole = [i for i, t in enumerate(trims) if t is None]
    if whole:
        parts, classes, _ = unfold_strips(
            [geometry[i] for i in whole], [ids[i] for i in whole],
            [columns[i] for i in whole], congruence_tol=congruence_tol, mirror_ok=mirror_ok,
            source=source, cut_edges=[cut_edges[i] for i in whole])
    else:
        parts, classes = [], []
    identity = Alignment.identity()
    for i, trim in enumerate(trims):
        if trim is None:
            continue
        d = devs[i]
        A, B = (np.asarray(X, float) for X in geometry[i])
        along = 0.5 * (cumulative(A) + cumulative(B))
        for piece in trim["parts"]:
            ring = np.asarray(piece["outline"], float)
            part = cuttable_part(d.A, d.B, ring, piece["id"], source)
            t0, t1 = float(ring[:, 0].min()), float(ring[:, 0].max())
            cls = f"C{len(classes) + 1:02d}"
            ga, gb = part["geodesics"]
            parts.append({"id": piece["id"], "strip": int(columns[i]), "board": 1,
                          "rows": [int(r) for r in piece["rows"]],
                          "positions": [float(np.interp(t0, np.arange(len(along)), along)),
                                        float(np.interp(t1, np.arange(len(along)), along))],
                          "class": cls, "strain": d.strain,
                          "width": list(part_widths(ga, gb)),
                          "alignment": identity.record(part["length"]), "trimmed": True,
                          **part})
            classes.append(class_record(cls, piece["id"], [piece["id"]], [0.0],
                                        part["length"]))
    if not parts:
        raise DgpcError("no part lies inside the reference's outline", source=source)
    log.info("%d parts (%d trimmed to the outline) in %d congruence classes", len(parts),
             sum(bool(p.get("trimmed")) for p in parts), len(classes))
    return parts, classes, []


def part_narrowness(parts: list[dict], units: str = "mm") -> dict:
    """How narrow the parts get (issue: no part narrower than a quarter of the mean width):
    ``mean_width_mm`` (their total area over their total length), the ``narrowest`` part (id,
    least width ``width_mm``, ``ratio`` to the mean width) and the parts ``pinched`` below
    :data:`~dgpc_cli.strips.pinch.PINCH` of it; ``parts`` in ``units``."""
    k = mm_per_unit(units)
    length = float(np.sum([p["length"] for p in parts]))
    mean = float(np.sum([p["area"] for p in parts])) / length if length > 0 else 0.0
    least = min(parts, key=lambda p: p["width"][0])
    ratio = least["width"][0] / mean if mean > 0 else 0.0
    return {"mean_width_mm": mean * k,
            "narrowest": {"part": least["id"], "width_mm": least["width"][0] * k,
                          "ratio": ratio},
            "pinched": [p["id"] for p in parts if p["width"][0] < PINCH * mean]}


def narrow_warnings(parts: list[dict], units: str) -> list[str]:
    """One line when a part is narrower than :data:`~dgpc_cli.strips.pinch.PINCH` of the mean
    width (:func:`part_narrowness`; ``parts`` in mm)."""
    n = part_narrowness(parts)
    if not n["pinched"]:
        return []
    k = mm_per_unit(units)
    names = ", ".join(n["pinched"][:6]) + (", ..." if len(n["pinched"]) > 6 else "")
    return [f"{len(n['pinched'])} part(s) narrower than {PINCH:g} of the mean width "
            f"{n['mean_width_mm'] / k:.4g} {units} ({names}; the narrowest "
            f"{n['narrowest']['width_mm'] / k:.4g} {units}): they pinch where the net's "
            "geodesics converge; `planarize-strips --trim` cuts such ends off"]


def flat_metrics(parts: list[dict], classes: list[dict], units: str) -> dict:
    """The metrics of a flat artifact recomputed from its records (``parts`` in ``units``),
    each key named with its unit: lengths in mm (``_mm``), areas in m² (``_m2``), the
    straightness of the developed geodesics (largest distance from their chord over their
    length) and the congruence error (over the part's length) ``relative``; strain
    dimensionless."""
    k = mm_per_unit(units)
    return {
        **part_narrowness(parts, units),
        "n_parts": len(parts), "n_classes": len(classes),
        "max_strain": max(p["strain"] for p in parts),
        "max_straightness_relative": float(max(max(p["straightness"]) for p in parts)),
        "max_congruence_error": max(c["max_relative_error"] for c in classes),
        "max_congruence_deviation_mm": max(c.get("max_deviation_mm", 0.0) for c in classes),
        "classes": {c["id"]: {"quantity": c["quantity"], "representative": c["representative"],
                              "members": c["members"],
                              "max_relative_error": c["max_relative_error"],
                              "max_deviation_mm": c.get("max_deviation_mm", 0.0),
                              "score_lines": c.get("score_lines", "shared")}
                    for c in classes},
        "per_part": {p["id"]: {"strain": p["strain"],
                               "straightness_relative": p["straightness"],
                               "length_mm": p["length"] * k, "class": p["class"],
                               "relative_error": p["alignment"]["relative_error"],
                               "deviation_mm": p["alignment"].get("deviation_mm", 0.0)}
                     for p in parts},
        "total_area_m2": float(np.sum([p["area"] for p in parts])) * k * k * 1e-6,
        "total_length_mm": float(np.sum([p["length"] for p in parts])) * k,
    }


def trimmed_boards(geometry, devs, ids, columns, trims, congruence_tol, mirror_ok,
                   stock_length, stagger, source):
    """:func:`unfold_strips` with a stock length for strips clipped to the reference's outline
    (mm): every trimmed part (a strip without a trim record: its whole length) cut at rulings
    into boards (:mod:`dgpc_cli.strips.trimmed_boards`), ids ``S-v07.1``, ``S-v07b.2``, the
    joints of neighbouring strips staggered. A board between two rulings that the outline does
    not touch is developed and classified as a board of a whole strip; a board with an end cut
    along the outline is its own class, as a trimmed part is."""
    relax = stagger is None
    stagger = STAGGER_FRACTION * stock_length if stagger is None else stagger
    along_a = [cumulative(np.asarray(A, float)) for A, _ in geometry]
    along_b = [cumulative(np.asarray(B, float)) for _, B in geometry]
    by_column = {int(v): i for i, v in enumerate(columns)}
    joints: dict[int, list[float]] = {}
    boards = []                       # (strip, part id, number, a, b, ring of the part)
    for i in sorted(range(len(geometry)), key=lambda i: columns[i]):
        m = len(geometry[i][0])
        pieces = (trims[i]["parts"] if trims[i] is not None else
                  [{"id": ids[i], "outline": [[0, 0], [m - 1, 0], [m - 1, 1], [0, 1]]}])
        left = by_column.get(int(columns[i]) - 1)
        forbidden = (at_rows(along_b[left], joints[left]) if left in joints else np.zeros(0))
        joints[i] = []
        for piece in pieces:
            ring = np.asarray(piece["outline"], float)
            cuts = split_trimmed(devs[i], ring, stock_length, forbidden, stagger, along_a[i],
                                 piece["id"], relax)
            joints[i] += cuts
            ends = [float(ring[:, 0].min()), *cuts, float(ring[:, 0].max())]
            boards += [(i, piece["id"], k + 1, a, b, ring)
                       for k, (a, b) in enumerate(zip(ends[:-1], ends[1:], strict=True))]
    parts, entire, cut = [], [], []
    for i, pid, k, a, b, ring in boards:
        a, b = snapped(a), snapped(b)
        A, B = (np.asarray(X, float) for X in geometry[i])
        along = 0.5 * (along_a[i] + along_b[i])
        r0, r1 = int(np.floor(a)), int(np.ceil(b))
        board = board_ring(Polygon(ring), a, b)
        if whole(board, a, b):         # no end cut along the outline: rows a … b
            sub = develop_strip(*strip_between(A, B, a, b))
            entire.append((len(parts), sub))
            parts.append(board_record(sub, f"{pid}.{k}", columns[i], k, [a, b],
                                      at_rows(along, [a, b])))
            continue
        sub = develop_strip(A[r0:r1 + 1], B[r0:r1 + 1])
        record = board_record(sub, f"{pid}.{k}", columns[i], k, [r0, r1],
                              at_rows(along, [a, b]))
        if (k > 1 and fractional(a)) or (b < float(ring[:, 0].max()) and fractional(b)):
            record["row_span"] = [float(a), float(b)]       # a joint inside a quad
        part = cuttable_part(sub.A, sub.B, board - [r0, 0.0], f"{pid}.{k}", source)
        ga, gb = part["geodesics"]
        record.update(part, width=list(part_widths(ga, gb)), trimmed=True)
        cut.append(len(parts))
        parts.append(record)
    classes = congruence_classes([(d.A, d.B) for _, d in entire], congruence_tol,
                                 [(parts[j]["strip"], parts[j]["id"]) for j, _ in entire],
                                 mirror_ok=mirror_ok) if entire else []
    class_records = []
    for cls in classes:
        rep = parts[entire[cls.representative][0]]
        for n, al in zip(cls.members, cls.alignments, strict=True):
            parts[entire[n][0]].update({"class": cls.id, "alignment": al.record(rep["length"])})
        class_records.append(class_record(cls.id, rep["id"],
                                          [parts[entire[n][0]]["id"] for n in cls.members],
                                          [al.error for al in cls.alignments], rep["length"]))
    identity = Alignment.identity()
    for j in cut:
        cid = f"C{len(class_records) + 1:02d}"
        parts[j].update({"class": cid, "alignment": identity.record(parts[j]["length"])})
        class_records.append(class_record(cid, parts[j]["id"], [parts[j]["id"]], [0.0],
                                          parts[j]["length"]))
    joint_records = [{"strip": ids[i], "row": joint_row(b),
                      "position": parts[n]["positions"][1],
                      "parts": [parts[n]["id"], parts[n + 1]["id"]]}
                     for n, (i, pid, k, a, b, _) in enumerate(boards[:-1])
                     if boards[n + 1][1] == pid]
    log.info("%d boards (%d with an end cut along the outline) in %d congruence classes, "
             "%d joints", len(parts), len(cut), len(class_records), len(joint_records))
    return parts, class_records, joint_records
