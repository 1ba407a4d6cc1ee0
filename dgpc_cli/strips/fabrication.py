"""Fabrication measures of planar-quad strips against their net (paper §6.2.4, Fig. 18; SPEC §6
planarize-strips, §7): what a shop builds when it cuts the developed strips and bends them back.

A strip v lies between the net's geodesics ``P = f[:, v]`` and ``Q = f[:, v+1]`` (``m`` rows,
row 0 and row m−1 the net's edge rows). Its planar-quad version is the polylines ``A`` (on P)
and ``B`` (on Q), ``r`` rows each, quads ``A_u A_(u+1) B_(u+1) B_u`` and rulings ``A_u B_u``.
Everything here is measured from this geometry alone (any construction of A, B), in the unit of
the coordinates given (the stages give millimetres), angles in degrees:

* end gaps (:func:`end_gaps`): at each end, how far along the geodesic the strip stops short of
  the net's edge row (negative: runs past it);
* deviation (:func:`~dgpc_cli.strips.quality.quad_deviation`): the largest distance of the strip
  surface from the net strip surface;
* seams (:func:`seam_offsets`): where two neighbouring strips' copies of their shared geodesic
  (B of strip v, A of strip v+1) lie apart, split along the net's normal (step) and across, in
  the tangent plane (gap);
* ruling turn (:func:`ruling_angles`): the angle between neighbouring rulings (a score line
  that zigzags);
* side ratio (:func:`side_ratios`): each quad's longest side over its shortest (1 for a
  square, large for a quad that is nearly a triangle);
* planarity (:func:`~dgpc_cli.strips.quality.diagonal_gap`): the distance between the lines of
  a quad's two diagonals;
* areas (:func:`strip_area`, :func:`net_strip_area`): what the parts cover against the net.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dgpc_cli.metrics.frames import tangent_frames, unit
from dgpc_cli.strips.quality import diagonal_gap, patch_mesh, quad_deviation, strip_width
from dgpc_cli.strips.trim import signed_outline_distance, strip_points

__all__ = ["StripMeasures", "end_gaps", "measure_strips", "net_quads_deviation", "net_strip_area",
           "part_end_gaps", "polyline_foot", "ruling_angles", "seam_offsets", "side_ratios",
           "strip_area", "summary"]


def polyline_foot(X: np.ndarray, points: np.ndarray, *, extend: bool = False):
    """Closest points on the polyline ``X (m, 3)`` to ``points (k, 3)``: their parameters
    ``t (k,)`` (segment index + fraction, so row u at t = u) and the feet ``(k, 3)``.

    With ``extend`` the first and last segments continue as lines beyond the polyline's ends
    (t < 0 or t > m − 1 there), so a point past an end is measured along the end segment.
    """
    X = np.asarray(X, float)
    p = np.asarray(points, float).reshape(-1, 3)
    a, e = X[:-1], np.diff(X, axis=0)                                        # (m-1, 3)
    ee = np.einsum("si,si->s", e, e)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.einsum("ksi,si->ks", p[:, None] - a[None], e) / np.where(ee > 0, ee, 1.0)
    lo = np.zeros(len(a))
    hi = np.ones(len(a))
    if extend:
        lo[0], hi[-1] = -np.inf, np.inf
    s = np.clip(s, lo, hi)
    foot = a[None] + s[..., None] * e[None]                                   # (k, m-1, 3)
    d = np.linalg.norm(foot - p[:, None], axis=-1)
    best = np.argmin(d, axis=1)
    k = np.arange(len(p))
    return best + s[k, best], foot[k, best]


def arc_length(X: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Arc length along the polyline ``X (m, 3)`` from its start to the parameters ``t``
    (segment index + fraction; linear beyond the ends along the end segments)."""
    seg = np.linalg.norm(np.diff(np.asarray(X, float), axis=0), axis=-1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.asarray(t, float)
    i = np.clip(np.floor(t), 0, len(seg) - 1).astype(int)
    return cum[i] + (t - i) * seg[i]


def end_gaps(P: np.ndarray, Q: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """End gaps ``(2, 2)`` of the strip ``A, B`` on the net strip ``P, Q (m, 3)``: row 0 the
    start (net row 0), row 1 the end (net row m − 1); column 0 the geodesic P (measured at A's
    end vertex), column 1 Q (at B's).

    Each is the length along the net geodesic from the foot of the strip's end vertex to the
    net's edge row: positive where the strip stops short of the edge row (the built wall has a
    gap there), negative where it runs past it, 0 when it ends on it.
    """
    out = np.empty((2, 2))
    for j, (X, Y) in enumerate(((P, A), (Q, B))):
        t, _ = polyline_foot(X, np.asarray(Y, float)[[0, -1]], extend=True)
        s = arc_length(X, t)
        out[0, j] = s[0]
        out[1, j] = arc_length(X, X.shape[0] - 1.0) - s[1]
    return out


def net_normals(f: np.ndarray) -> np.ndarray:
    """Unit net normals N = T^u × T^v ``(m, n, 3)`` at the vertices of the net ``f`` (paper
    §2.2.1, one-sided at the edges)."""
    return tangent_frames(f, one_sided=True)[2]


def net_normals_on(f: np.ndarray, column: int, points: np.ndarray,
                   normals: np.ndarray | None = None) -> np.ndarray:
    """Unit net normals N = T^u × T^v (paper §2.2.1, one-sided at the edges) at the feet of
    ``points (k, 3)`` on the net's geodesic ``f[:, column]`` (linear between rows);
    ``normals`` the net's :func:`net_normals`, where the caller has them already."""
    N = (net_normals(f) if normals is None else normals)[:, column]          # (m, 3)
    t, _ = polyline_foot(f[:, column], points)
    i = np.clip(np.floor(t), 0, len(N) - 2).astype(int)
    w = (t - i)[:, None]
    return unit((1 - w) * N[i] + w * N[i + 1])


def seam_offsets(X: np.ndarray, Y: np.ndarray, normals: np.ndarray):
    """Seam step and gap ``(k,)`` at the vertices of ``X (k, 3)``, one neighbour's copy of a
    shared geodesic, against the other's copy ``Y (l, 3)``, with the surface normals
    ``normals (k, 3)`` there.

    The offset from X's vertex to its closest point on Y, without its part along Y (an offset
    along the geodesic is an end gap, not a seam), splits into the step ``|d · N|`` along the
    normal (the two parts' faces stand apart: a step in the cladding) and the gap
    ``|d − (d · N) N|`` across, in the tangent plane (the parts overlap or leave a slit).
    """
    X, Y = np.asarray(X, float), np.asarray(Y, float)
    t, foot = polyline_foot(Y, X)
    i = np.clip(np.floor(t), 0, len(Y) - 2).astype(int)
    T = unit(Y[i + 1] - Y[i])
    d = X - foot
    d = d - np.einsum("ki,ki->k", d, T)[:, None] * T
    along = np.einsum("ki,ki->k", d, normals)
    step = np.abs(along)
    gap = np.linalg.norm(d - along[:, None] * normals, axis=-1)
    return step, gap


def ruling_angles(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Angles (degrees) ``(r − 1,)`` between neighbouring rulings ``A_u B_u`` and
    ``A_(u+1) B_(u+1)``; in a planar quad both lie in its plane, so this is also their angle on
    the developed part (how much the score lines zigzag)."""
    R = unit(np.asarray(B, float) - np.asarray(A, float))
    c = np.clip(np.einsum("ui,ui->u", R[:-1], R[1:]), -1.0, 1.0)
    return np.degrees(np.arccos(c))


def side_ratios(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Per quad ``(r − 1,)`` its longest side over its shortest (the two rulings and the two
    geodesic edges): 1 for a square, large for a quad that is nearly a triangle (inf for a
    collapsed side)."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    ruling = np.linalg.norm(B - A, axis=-1)
    sides = np.stack([ruling[:-1], ruling[1:], np.linalg.norm(np.diff(A, axis=0), axis=-1),
                      np.linalg.norm(np.diff(B, axis=0), axis=-1)])
    lo = sides.min(axis=0)
    with np.errstate(divide="ignore"):
        return np.where(lo > 0, sides.max(axis=0) / np.where(lo > 0, lo, 1.0), np.inf)


def strip_area(A: np.ndarray, B: np.ndarray) -> float:
    """Area of the strip's quads, each ``|d1 × d2| / 2`` of its diagonals (exact for a planar
    quad, whatever its shape)."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    return float(0.5 * np.linalg.norm(np.cross(B[1:] - A[:-1], B[:-1] - A[1:]), axis=-1).sum())


def net_strip_area(P: np.ndarray, Q: np.ndarray) -> float:
    """Area of the net strip ``P, Q (m, 3)`` over all its rows: its quads as bilinear patches,
    finely triangulated (:func:`~dgpc_cli.strips.quality.patch_mesh`)."""
    from trimesh.triangles import area as triangle_areas

    V, F = patch_mesh(np.asarray(P, float), np.asarray(Q, float))
    return float(triangle_areas(V[F]).sum())


def part_end_gaps(A: np.ndarray, B: np.ndarray, ring: np.ndarray, reference) -> np.ndarray:
    """End gaps ``(2, 2)`` of a trimmed part (``strips.trim``: outline ``ring (k, 2)`` in the
    strip's ``(t, s)``) of the strip ``A, B (r, 3)``, as :func:`end_gaps` but against the
    outline of ``reference``: at the part's first and last point on each boundary geodesic
    (s = 0 for A, 1 for B), the distance over the reference to its outline
    (``trim.signed_outline_distance``: 0 on the outline, positive inside it, where the part
    stops short, negative beyond it). NaN for a boundary the part does not touch."""
    ring = np.asarray(ring, float)
    out = np.full((2, 2), np.nan)
    for j, side in enumerate((0.0, 1.0)):
        t = ring[np.abs(ring[:, 1] - side) <= 1e-9, 0]
        if len(t):
            ends = np.array([[t.min(), side], [t.max(), side]])
            out[:, j] = signed_outline_distance(reference, strip_points(A, B, ends))
    return out


@dataclass
class StripMeasures:
    """The fabrication measures of one strip ``v`` (see the module), per quad where they vary
    along it: ``end_gaps (2, 2)`` (:func:`end_gaps`), ``deviation``, ``planarity``,
    ``ruling_angle`` (degrees) and ``side_ratio`` ``(r − 1,)``, its ``width`` (mean v-edge
    of the net strip), ``area`` and the net strip's ``net_area``; ``seams`` maps a
    neighbour's v to ``(step, gap)``, each ``(k,)`` at this strip's vertices on the shared
    geodesic (B for the neighbour v+1, A for v−1)."""

    v: int
    end_gaps: np.ndarray
    deviation: np.ndarray
    planarity: np.ndarray
    ruling_angle: np.ndarray
    side_ratio: np.ndarray
    width: float
    area: float
    net_area: float
    seams: dict = field(default_factory=dict)

    def seam(self, other: StripMeasures) -> tuple[float, float]:
        """Largest seam step and gap between this strip and its neighbour ``other`` (both
        ways), or NaN when they are not neighbours."""
        a, b = self.seams.get(other.v), other.seams.get(self.v)
        if a is None or b is None:
            return float("nan"), float("nan")
        return (float(max(a[0].max(), b[0].max())), float(max(a[1].max(), b[1].max())))


def measure_strips(f: np.ndarray, strips: list[tuple[int, np.ndarray, np.ndarray]]
                   ) -> list[StripMeasures]:
    """The measures of the strips ``(v, A, B)`` of the net ``f (m, n, 3)``, all in f's unit;
    strips v and v+1 both given are neighbours (their seam is measured)."""
    f = np.asarray(f, float)
    out = []
    for v, A, B in strips:
        A, B = np.asarray(A, float), np.asarray(B, float)
        P, Q = f[:, v], f[:, v + 1]
        out.append(StripMeasures(
            v=int(v), end_gaps=end_gaps(P, Q, A, B), deviation=quad_deviation(A, B, P, Q),
            planarity=diagonal_gap(A, B), ruling_angle=ruling_angles(A, B),
            side_ratio=side_ratios(A, B), width=strip_width(P, Q), area=strip_area(A, B),
            net_area=net_strip_area(P, Q)))
    by_v = {s.v: (s, A, B) for s, (_, A, B) in zip(out, strips, strict=True)}
    normals = net_normals(f)
    for v, (s, _, B) in by_v.items():
        if v + 1 not in by_v:
            continue
        t, A1, _ = by_v[v + 1]
        s.seams[v + 1], t.seams[v] = seam_pair(f, v, B, A1, normals)
    return out


def seam_pair(f: np.ndarray, v: int, B: np.ndarray, A1: np.ndarray,
              normals: np.ndarray | None = None) -> tuple:
    """The seam between strip v (its copy ``B`` of the net's geodesic v+1) and strip v+1 (its
    copy ``A1``): :func:`seam_offsets` both ways, ``(of B's vertices, of A1's)``."""
    B, A1 = np.asarray(B, float), np.asarray(A1, float)
    normals = net_normals(f) if normals is None else normals
    return (seam_offsets(B, A1, net_normals_on(f, v + 1, B, normals)),
            seam_offsets(A1, B, net_normals_on(f, v + 1, A1, normals)))


def net_quads_deviation(f: np.ndarray, strips: list[tuple[int, np.ndarray, np.ndarray]]
                        ) -> float:
    """The largest deviation of the strips ``(v, A, B)`` from the net ``f (m, n, 3)``'s own
    strips (its bilinear quads, :func:`~dgpc_cli.strips.quality.quad_deviation`), in f's
    unit."""
    f = np.asarray(f, float)
    return max(float(np.max(quad_deviation(np.asarray(A, float), np.asarray(B, float),
                                           f[:, v], f[:, v + 1]))) for v, A, B in strips)


def _max(x) -> float:
    x = np.asarray(x, float)
    x = x[~np.isnan(x)]
    return float(x.max()) if x.size else float("nan")


def summary(ids: list[str], measures: list[StripMeasures], *, mm_per_unit: float = 1.0,
            part_areas: dict | None = None, part_gaps: dict | None = None,
            outline_area: float | None = None) -> dict:
    """The JSON record of the measures: per strip (keyed by ``ids``) and the worst over the
    strips, each key named with its unit: lengths in mm (``_mm``: the measures' unit times
    ``mm_per_unit``), angles in degrees (``_deg``), areas in m² (``_m2``), shares of the mean
    strip width ``_relative``; ratios (``side_ratio``, ``area_ratio``) have none.

    Per strip: ``end_gaps_mm`` [start, end] (each the larger of the two geodesics' by
    magnitude, signed as :func:`end_gaps`), ``deviation_mm``, ``planarity_mm``,
    ``seam_step_mm`` and ``seam_gap_mm`` [to strip v−1, to strip v+1] (null without that
    neighbour), ``ruling_angle_deg`` (the largest between neighbouring rulings),
    ``side_ratio`` (the largest longest-over-shortest side), ``width_mm``, ``area_m2`` and
    ``area_ratio`` (over the net strip's); non-finite values (a collapsed quad side's ratio, a
    missing measure) become null in the JSON. For a trimmed strip ``part_gaps[id]`` (its
    parts' :func:`part_end_gaps`) replace the end gaps and ``part_areas[id]`` (its parts'
    areas) the area; the ratio is then taken over ``outline_area`` (the reference's, for all
    strips together) rather than the net's.
    """
    k = mm_per_unit
    by_v = {s.v: s for s in measures}
    per, worst = {}, {}
    part_areas, part_gaps = part_areas or {}, part_gaps or {}
    for sid, s in zip(ids, measures, strict=True):
        gaps = np.asarray(part_gaps.get(sid, s.end_gaps[None]), float).reshape(-1, 2, 2)
        ends = [_scaled(_signed_worst(gaps[:, e].ravel()), k) for e in (0, 1)]
        seams = [s.seam(by_v[w]) if w in by_v else (float("nan"),) * 2
                 for w in (s.v - 1, s.v + 1)]
        area = float(sum(part_areas[sid])) if sid in part_areas else s.area
        per[sid] = {"end_gaps_mm": ends, "deviation_mm": _max(s.deviation) * k,
                    "planarity_mm": _max(s.planarity) * k,
                    "seam_step_mm": [_none(x[0] * k) for x in seams],
                    "seam_gap_mm": [_none(x[1] * k) for x in seams],
                    "ruling_angle_deg": _max(s.ruling_angle),
                    "side_ratio": _max(s.side_ratio),
                    "width_mm": s.width * k, "area_m2": area * k * k * 1e-6,
                    "area_ratio": area / s.net_area}
    rows = list(per.values())
    width = float(np.mean([s.width for s in measures])) * k
    for key in ("deviation_mm", "planarity_mm", "ruling_angle_deg", "side_ratio"):
        worst[f"max_{key}"] = _max([r[key] for r in rows])
    worst["max_end_gap_mm"] = _max([abs(g) for r in rows for g in r["end_gaps_mm"]
                                    if g is not None])
    for key in ("seam_step_mm", "seam_gap_mm"):
        worst[f"max_{key}"] = _none(_max([x for r in rows for x in r[key] if x is not None]))
    area = float(sum(r["area_m2"] for r in rows))
    reference = (outline_area * k * k * 1e-6 if part_areas and outline_area
                 else float(sum(s.net_area for s in measures)) * k * k * 1e-6)
    return {"mean_width_mm": width, **worst,
            "max_deviation_relative": worst["max_deviation_mm"] / width,
            "max_seam_step_relative": (None if worst["max_seam_step_mm"] is None
                                       else worst["max_seam_step_mm"] / width),
            "max_planarity_relative": worst["max_planarity_mm"] / width,
            "area_m2": area, "reference_area_m2": reference,
            "area_reference": "outline" if part_areas and outline_area else "net",
            "area_ratio": area / reference if reference > 0 else None,
            "per_strip": per}


def _signed_worst(x: np.ndarray):
    """The value of largest magnitude among ``x`` (NaN ignored), or None."""
    x = np.asarray(x, float)
    x = x[~np.isnan(x)]
    return float(x[np.argmax(np.abs(x))]) if x.size else None


def _scaled(x, k: float):
    return None if x is None else x * k


def _none(x):
    """A float, or None for NaN (JSON null)."""
    return None if x is None or not np.isfinite(x) else float(x)
