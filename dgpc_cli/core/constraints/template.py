"""One flat template shared by S planar-quad strips (paper §6.2.4, Fig. 18: "congruent bendable
strips"): the terms of the template fit of ``planarize-strips`` (SPEC §6).

The variables (:class:`StripSetLayout`) are the 3-D vertices of S strips of m rows, one auxiliary
normal per strip quad (planarity stays quadratic, as in :mod:`.planarity`), and the 2-D vertices
``a_u, b_u`` of the template shared by all strips. Vertex ``(u, c)`` of the 3-D grid is row u of
column c, with strip s occupying the columns ``2s`` (A, on its geodesic v) and ``2s + 1`` (B, on
v + 1); its quads are ``(u, 2s), (u+1, 2s), (u+1, 2s+1), (u, 2s+1)``. The layout offers the
interface of :class:`.planarity.QuadGridLayout` (``vid``, ``corners``, ``f_cols``, ``n_cols``,
``split``, ``size``), so the planarity, lateral, slide-fairness, surface-closeness and anchor
terms apply to it unchanged.

Terms of its own (``term(x, layout, ...) -> (phi, J)``, value-independent COO patterns):

* template isometry: ``½(‖p_i − p_j‖² − ‖t_i − t_j‖²)`` for the two geodesic edges, the ruling
  and both diagonals of every quad of every strip against the same pair of the template: every
  strip quad is congruent to the template quad (six distances fix four points up to a rigid
  motion, a planar quad's distances force a planar quad);
* template gauge: ``a_0 = (0, 0)``, ``b_0`` on the x-axis (the template's rigid motions);
* ruling fairness: second differences along u of the ruling vectors ``B_u − A_u`` (rulings
  that turn smoothly: score lines that do not zigzag);
* seam: ``⟨d, X − foot⟩`` of every vertex X of one strip's copy of a shared geodesic from its
  foot on the neighbour's copy (segment and fraction held for a round), along the net's
  normal and across in the tangent plane: the seam step and gap of the fabrication metrics,
  each copy on the other;
* template order and ruling turn (slack form of inequalities): no folded template quad, and
  neighbouring rulings within an angle;
* template outline (variant shared outline, one development per strip): every development's
  boundary vertices on the two shared outline curves, the end edges shared.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


@dataclass(frozen=True)
class StripSetLayout:
    """Variables of S strips of m rows sharing one template:
    ``x = [p (3 · m · 2S), n (3 · (m−1) S), t (2 · 2m · D), c (2 (d+1)), σ (3 (m−1) D)]``
    (see the module).

    ``outline_degree`` d = 0: the variant *shared vertices*, one template (D = 1) whose
    vertices every strip shares. d > 0: the variant *shared outline*, one development per strip
    (D = S, each in the template's frame) whose boundary vertices lie on the two shared
    outline curves ``x = Σ_k c_(j,k) T_k(ŷ)`` (Chebyshev polynomials of degree d in the
    normalized y, :func:`template_outline`): each strip its own rulings on one outline."""

    m: int
    S: int
    outline_degree: int = 0
    vid: np.ndarray = field(init=False, repr=False)
    corners: np.ndarray = field(init=False, repr=False)
    pairs: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        if self.m < 2 or self.S < 1:
            raise ValueError(f"a strip set needs 2 rows and 1 strip, got {self.m}×{self.S}")
        vid = np.arange(self.m * self.k).reshape(self.m, self.k)
        a, b = vid[:, 0::2], vid[:, 1::2]                                   # (m, S)
        corners = np.stack([a[:-1], a[1:], b[1:], b[:-1]], axis=-1)        # (m-1, S, 4)
        corners = np.moveaxis(corners, 1, 0).reshape(-1, 4)                 # strip-major
        # template vertex ids (d, u, j) -> 2m d + 2u + j (d the development: 0 when shared);
        # pairs (3-D ids, template ids) per strip
        ta, tb = 2 * np.arange(self.m), 2 * np.arange(self.m) + 1
        t_pairs = np.concatenate([np.stack(p, -1) for p in (
            (ta[:-1], ta[1:]), (tb[:-1], tb[1:]), (ta, tb), (ta[:-1], tb[1:]), (tb[:-1], ta[1:]))])
        p_pairs = np.concatenate([np.stack(p, -1) for p in (
            (a[:-1], a[1:]), (b[:-1], b[1:]), (a, b), (a[:-1], b[1:]), (b[:-1], a[1:]))])
        dev = (np.arange(self.S) if self.outline_degree > 0 else np.zeros(self.S, int))
        t_pairs = (t_pairs[None] + 2 * self.m * dev[:, None, None]).reshape(-1, 2)
        pairs = np.concatenate([np.moveaxis(p_pairs, 1, 0).reshape(-1, 2), t_pairs],
                               axis=1)                                        # (S·(5m−4), 4)
        for name, value in (("vid", vid), ("corners", corners), ("pairs", pairs)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def k(self) -> int:
        return 2 * self.S

    @property
    def n_vertices(self) -> int:
        return self.m * self.k

    @property
    def n_quads(self) -> int:
        return (self.m - 1) * self.S

    @property
    def n_devs(self) -> int:
        """Developments: 1 (shared vertices) or S (shared outline)."""
        return self.S if self.outline_degree > 0 else 1

    @property
    def t_offset(self) -> int:
        return 3 * self.n_vertices + 3 * self.n_quads

    @property
    def c_offset(self) -> int:
        """Columns of the outline coefficients ``c (2, d+1)`` (none when shared)."""
        return self.t_offset + 4 * self.m * self.n_devs

    @property
    def slack_offset(self) -> int:
        """Columns of the slack variables σ of :func:`template_order`, ``3 (m−1) D``."""
        return self.c_offset + (2 * (self.outline_degree + 1) if self.outline_degree > 0 else 0)

    @property
    def turn_offset(self) -> int:
        """Columns of the slack variables of :func:`ruling_turn`, ``2 (m−1) D``."""
        return self.slack_offset + 3 * (self.m - 1) * self.n_devs

    @property
    def size(self) -> int:
        return self.turn_offset + 2 * (self.m - 1) * self.n_devs

    def f_cols(self, vertex_ids) -> np.ndarray:
        """Columns of p_i, shape ``(*vertex_ids.shape, 3)``."""
        return 3 * np.asarray(vertex_ids)[..., None] + np.arange(3)

    def n_cols(self, quad_ids) -> np.ndarray:
        """Columns of n_q, shape ``(*quad_ids.shape, 3)``."""
        return 3 * self.n_vertices + 3 * np.asarray(quad_ids)[..., None] + np.arange(3)

    def t_cols(self, template_ids) -> np.ndarray:
        """Columns of the template vertex t_i (id 2u for a_u, 2u + 1 for b_u), ``(..., 2)``."""
        return self.t_offset + 2 * np.asarray(template_ids)[..., None] + np.arange(2)

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Views ``p (|V|, 3)`` and ``n (|Q|, 3)`` of the variable vector."""
        nv = self.n_vertices
        return x[: 3 * nv].reshape(nv, 3), x[3 * nv: self.t_offset].reshape(-1, 3)

    def template(self, x: np.ndarray) -> np.ndarray:
        """The template ``(m, 2, 2)`` (``[u, 0] = a_u``, ``[u, 1] = b_u``), or with a shared
        outline the developments ``(S, m, 2, 2)``."""
        t = x[self.t_offset:self.c_offset]
        return (t.reshape(self.S, self.m, 2, 2) if self.outline_degree > 0
                else t.reshape(self.m, 2, 2)).copy()

    def coefficients(self, x: np.ndarray) -> np.ndarray:
        """The outline coefficients ``(2, d+1)`` (shared outline only)."""
        return x[self.c_offset:self.slack_offset].reshape(2, -1).copy()

    def strips(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The strips' vertices ``A, B (S, m, 3)``."""
        p = x[: 3 * self.n_vertices].reshape(self.m, self.S, 2, 3)
        return np.moveaxis(p[:, :, 0], 1, 0).copy(), np.moveaxis(p[:, :, 1], 1, 0).copy()

    def pack(self, A: np.ndarray, B: np.ndarray, template: np.ndarray,
             coefficients: np.ndarray | None = None) -> np.ndarray:
        """Variable vector from strips ``A, B (S, m, 3)``, a template ``(m, 2, 2)`` (or the
        developments ``(S, m, 2, 2)`` and outline ``coefficients (2, d+1)``); n_q the unit
        normal of the diagonals' cross product (+z for a degenerate quad); σ zero."""
        p = np.stack([np.moveaxis(np.asarray(A, float), 0, 1),
                      np.moveaxis(np.asarray(B, float), 0, 1)], axis=2).reshape(-1, 3)
        c = p[self.corners]
        n = np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])
        norm = np.linalg.norm(n, axis=1, keepdims=True)
        n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), [0.0, 0.0, 1.0])
        c = (np.asarray(coefficients, float).ravel() if self.outline_degree > 0
             else np.zeros(0))
        return np.concatenate([p.ravel(), n.ravel(), np.asarray(template, float).ravel(), c,
                               np.zeros(5 * (self.m - 1) * self.n_devs)])


def template_isometry(x, layout: StripSetLayout):
    """Residuals ``½(‖p_i − p_j‖² − ‖t_k − t_l‖²)`` (one per edge, ruling and diagonal of every
    strip quad) against the template's same pair. Quadratic, so the Jacobian is exact."""
    p, _ = layout.split(x)
    t = x[layout.t_offset:layout.c_offset].reshape(-1, 2)
    i, j, k, l = layout.pairs.T  # noqa: E741 - vertex indices
    dp = p[i] - p[j]
    dt = t[k] - t[l]
    phi = 0.5 * (np.einsum("ij,ij->i", dp, dp) - np.einsum("ij,ij->i", dt, dt))
    rows = np.arange(phi.size)[:, None]
    J = jacobian(phi.size, layout.size,
                 (rows, layout.f_cols(i), dp), (rows, layout.f_cols(j), -dp),
                 (rows, layout.t_cols(k), -dt), (rows, layout.t_cols(l), dt))
    return phi, J


def template_gauge(x, layout: StripSetLayout):
    """Residuals ``a_0 = (0, 0)`` and ``(b_0)_y = 0`` (3): the template's rigid motions fixed."""
    cols = layout.t_offset + np.array([0, 1, 3])
    phi = x[cols].copy()
    return phi, jacobian(3, layout.size, (np.arange(3), cols, 1.0))


def ruling_fairness(x, layout: StripSetLayout):
    """Residuals ``r_(u−1) − 2 r_u + r_(u+1)`` (xyz, every inner row of every strip) of the
    ruling vectors ``r_u = B_u − A_u``. Linear."""
    p, _ = layout.split(x)
    a, b = layout.vid[:, 0::2], layout.vid[:, 1::2]                        # (m, S)
    r = p[b] - p[a]
    phi = (r[:-2] - 2.0 * r[1:-1] + r[2:]).ravel()
    rows = np.arange(phi.size).reshape(-1, 3)
    blocks = []
    for lo, w in ((0, 1.0), (1, -2.0), (2, 1.0)):
        sl = slice(lo, layout.m - 2 + lo)
        blocks += [(rows, layout.f_cols(b[sl].ravel()), w),
                   (rows, layout.f_cols(a[sl].ravel()), -w)]
    return phi, jacobian(phi.size, layout.size, *blocks)


def seam(x, layout: StripSetLayout, ids, ends, fractions, directions):
    """Residuals ``⟨d_k, p_(i_k) − (1 − τ_k) p_(j_k) − τ_k p_(l_k)⟩`` (1 per row) of the
    vertices ``ids (k,)`` from the points at the ``fractions τ (k,)`` of the segments ``ends (k,
    2)`` = ``(j, l)`` (a neighbour's copy of the shared geodesic), along the unit ``directions
    (k, 3)``: with the net's normal the seam step of
    :func:`~dgpc_cli.strips.fabrication.seam_offsets`, across the segment in the tangent plane
    its gap, each with its foot (segment and fraction) held. Linear."""
    p, _ = layout.split(x)
    ids, ends = np.asarray(ids), np.asarray(ends)
    tau = np.asarray(fractions, dtype=float)[:, None]
    n = np.asarray(directions, dtype=float).reshape(-1, 3)
    foot = (1.0 - tau) * p[ends[:, 0]] + tau * p[ends[:, 1]]
    phi = np.einsum("kj,kj->k", p[ids] - foot, n)
    rows = np.arange(phi.size)[:, None]
    return phi, jacobian(phi.size, layout.size, (rows, layout.f_cols(ids), n),
                         (rows, layout.f_cols(ends[:, 0]), -(1.0 - tau) * n),
                         (rows, layout.f_cols(ends[:, 1]), -tau * n))


def strip_quad_samples(layout: StripSetLayout, k: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Sample points of every strip quad as affine combinations of its corners: the ``k × k``
    points of its bilinear patch. Vertex ids ``(Q k², 4)`` and coefficients ``(Q k², 4)``."""
    s = np.linspace(0.0, 1.0, k)
    su, sv = (g.ravel() for g in np.meshgrid(s, s, indexing="ij"))
    w = np.stack([(1 - su) * (1 - sv), su * (1 - sv), su * sv, (1 - su) * sv], axis=-1)
    ids = np.repeat(layout.corners, k * k, axis=0)
    return ids, np.tile(w, (layout.n_quads, 1))


def plane_offsets(x, layout: StripSetLayout, samples, points, normals):
    """Residuals ``⟨n_k, Σ_j c_kj p_j − q_k⟩`` (1 per sample) of the points ``samples = (ids
    (K, c), coefficients (K, c))`` (affine combinations of vertices, e.g. ruling midpoints)
    from the planes through ``points (K, 3)`` with the unit ``normals (K, 3)``: the offset of
    a point from a fixed tangent plane of the net (§5.1's point-to-plane distance with the
    foot held). Linear."""
    p, _ = layout.split(x)
    ids, coefficients = (np.asarray(a) for a in samples)
    n = np.asarray(normals, dtype=float)
    s = np.einsum("kc,kcj->kj", coefficients, p[ids])
    phi = np.einsum("kj,kj->k", s - np.asarray(points, dtype=float), n)
    rows = np.arange(phi.size)[:, None, None]
    return phi, jacobian(phi.size, layout.size,
                         (rows, layout.f_cols(ids), coefficients[:, :, None] * n[:, None, :]))



def template_order(x, layout: StripSetLayout, direction, sign, step, area):
    """Residuals ``g − ε − σ²`` (Tang et al. 2014's slack form of ``g ≥ ε``, 3 per quad of
    every development): both boundary steps run forward, ``⟨a_(u+1) − a_u, e⟩ ≥ step`` and the
    same for b, along the fixed unit ``direction`` e; and the quad keeps its turn, ``sign ·
    (d₁ × d₂) ≥ area`` with the diagonals ``d₁ = b_(u+1) − a_u``, ``d₂ = a_(u+1) − b_u``: no two
    rulings cross (no folded quad). Quadratic."""
    m, D = layout.m, layout.n_devs
    t = x[layout.t_offset:layout.c_offset].reshape(D, m, 2, 2)
    sig = x[layout.slack_offset:layout.turn_offset].reshape(3, D, m - 1)
    e = np.asarray(direction, dtype=float)
    a, b = t[:, :, 0], t[:, :, 1]
    d1, d2 = b[:, 1:] - a[:, :-1], a[:, 1:] - b[:, :-1]
    cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    phi = np.concatenate([(np.diff(a, axis=1) @ e - step - sig[0] ** 2).ravel(),
                          (np.diff(b, axis=1) @ e - step - sig[1] ** 2).ravel(),
                          (sign * cross - area - sig[2] ** 2).ravel()])
    r0, r1, r2 = (np.arange(D * (m - 1)) + k * D * (m - 1) for k in range(3))
    ia = (2 * m * np.arange(D)[:, None] + 2 * np.arange(m - 1)[None]).ravel()  # ids of a_u
    ib = ia + 1
    g1 = sign * np.stack([d2[..., 1], -d2[..., 0]], -1).reshape(-1, 2)   # ∂cross/∂d1
    g2 = sign * np.stack([-d1[..., 1], d1[..., 0]], -1).reshape(-1, 2)   # ∂cross/∂d2
    sc = layout.slack_offset + np.arange(3 * D * (m - 1))
    J = jacobian(phi.size, layout.size,
                 (r0[:, None], layout.t_cols(ia + 2), e), (r0[:, None], layout.t_cols(ia), -e),
                 (r1[:, None], layout.t_cols(ib + 2), e), (r1[:, None], layout.t_cols(ib), -e),
                 (r2[:, None], layout.t_cols(ib + 2), g1), (r2[:, None], layout.t_cols(ia), -g1),
                 (r2[:, None], layout.t_cols(ia + 2), g2), (r2[:, None], layout.t_cols(ib), -g2),
                 (np.concatenate([r0, r1, r2]), sc, -2.0 * sig.ravel()))
    return phi, J


def ruling_turn(x, layout: StripSetLayout, tan_max: float):
    """Residuals ``tan θ · ⟨r_u, r_(u+1)⟩ ∓ r_u × r_(u+1) − σ²`` (2 per pair of neighbouring
    rulings ``r_u = b_u − a_u`` of every development, Tang et al. 2014's slack form of ``g ≥
    0``): both hold exactly when the rulings turn by at most θ (``tan_max`` = tan θ) and keep
    their sense. A planar quad holds both its rulings, so this is also their angle in 3-D: the
    score lines of neighbouring quads stay within θ. Quadratic."""
    m, D = layout.m, layout.n_devs
    t = x[layout.t_offset:layout.c_offset].reshape(D, m, 2, 2)
    sig = x[layout.turn_offset:].reshape(2, D, m - 1)
    r = t[:, :, 1] - t[:, :, 0]                                            # (D, m, 2)
    r0, r1 = r[:, :-1], r[:, 1:]
    dot = np.einsum("dui,dui->du", r0, r1)
    cross = r0[..., 0] * r1[..., 1] - r0[..., 1] * r1[..., 0]
    phi = np.concatenate([(tan_max * dot - cross - sig[0] ** 2).ravel(),
                          (tan_max * dot + cross - sig[1] ** 2).ravel()])
    n = D * (m - 1)
    ia = (2 * m * np.arange(D)[:, None] + 2 * np.arange(m - 1)[None]).ravel()  # ids of a_u
    rr0, rr1 = r0.reshape(-1, 2), r1.reshape(-1, 2)
    dc0 = np.stack([rr1[:, 1], -rr1[:, 0]], -1)                           # ∂cross/∂r_u
    dc1 = np.stack([-rr0[:, 1], rr0[:, 0]], -1)                           # ∂cross/∂r_(u+1)
    blocks = []
    for k, sign in ((0, -1.0), (1, 1.0)):
        rows = (k * n + np.arange(n))[:, None]
        g0, g1 = tan_max * rr1 + sign * dc0, tan_max * rr0 + sign * dc1   # ∂/∂r_u, ∂/∂r_(u+1)
        blocks += [(rows, layout.t_cols(ia + 1), g0), (rows, layout.t_cols(ia), -g0),
                   (rows, layout.t_cols(ia + 3), g1), (rows, layout.t_cols(ia + 2), -g1)]
    blocks.append((np.arange(2 * n), layout.turn_offset + np.arange(2 * n), -2.0 * sig.ravel()))
    return phi, jacobian(phi.size, layout.size, *blocks)


@functools.lru_cache(maxsize=8)
def _chebyshev_derivative(degree: int) -> np.ndarray:
    """``(d+1, d+1)``: column k holds the Chebyshev coefficients of ``T_k'``."""
    from numpy.polynomial import chebyshev

    out = np.stack([np.pad(chebyshev.chebder(np.eye(degree + 1)[k]), (0, 1))
                    for k in range(degree + 1)], axis=1)
    out.setflags(write=False)
    return out


def chebyshev_basis(y, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev polynomials ``T_0 .. T_d`` and their derivatives at ``y (k,)``, each
    ``(k, d+1)``."""
    from numpy.polynomial import chebyshev

    V = chebyshev.chebvander(np.asarray(y, dtype=float), degree)
    return V, V @ _chebyshev_derivative(degree)


def template_outline(x, layout: StripSetLayout, y0: float, h: float):
    """Shared outline (``outline_degree`` d > 0): residuals ``x_(s,u,j) − Σ_k c_(j,k)
    T_k((y_(s,u,j) − y0) / h)`` for every development vertex ``(x, y)`` (strip s, row u,
    boundary j: a or b) on its outline curve, and ``t_(s,r,j) − t_(0,r,j)`` (2-D) for the end
    rows r = 0, m−1 of every strip s ≥ 1: the parts' end edges are shared too, so every strip
    is cut from the same outline between the same ends. Polynomial (exact Jacobian)."""
    m, S, d = layout.m, layout.S, layout.outline_degree
    t = x[layout.t_offset:layout.c_offset].reshape(S, m, 2, 2)
    c = x[layout.c_offset:layout.slack_offset].reshape(2, d + 1)
    yh = (t[..., 1] - y0) / h                                             # (S, m, 2)
    V, dV = chebyshev_basis(yh.ravel(), d)                                 # (S m 2, d+1)
    side = np.tile([0, 1], S * m)
    phi_on = t[..., 0].ravel() - np.einsum("kd,kd->k", V, c[side])
    slope = np.einsum("kd,kd->k", dV, c[side]) / h
    ids = np.arange(S * m * 2)                                             # 2m s + 2u + j
    rows = np.arange(phi_on.size)
    ends = np.array([0, 1, 2 * m - 2, 2 * m - 1])
    later = (2 * m * np.arange(1, S)[:, None] + ends[None]).ravel()        # (4 (S−1),)
    first = np.tile(ends, S - 1)
    phi_end = (x[layout.t_cols(later)] - x[layout.t_cols(first)]).ravel()
    rows_end = phi_on.size + np.arange(phi_end.size).reshape(-1, 2)
    c_cols = layout.c_offset + (d + 1) * side[:, None] + np.arange(d + 1)
    J = jacobian(phi_on.size + phi_end.size, layout.size,
                 (rows, layout.t_cols(ids)[:, 0], 1.0),
                 (rows, layout.t_cols(ids)[:, 1], -slope),
                 (rows[:, None], c_cols, -V),
                 (rows_end, layout.t_cols(later), 1.0),
                 (rows_end, layout.t_cols(first), -1.0))
    return np.concatenate([phi_on, phi_end]), J
