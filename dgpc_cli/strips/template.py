"""One cutting template for all strips of a net isometric to a surface of revolution (paper
§6.2.4, Fig. 18; SPEC §6 planarize-strips).

Such a net's strips between neighbouring geodesics are intrinsically one strip (equation (5)
with equal strip widths (7)), so they can all be cut from one flat template and bent into
place. The fit (:func:`fit_template`) solves, by guided projection, for one flat template (its
2-D vertices ``a_u, b_u``, shared) and every strip's 3-D vertices at once:

* hard: every strip quad congruent to the template quad (edges, ruling and both diagonals,
  :func:`~dgpc_cli.core.constraints.template.template_isometry`), planar, its boundary vertices
  on their net geodesic (no move across it), the end rulings on the net's end v-edges (the parts
  cover the design edge to edge), the template's rigid motions fixed, its quads not folded and
  neighbouring rulings within 20° (:func:`~dgpc_cli.core.constraints.template.ruling_turn`);
* soft: the strips' quads (3 × 3 samples of each) close to the net (point-to-plane, §5.1),
  the boundary vertices on their geodesic (across it and along the net's normal), and the
  seams: every vertex of a strip's copy of a shared geodesic on its neighbour's copy, along the
  normal and across it (:func:`~dgpc_cli.core.constraints.template.seam`: the seam step and
  gap that :mod:`~dgpc_cli.strips.fabrication` measures, its feet re-taken every round);
* regularizers: fairness of the ruling vectors and of the vertices' slides along the geodesics,
  and a proximal term on the slides within a round.

One :class:`TemplateProblem` holds what every start shares (scaled net, reference surface,
samples, end edges, weights, the solver's workspace). A fit starts from planar strips (the
per-strip ones, ends on the end v-edges, or the net's own) and a template averaged from their
developments, and runs a few rounds of guided projection, the frames of the soft terms taken
anew and their weights lowered tenfold each round (a penalty method whose last round ends on
the hard terms close to the best fit; one projection onto the hard terms alone, the least
change, if it did not reach the tolerance). Afterwards every strip is rebuilt from the
template quad by quad (:func:`bend_template`): quad 0 placed by Kabsch onto the fitted quad,
each next quad turned about the ruling it shares with the previous one to its best angle. The
rebuilt strips are exact isometric bendings of the template: congruent and planar to
round-off.

Variant ``shared-vertices``: the template's vertices, hence its rulings (score lines), are the
same on every strip. Variant ``shared-outline``: every strip has its own development (its own
score lines) whose boundary vertices lie on two outline curves shared by all strips (Chebyshev
polynomials of low degree in the template's frame), with the end edges shared: one outline to
cut, each copy scored for its own bending. Its strips' polylines would differ by the curves'
sag between neighbouring vertices, so the fit returns the curves too
(:attr:`TemplateFit.outline`) and every strip is cut along them, sampled at the same points
(:mod:`dgpc_cli.strips.cut_edges`).
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass

import numpy as np

from dgpc_cli.core.constraints.planarity import lateral, planarity, slide_fairness
from dgpc_cli.core.constraints.template import (
    StripSetLayout,
    chebyshev_basis,
    plane_offsets,
    ruling_fairness,
    ruling_turn,
    seam,
    strip_quad_samples,
    template_gauge,
    template_isometry,
    template_order,
    template_outline,
)
from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.core.solver import Schedule, Term, guided_projection
from dgpc_cli.metrics.frames import unit
from dgpc_cli.strips.congruence import kabsch
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.quality import patch_mesh

log = logging.getLogger(__name__)

#: The variants of the fit (see the module).
VARIANTS = ("shared-vertices", "shared-outline")
#: The outline polynomials' y range is the start template's times this (room to move).
OUTLINE_MARGIN = 1.1
#: Lowest degree of the Chebyshev polynomials of the shared outline's two curves; higher (up
#: to m − 1, :func:`outline_degree`) until the curves hold the net's own developed strip within
#: OUTLINE_TOL of its width (a bowling pin's meridian strips, whose width changes fourfold with
#: a neck between, need degree 18 at 21 rows: degree 6 leaves 3.9 % of the width).
OUTLINE_DEGREE = 6
OUTLINE_TOL = 1e-3
#: Weights of the soft terms and regularizers in the first round (the hard terms have weight
#: 1): closeness of the strips to the net, the boundary vertices' distance across their net
#: geodesic and along the net's normal (the common target of both copies of a seam: the
#: boundaries stay on the surface rather than where the strip's middle would pull them), their
#: slide along it within a round (a proximal term: sliding is free for the closeness), the
#: fairness of the slides.
WEIGHTS = {"closeness": 1e-3, "across": 1e-3, "normal": 1e-2, "slide": 1e-5,
           "slide_fairness": 1e-8, "max_ruling_turn": 20.0}
#: The default largest turn between neighbouring rulings, degrees.
MAX_RULING_TURN = WEIGHTS["max_ruling_turn"]
#: (``max_ruling_turn``: not a weight, the largest angle in degrees between neighbouring
#: rulings, a hard bound: :func:`~dgpc_cli.core.constraints.template.ruling_turn`.)
#: Weight of the fairness of the ruling vectors.
RULING_FAIRNESS = 1e-7
#: Factors of the soft weights, one per round.
ROUND_FACTORS = (1.0, 0.1, 0.01, 1e-3)
#: The template's boundary steps and quad turns stay above this fraction of their mean (no
#: folded quad, no crossing rulings).
ORDER_MARGIN = 0.2
#: Default weight of the seam term (each copy of a shared geodesic on the other, along the
#: normal and across; lowered over the rounds with the other soft terms): see the README's
#: trade-off table.
SEAM_WEIGHT = 2e-2
#: Tolerance (hard residual at mean edge length 1) and iteration limit of the fit.
FIT_TOL = 1e-10
FIT_ROUNDS = 4
ROUND_MAX_ITER = 30
#: Rounds stop once their objective fell by less than 0.1 % over this many iterations.
ROUND_STAGNATION = 10
PROJECTION_MAX_ITER = 30


@dataclass
class TemplateFit:
    """The fitted strips ``A, B (S, m, 3)`` (rebuilt from the template: exact bendings), the
    template ``(m, 2, 2)`` (``[u, 0] = a_u``, ``[u, 1] = b_u``), the variant and the solver's
    outcome; with a shared outline ``developments (S, m, 2, 2)``, every strip's own (its
    vertices on the template's outline), the template being the first one's."""

    A: np.ndarray
    B: np.ndarray
    template: np.ndarray
    variant: str
    status: str
    iterations: int
    R: float
    developments: np.ndarray | None = None
    #: With a shared outline its two curves in the developments' frame: ``(y0, h, c (2, d+1))``,
    #: curve j (0: side A, 1: side B) ``x = Σ_k c_(j,k) T_k((y − y0) / h)``.
    outline: tuple | None = None


def closest_on_polylines(X: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """For points ``X (S, k, 3)`` their closest points on the polylines ``P (S, m, 3)``, the
    unit segment tangents there and the parameters (segment index + fraction), each over
    ``(S, k)``."""
    a, b = P[:, None, :-1], P[:, None, 1:]                       # (S, 1, m-1, 3)
    e = b - a
    t = np.clip(np.einsum("skmj,skmj->skm", X[:, :, None] - a, e)
                / np.einsum("skmj,skmj->skm", e, e), 0.0, 1.0)   # (S, k, m-1)
    foot = a + t[..., None] * e
    dist = np.linalg.norm(X[:, :, None] - foot, axis=-1)
    seg = np.argmin(dist, axis=-1)
    pick = seg[..., None]
    c = np.take_along_axis(foot, pick[..., None], 2)[:, :, 0]
    tangent = unit(np.take_along_axis(np.broadcast_to(e, foot.shape), pick[..., None], 2)[:, :, 0])
    return c, tangent, seg + np.take_along_axis(t, pick, 2)[..., 0]


def start_developments(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The developments ``(S, m, 2, 2)`` of planar strips ``A, B (S, m, 3)`` aligned onto
    their mean (Kabsch), and that mean, the start template ``(m, 2, 2)``: placed with ``a_0`` at
    the origin and ``b_0`` on the +x axis (the gauge of the fit)."""
    devs = [develop_strip(a, b) for a, b in zip(A, B, strict=True)]
    ref = np.concatenate([devs[0].A, devs[0].B])
    aligned = []
    for d in devs:
        X = np.concatenate([d.A, d.B])
        R, t = kabsch(X, ref, allow_reflection=False)
        aligned.append(X @ R.T + t)
    aligned = np.stack(aligned)                                          # (S, 2m, 2)
    mean = aligned.mean(axis=0)
    m = A.shape[1]
    origin = mean[0]
    ang = np.arctan2(*(mean[m] - origin)[::-1])
    c, s = np.cos(-ang), np.sin(-ang)
    rot = np.array([[c, -s], [s, c]])
    placed = (aligned - origin) @ rot.T
    devs2 = np.stack([placed[:, :m], placed[:, m:]], axis=2)             # (S, m, 2, 2)
    return devs2, devs2.mean(axis=0)


def start_template(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """A template ``(m, 2, 2)`` from planar strips ``A, B (S, m, 3)``: their developments
    aligned onto the first one's (Kabsch) and averaged, placed with ``a_0`` at the origin and
    ``b_0`` on the +x axis (the gauge of the fit)."""
    return start_developments(A, B)[1]


def outline_degree(P: np.ndarray, Q: np.ndarray) -> int:
    """The degree of the shared outline's curves for the net strips ``P, Q (S, m, 3)``: the
    lowest from :data:`OUTLINE_DEGREE` to m − 1 whose two Chebyshev polynomials (``x`` of
    ``y`` in the gauge of the fit, least squares) hold the boundaries of the net's own strip
    developed and averaged (:func:`start_template`, the strip every net strip is intrinsically)
    within :data:`OUTLINE_TOL` of its mean width; m − 1 if none does."""
    m = P.shape[1]
    T = start_template(P, Q)
    y, x = T[..., 1], T[..., 0]
    t = (y - 0.5 * (y.max() + y.min())) / (OUTLINE_MARGIN * 0.5 * float(np.ptp(y)))
    tol = OUTLINE_TOL * float(np.mean(np.linalg.norm(T[:, 1] - T[:, 0], axis=-1)))
    for degree in range(min(OUTLINE_DEGREE, m - 1), m - 1):
        V, _ = chebyshev_basis(t.T.reshape(-1), degree)                  # side a, then side b
        fit = [V[j * m:(j + 1) * m] @ np.linalg.lstsq(V[j * m:(j + 1) * m], x[:, j],
                                                       rcond=None)[0] for j in (0, 1)]
        if max(float(np.abs(fit[j] - x[:, j]).max()) for j in (0, 1)) <= tol:
            return degree
    return m - 1


def _rotate_about(X, origin, axis, angle):
    """Points ``X (S, k, 3)`` turned by ``angle (S,)`` about the lines through ``origin (S, 3)``
    along the unit ``axis (S, 3)`` (Rodrigues)."""
    v = X - origin[:, None]
    k = axis[:, None]
    c, s = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
    return (origin[:, None] + v * c + np.cross(k, v) * s
            + k * np.einsum("skj,skj->sk", k, v)[..., None] * (1 - c))


def bend_template(template: np.ndarray, A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray,
                                                                                np.ndarray]:
    """Exact isometric bendings of the ``template (m, 2, 2)`` (or of one development per strip,
    ``(S, m, 2, 2)``) fitted to the strips ``A, B (S, m, 3)``: quad 0 by Kabsch onto the
    strip's quad 0, then every next template quad attached to the ruling already placed, flat,
    and turned about it to the angle that brings its two far vertices closest to the strip's
    (least squares). Congruent and planar quads to round-off."""
    S, m = A.shape[:2]
    template = np.broadcast_to(template, (S, m, 2, 2))
    T = np.concatenate([template, np.zeros((S, m, 2, 1))], axis=-1)       # (S, m, 2, 3)
    outA, outB = np.empty_like(A), np.empty_like(B)
    motions = []
    for s in range(S):
        X0 = np.concatenate([T[s, :2, 0], T[s, :2, 1]])                   # (4, 3)
        Y0 = np.concatenate([A[s, :2], B[s, :2]])
        motions.append(_kabsch3(X0, Y0))
    Rm = np.stack([r for r, _ in motions])                                 # (S, 3, 3)
    tm = np.stack([t for _, t in motions])                                 # (S, 3)

    def place(points):                                             # (S, k, 3) -> (S, k, 3)
        return np.einsum("sij,skj->ski", Rm, points) + tm[:, None]

    first = place(T[:, :2].reshape(S, -1, 3)).reshape(S, 2, 2, 3)
    outA[:, :2], outB[:, :2] = first[:, :, 0], first[:, :, 1]
    for u in range(1, m - 1):
        flat = place(T[:, u + 1])                                          # (S, 2, 3)
        origin = outA[:, u]
        axis = unit(outB[:, u] - origin)
        x = flat - origin[:, None]
        y = np.stack([A[:, u + 1], B[:, u + 1]], axis=1) - origin[:, None]
        xp = x - np.einsum("skj,sj->sk", x, axis)[..., None] * axis[:, None]
        yp = y - np.einsum("skj,sj->sk", y, axis)[..., None] * axis[:, None]
        angle = np.arctan2(np.einsum("skj,sj->s", np.cross(xp, yp), axis),
                           np.einsum("skj,skj->s", xp, yp))
        turned = _rotate_about(flat, origin, axis, angle)
        outA[:, u + 1], outB[:, u + 1] = turned[:, 0], turned[:, 1]
        c, s_ = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
        K = _cross_matrix(axis)
        rot = np.eye(3) + s_ * K + (1 - c) * (K @ K)                       # (S, 3, 3)
        tm = np.einsum("sij,sj->si", rot, tm - origin) + origin
        Rm = rot @ Rm
    return outA, outB


def _cross_matrix(k):
    z = np.zeros(k.shape[0])
    return np.stack([np.stack([z, -k[:, 2], k[:, 1]], -1), np.stack([k[:, 2], z, -k[:, 0]], -1),
                     np.stack([-k[:, 1], k[:, 0], z], -1)], axis=1)


def _kabsch3(X, Y):
    """The rotation R (det +1) and translation t minimizing ``Σ‖R x + t − y‖²`` in 3-D."""
    cx, cy = X.mean(axis=0), Y.mean(axis=0)
    U, _, Vt = np.linalg.svd((X - cx).T @ (Y - cy))
    d = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
    R = Vt.T @ np.diag([1.0, 1.0, d]) @ U.T
    return R, cy - R @ cx


def _net_surface(f: np.ndarray, columns) -> ReferenceSurface:
    """The strips ``columns`` of the net ``f`` as one triangle mesh (bilinear quads)."""
    Vs, Fs, base = [], [], 0
    for v in columns:
        V, F = patch_mesh(f[:, v], f[:, v + 1])
        Vs.append(V)
        Fs.append(F + base)
        base += len(V)
    return ReferenceSurface(np.concatenate(Vs), np.concatenate(Fs))


def _frames(P, Q, X, is_b):
    """Closest points on the strips' own geodesics, tangents and across-directions for the
    boundary vertices ``X (S, m, 3)`` (``is_b``: on Q, else on P)."""
    c, t, _ = closest_on_polylines(X, Q if is_b else P)
    return c, t, unit(np.cross(_row_normals(P, Q), t))


def _order_bounds(T: np.ndarray):
    """Direction, turn and bounds of :func:`template_order` from a start template ``T (m, 2,
    2)``: along its chord, its prevailing turn, steps and turns at least ORDER_MARGIN of their
    mean."""
    a, b = T[:, 0], T[:, 1]
    e = unit(0.5 * (a[-1] + b[-1] - a[0] - b[0]))
    d1, d2 = b[1:] - a[:-1], a[1:] - b[:-1]
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    sign = 1.0 if cross.sum() >= 0 else -1.0
    step = ORDER_MARGIN * 0.5 * float(np.mean(np.diff(a, axis=0) @ e + np.diff(b, axis=0) @ e))
    return e, sign, step, ORDER_MARGIN * float(np.mean(np.abs(cross)))


def _soft_terms(x, setup: TemplateProblem, factor: float):
    """The soft terms and regularizers, their frames (closest points on the geodesics, tangent
    planes of the net at the samples' feet) taken at ``x``: held fixed for one round. The soft
    weights are scaled by ``factor`` (the rounds lower it: a penalty method whose last round
    is close to the hard constraints)."""
    layout, P, Q, m, S = setup.layout, setup.P, setup.Q, setup.layout.m, setup.layout.S
    A, B = layout.strips(x)
    cA, tA, bA = _frames(P, Q, A, False)
    cB, tB, bB = _frames(P, Q, B, True)

    def grid(a, b):                                   # (S, m, 3) pairs -> (m, 2S, 3)
        return np.stack([np.moveaxis(a, 0, 1), np.moveaxis(b, 0, 1)], axis=2).reshape(m, 2 * S, 3)

    c, t, across = grid(cA, cB), grid(tA, tB), grid(bA, bB)
    p = x[: 3 * layout.n_vertices].reshape(-1, 3)
    samples = setup.samples
    feet, planes = setup.reference.closest(np.einsum("kc,kcj->kj", samples[1], p[samples[0]]))
    w = setup.weights

    def const(v):
        return Schedule.constant(v * factor)

    terms = [
        Term("closeness", lambda x: plane_offsets(x, layout, samples, feet, planes),
             const(w["closeness"]), False),
        Term("across", lambda x: lateral(x, layout, c.reshape(-1, 3), across.reshape(-1, 3)),
             const(w["across"]), False),
        Term("slide", lambda x: lateral(x, layout, c.reshape(-1, 3), t.reshape(-1, 3)),
             const(w["slide"]), False, True),
        Term("ruling_fairness", lambda x: ruling_fairness(x, layout),
             const(w["ruling_fairness"]), False, True),
        Term("slide_fairness", lambda x: slide_fairness(x, layout, c, t),
             const(w["slide_fairness"]), False, True)]
    if w["normal"] > 0:
        normals = grid(*_boundary_normals(setup, A, B)).reshape(-1, 3)
        terms.append(Term("normal", lambda x: lateral(x, layout, c.reshape(-1, 3), normals),
                          const(w["normal"]), False))
    if w["seam"] > 0 and S > 1:
        frames = _seam_frames(setup, A, B)
        terms.append(Term("seam", lambda x: seam(x, layout, *frames), const(w["seam"]),
                          False))
    return terms


def _row_normals(P, Q):
    """Unit normals ``(S, m, 3)`` of the net strips ``P, Q`` at their rows."""
    return unit(np.cross(np.gradient(P, axis=1) + np.gradient(Q, axis=1), Q - P))


def _at_parameters(n, t):
    """The row vectors ``n (S, m, 3)`` interpolated at the parameters ``t (S, k)`` (row index +
    fraction), unit."""
    i = np.clip(np.floor(t).astype(int), 0, n.shape[1] - 2)
    w = (t - i)[..., None]
    return unit((1 - w) * np.take_along_axis(n, i[..., None], 1)
                + w * np.take_along_axis(n, i[..., None] + 1, 1))


def _boundary_normals(setup, A, B):
    """The net's normals at the feet of the boundary vertices ``A, B (S, m, 3)`` on their own
    geodesics, each ``(S, m, 3)``."""
    n = _row_normals(setup.P, setup.Q)
    return [_at_parameters(n, closest_on_polylines(X, G)[2])
            for X, G in ((A, setup.P), (B, setup.Q))]


def _seam_frames(setup, A, B):
    """The frames of :func:`~dgpc_cli.core.constraints.template.seam` at the strips ``A, B (S,
    m, 3)``: every vertex of both copies of a shared geodesic (strip s's B, strip s+1's A), the
    segment of the other copy holding its foot, the fraction there, and twice (a step and a
    gap) a direction: the net's normal at the foot (the mean of both strips') and the one
    across the other copy in the tangent plane."""
    layout = setup.layout
    n = _row_normals(setup.P, setup.Q)
    shared = unit(n[:-1] + n[1:])                                          # (S-1, m, 3)
    on_b, on_a = layout.vid[:, 1:-1:2].T, layout.vid[:, 2::2].T            # (S-1, m)
    ids, ends, fractions, directions = [], [], [], []
    for X, Y, own, other in ((B[:-1], A[1:], on_b, on_a), (A[1:], B[:-1], on_a, on_b)):
        t = closest_on_polylines(X, Y)[2]
        i = np.clip(np.floor(t).astype(int), 0, layout.m - 2)[..., None]
        normal = _at_parameters(shared, t)
        along = np.take_along_axis(Y, i + 1, 1) - np.take_along_axis(Y, i, 1)
        segment = np.stack([np.take_along_axis(other, i[..., 0], 1),
                            np.take_along_axis(other, i[..., 0] + 1, 1)], -1).reshape(-1, 2)
        for d in (normal, unit(np.cross(normal, along))):
            ids.append(own.ravel())
            ends.append(segment)
            fractions.append((t - i[..., 0]).ravel())
            directions.append(d.reshape(-1, 3))
    return tuple(np.concatenate(a) for a in (ids, ends, fractions, directions))


@dataclass
class TemplateProblem:
    """What every start of a template fit shares (see :func:`fit_template`): the net strips
    ``P, Q (S, m, 3)`` scaled to mean edge length 1 about ``center`` (``scale``), the layout,
    the net as a reference surface and the sample points of the closeness, the end v-edges
    and the weights; the solver's workspace (one pattern for every start and round, one
    symbolic factorization, but for the seam term's feet when they move to another segment)."""

    layout: StripSetLayout
    P: np.ndarray
    Q: np.ndarray
    center: np.ndarray
    scale: float
    reference: ReferenceSurface
    samples: tuple
    end_c: np.ndarray
    end_t: np.ndarray
    weights: dict
    variant: str = "shared-vertices"
    workspace: object = None

    def with_variant(self, variant: str) -> TemplateProblem:
        """The same problem for the other ``variant`` (its own layout and workspace)."""
        degree = outline_degree(self.P, self.Q) if variant == "shared-outline" else 0
        return dataclasses.replace(self, variant=variant, workspace=None,
                                   layout=StripSetLayout(self.layout.m, self.layout.S, degree))

    @classmethod
    def build(cls, f: np.ndarray, columns, *, seam_weight: float = SEAM_WEIGHT,
              ruling_fairness: float = RULING_FAIRNESS, variant: str = "shared-vertices",
              **weights) -> TemplateProblem:
        """The problem of the strips ``columns`` of the net ``f (m, n, 3)`` for ``variant``;
        ``weights`` override :data:`WEIGHTS` by name."""
        f = np.asarray(f, dtype=float)
        columns = np.asarray(columns, dtype=int)
        P, Q = np.moveaxis(f[:, columns], 1, 0), np.moveaxis(f[:, columns + 1], 1, 0)
        S, m = P.shape[:2]
        center = f.reshape(-1, 3).mean(axis=0)
        edges = np.concatenate([np.linalg.norm(np.diff(P, axis=1), axis=-1).ravel(),
                                np.linalg.norm(Q - P, axis=-1).ravel()])
        scale = 1.0 / float(np.mean(edges))
        P, Q = (P - center) * scale, (Q - center) * scale
        layout = StripSetLayout(m, S)
        # the end rulings: the net's end v-edges (no slide along the geodesic there)
        end_c = np.stack([np.stack([P[:, r], Q[:, r]], axis=1).reshape(2 * S, 3)
                          for r in (0, -1)])
        tP, tQ = unit(np.gradient(P, axis=1)), unit(np.gradient(Q, axis=1))
        end_t = np.stack([np.stack([tP[:, r], tQ[:, r]], axis=1).reshape(2 * S, 3)
                          for r in (0, -1)])
        w = {**WEIGHTS, "seam": seam_weight, "ruling_fairness": ruling_fairness, **weights}
        problem = cls(layout=layout, P=P, Q=Q, center=center, scale=scale,
                      reference=_net_surface((f - center) * scale, columns),
                      samples=strip_quad_samples(layout), end_c=end_c, end_t=end_t,
                      weights=w)
        return problem if variant == "shared-vertices" else problem.with_variant(variant)

    def hard_terms(self, order, outline, tan_max) -> list[Term]:
        """The hard terms: ``order`` the bounds of :func:`template_order`, ``outline`` the
        ``(y0, h)`` of :func:`template_outline` (None for shared vertices), ``tan_max`` the
        tangent of the largest ruling turn."""
        layout, ends = self.layout, np.r_[self.layout.vid[0], self.layout.vid[-1]]
        end_c, end_t = self.end_c.reshape(-1, 3), self.end_t.reshape(-1, 3)
        one = Schedule.constant(1.0)
        return [
            Term("template_isometry", lambda x: template_isometry(x, layout), one),
            Term("planarity", lambda x: planarity(x, layout), one),
            Term("ends", lambda x: lateral(x, layout, end_c, end_t, ends), one),
            Term("template_gauge", lambda x: template_gauge(x, layout), one),
            Term("template_order", lambda x: template_order(x, layout, *order), one),
            Term("ruling_turn", lambda x: ruling_turn(x, layout, tan_max), one)] + (
            [Term("template_outline", lambda x: template_outline(x, layout, *outline), one)]
            if outline is not None else [])

    def fit(self, A0: np.ndarray, B0: np.ndarray, *, rounds: int = FIT_ROUNDS) -> TemplateFit:
        """One fit from the strips ``A0, B0 (S, m, 3)`` (unscaled)."""
        layout = self.layout
        A, B = (A0 - self.center) * self.scale, (B0 - self.center) * self.scale
        devs, T0 = start_developments(A, B)
        outline = None
        if layout.outline_degree > 0:
            y = T0[..., 1]
            outline = (0.5 * float(y.max() + y.min()), OUTLINE_MARGIN * 0.5 * float(np.ptp(y)))
            V, _ = chebyshev_basis((devs[..., 1].reshape(-1) - outline[0]) / outline[1],
                                   layout.outline_degree)
            side = np.tile([0, 1], devs.shape[0] * devs.shape[1])
            coefficients = np.stack([np.linalg.lstsq(V[side == j], devs[..., 0].reshape(-1)[
                side == j], rcond=None)[0] for j in (0, 1)])
            x = layout.pack(A, B, devs, coefficients)
        else:
            x = layout.pack(A, B, T0)
        order = _order_bounds(T0)
        x[layout.slack_offset:layout.turn_offset] = np.sqrt(np.maximum(
            template_order(x, layout, *order)[0], 0.0))
        tan_max = np.tan(np.radians(self.weights["max_ruling_turn"]))
        x[layout.turn_offset:] = np.sqrt(np.maximum(ruling_turn(x, layout, tan_max)[0], 0.0))
        hard = self.hard_terms(order, outline, tan_max)
        iterations, result = 0, None
        factors = ROUND_FACTORS[:rounds]
        for k, factor in enumerate(factors):
            last = k == len(factors) - 1
            fitted = guided_projection(x, hard + _soft_terms(x, self, factor), tol=FIT_TOL,
                                       max_iter=PROJECTION_MAX_ITER if last else ROUND_MAX_ITER,
                                       stagnation_window=ROUND_STAGNATION,
                                       workspace=self.workspace)
            x, self.workspace = fitted.x, fitted.workspace
            iterations += fitted.iterations
            result = fitted
            log.debug("template fit round %d (soft ×%g): %s, R %.3g", k, factor,
                      fitted.status, fitted.R)
        if result.R > FIT_TOL:
            result = guided_projection(x, hard, tol=FIT_TOL, max_iter=PROJECTION_MAX_ITER)
            iterations += result.iterations
        template = layout.template(result.x)
        A1, B1 = bend_template(template, *layout.strips(result.x))
        s, c = self.scale, self.center
        devs = template if layout.outline_degree > 0 else None
        curves = None if outline is None else (
            outline[0] / s, outline[1] / s,
            result.x[layout.c_offset:layout.slack_offset].reshape(2, -1) / s)
        return TemplateFit(A=A1 / s + c, B=B1 / s + c,
                           template=(template if devs is None else devs[0]) / s,
                           variant=self.variant, status=result.status,
                           iterations=iterations, R=result.R / s,
                           developments=None if devs is None else devs / s,
                           outline=curves)


def fit_template(f: np.ndarray, columns: list[int], A0: np.ndarray, B0: np.ndarray, *,
                 seam_weight: float = SEAM_WEIGHT, ruling_fairness: float = RULING_FAIRNESS,
                 variant: str = "shared-vertices", rounds: int = FIT_ROUNDS) -> TemplateFit:
    """Fit one template to the strips ``columns`` of the net ``f (m, n, 3)``, starting from the
    planar strips ``A0, B0 (S, m, 3)`` (see the module). Returns the rebuilt strips.

    The soft terms' frames follow the strips: ``rounds`` guided projections, each with the
    frames taken where the previous one ended (warm start, the same factorization pattern)
    and the soft weights lowered tenfold (:data:`ROUND_FACTORS`), so the last round ends on
    the hard terms near the best fit; a projection onto the hard terms alone only if it did
    not reach the tolerance."""
    problem = TemplateProblem.build(f, columns, seam_weight=seam_weight,
                                    ruling_fairness=ruling_fairness, variant=variant)
    return problem.fit(A0, B0, rounds=rounds)

