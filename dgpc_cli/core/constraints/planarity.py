"""Planarity of quads and closeness to the original strip, for discrete developable strips
(paper §6.2.4: "we first transform each strip into a discrete developable strip (strip with
*planar* quadrilateral faces)").

The terms live on their own variable vector (:class:`QuadGridLayout`): the vertices of a small
``m × k`` grid of quads (a strip has k = 2) and one auxiliary normal n_q per quad, so that every
constraint stays at most quadratic (Tang et al. 2014, as in paper §5.1):

* planarity: ``⟨n_q, c_(i+1) − c_i⟩ = 0`` for the four edges of quad q and ``⟨n_q, n_q⟩ − 1 = 0``;
* lateral: ``⟨b, p − c⟩ = 0`` with c the vertex's start point on its boundary geodesic and b the
  unit surface direction across the geodesic there: the vertex keeps the strip's width but may
  slide along the geodesic and leave the surface along its normal;
* slide fairness: second differences of the vertices' slides along their curves (no zigzag);
* surface closeness: ``⟨n_k, s_k − π(s_k)⟩`` for sample points ``s_k`` (fixed affine combinations
  of the vertices: corners, edge midpoints, centres of the quads) against their closest points
  π(s_k) on the original strip, whose normal there is n_k (the point-to-plane distance of §5.1).

Both are ``term(x, layout, ...) -> (phi, J)`` with a value-independent COO pattern.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


@dataclass(frozen=True)
class QuadGridLayout:
    """Variables of an ``m × k`` grid of vertices ``p[u, j]`` and one normal per quad.

    Vertex ``(u, j)`` has id ``u * k + j``; quad ``(u, j)`` (id ``u * (k-1) + j``) has the corners
    ``(u, j), (u+1, j), (u+1, j+1), (u, j+1)``. ``x = [p (3 m k), n (3 (m-1)(k-1))]``.
    """

    m: int
    k: int = 2
    vid: np.ndarray = field(init=False, repr=False)
    corners: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        if self.m < 2 or self.k < 2:
            raise ValueError(f"a quad grid needs at least 2×2 vertices, got {self.m}×{self.k}")
        vid = np.arange(self.m * self.k).reshape(self.m, self.k)
        corners = np.stack([vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]], axis=-1)
        for name, value in (("vid", vid), ("corners", corners.reshape(-1, 4))):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def n_vertices(self) -> int:
        return self.m * self.k

    @property
    def n_quads(self) -> int:
        return (self.m - 1) * (self.k - 1)

    @property
    def size(self) -> int:
        return 3 * self.n_vertices + 3 * self.n_quads

    def f_cols(self, vertex_ids) -> np.ndarray:
        """Columns of p_i, shape ``(*vertex_ids.shape, 3)``."""
        return 3 * np.asarray(vertex_ids)[..., None] + np.arange(3)

    def n_cols(self, quad_ids) -> np.ndarray:
        """Columns of n_q, shape ``(*quad_ids.shape, 3)``."""
        return 3 * self.n_vertices + 3 * np.asarray(quad_ids)[..., None] + np.arange(3)

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Views ``p (|V|, 3)`` and ``n (|Q|, 3)`` of the variable vector."""
        nv = self.n_vertices
        return x[: 3 * nv].reshape(nv, 3), x[3 * nv:].reshape(-1, 3)

    def pack(self, p: np.ndarray) -> np.ndarray:
        """Variable vector from vertices ``p (m, k, 3)``; n_q the unit normal of the diagonals'
        cross product (exact for planar quads; +z for a degenerate quad)."""
        p = np.asarray(p, dtype=float).reshape(-1, 3)
        c = p[self.corners]
        n = np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])
        norm = np.linalg.norm(n, axis=1, keepdims=True)
        n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), [0.0, 0.0, 1.0])
        return np.concatenate([p.ravel(), n.ravel()])

    def vertices(self, x: np.ndarray) -> np.ndarray:
        """Vertices as a grid ``(m, k, 3)``."""
        return x[: 3 * self.n_vertices].reshape(self.m, self.k, 3).copy()


def planarity(x, layout: QuadGridLayout):
    """Residuals ``⟨n_q, c_(i+1) − c_i⟩`` (4 per quad, edges in corner order) followed by
    ``⟨n_q, n_q⟩ − 1`` (1 per quad). Bilinear, so the Jacobian is exact."""
    p, n = layout.split(x)
    corners = layout.corners                                      # (Q, 4)
    a, b = corners, np.roll(corners, -1, axis=1)                  # edge c_i -> c_(i+1)
    edge = p[b] - p[a]                                            # (Q, 4, 3)
    q = np.arange(layout.n_quads)
    phi_edge = np.einsum("qij,qj->qi", edge, n)                   # (Q, 4)
    phi_unit = np.einsum("qj,qj->q", n, n) - 1.0
    phi = np.concatenate([phi_edge.ravel(), phi_unit])
    rows_edge = np.arange(4 * layout.n_quads).reshape(-1, 4)[..., None]     # (Q, 4, 1)
    rows_unit = 4 * layout.n_quads + q[:, None]                             # (Q, 1)
    nq = n[:, None, :]
    J = jacobian(phi.size, layout.size,
                 (rows_edge, layout.n_cols(q)[:, None, :], edge),
                 (rows_edge, layout.f_cols(b), nq),
                 (rows_edge, layout.f_cols(a), -nq),
                 (rows_unit, layout.n_cols(q), 2.0 * n))
    return phi, J


def lateral(x, layout: QuadGridLayout, points, directions, vertex_ids=None):
    """Residuals ``⟨d_k, p_k − c_k⟩`` (1 per row) for the vertices ``vertex_ids`` (default: all,
    in id order) against the start points ``points (k, 3)`` along the unit ``directions
    (k, 3)``. With d = b (across the geodesic) the vertex keeps its side of the strip; with
    d = t (along it) it cannot slide. Linear in x."""
    p, _ = layout.split(x)
    ids = layout.vid.ravel() if vertex_ids is None else np.asarray(vertex_ids)
    d = np.asarray(directions, dtype=float).reshape(-1, 3)
    phi = np.einsum("kj,kj->k", p[ids] - np.asarray(points, dtype=float).reshape(-1, 3), d)
    rows = np.arange(phi.size)[:, None]
    return phi, jacobian(phi.size, layout.size, (rows, layout.f_cols(ids), d))


def slide_fairness(x, layout: QuadGridLayout, points, tangents):
    """Residuals ``s_(u−1) − 2 s_u + s_(u+1)`` (1 per inner vertex of every grid column) of the
    slides ``s = ⟨t, p − c⟩`` of the vertices along their curves, from the start points
    ``points (m, k, 3)`` along the unit ``tangents (m, k, 3)``: the rulings may shift along the
    strip together but not zigzag (a zigzag turns quads into near-triangles, which are planar
    and hug the surface, and folds the strip). Linear in x."""
    p, _ = layout.split(x)
    c = np.asarray(points, dtype=float).reshape(layout.m, layout.k, 3)
    t = np.asarray(tangents, dtype=float).reshape(layout.m, layout.k, 3)
    slide = np.einsum("ukj,ukj->uk", p[layout.vid] - c, t)
    phi = (slide[:-2] - 2.0 * slide[1:-1] + slide[2:]).ravel()
    rows = np.arange(phi.size)[:, None]
    blocks = [(rows, layout.f_cols(layout.vid[a:layout.m - 2 + a].ravel()),
               w * t[a:layout.m - 2 + a].reshape(-1, 3))
              for a, w in ((0, 1.0), (1, -2.0), (2, 1.0))]
    return phi, jacobian(phi.size, layout.size, *blocks)


def quad_samples(layout: QuadGridLayout) -> tuple[np.ndarray, np.ndarray]:
    """Sample points of the quads as affine combinations of the vertices: every vertex, the
    midpoint of every edge and the centre of every quad (the 3 × 3 samples of each quad's
    bilinear patch, each taken once). Returns vertex ids ``(K, 4)`` and coefficients
    ``(K, 4)`` (unused slots have coefficient 0)."""
    vid = layout.vid
    groups = (([vid], 1.0), ([vid[:, :-1], vid[:, 1:]], 0.5), ([vid[:-1], vid[1:]], 0.5),
              ([layout.corners[:, i] for i in range(4)], 0.25))
    ids, coefficients = [], []
    for members, c in groups:
        cols = [np.ravel(a) for a in members]
        used = len(cols)
        ids.append(np.stack(cols + [cols[0]] * (4 - used), axis=-1))
        coefficients.append(np.broadcast_to([c] * used + [0.0] * (4 - used), (cols[0].size, 4)))
    return np.concatenate(ids), np.concatenate(coefficients)


def surface_closeness(x, layout: QuadGridLayout, reference, samples):
    """Residuals ``⟨n_k, s_k − π(s_k)⟩`` (1 per sample) of the sample points ``s_k = Σ c_kj p_j``
    (``samples = (ids, coefficients)`` of :func:`quad_samples`) against their closest points on
    ``reference`` (a :class:`dgpc_cli.core.reference.ReferenceSurface`; recomputed at every x,
    held fixed in the Jacobian, as in the approximation term of §5.1)."""
    p, _ = layout.split(x)
    ids, coefficients = samples
    s = np.einsum("kc,kcj->kj", coefficients, p[ids])
    foot, n = reference.closest(s)
    phi = np.einsum("kj,kj->k", s - foot, n)
    rows = np.arange(phi.size)[:, None, None]
    return phi, jacobian(phi.size, layout.size,
                         (rows, layout.f_cols(ids), coefficients[:, :, None] * n[:, None, :]))


def anchor(x, layout: QuadGridLayout, targets):
    """Residuals ``p − p⁰`` (3 per vertex) against the start positions ``targets (m, k, 3)``:
    with a weight that fades out (e.g. 0.01 → 0) it keeps the first steps from sliding the
    vertices past each other along their curves."""
    p, _ = layout.split(x)
    phi = (p - np.asarray(targets, dtype=float).reshape(-1, 3)).ravel()
    rows = np.arange(phi.size)
    cols = layout.f_cols(layout.vid.ravel()).ravel()
    return phi, jacobian(phi.size, layout.size, (rows, cols, 1.0))
