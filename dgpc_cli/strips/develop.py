"""Development of a planar-quad strip into the plane (paper §6.2.4, Fig. 18 bottom-left).

The strip ``A_u, B_u (m, 3)`` (rulings ``A_u B_u``) is a triangle strip A_0 B_0 A_1 B_1 … cut by
the diagonals ``A_(u+1) B_u``. Each quad is laid out in its own frame from its five lengths (the
rulings, the two geodesic edges and that diagonal): ``A_u = (0, 0)``, ``B_u = (|A_u B_u|, 0)``,
``A_(u+1)`` and ``B_(u+1)`` on the sides of the ruling and of the diagonal that the 3-D quad
puts them on (seen along the quad's normal, so non-convex quads unfold correctly too). The
frames are then chained by cumulative rigid motions (angles and offsets summed with cumsum), so
the development is vectorized although unfolding is sequential. For planar quads it is exact:
every edge and both diagonals keep their lengths; the second diagonal's change measures what
non-planarity is left.

The result is oriented as the strip seen from the side its normal N = T^u × T^v points to: the
geodesics run along +x (u increasing), the rulings from A to B towards +y, and it is placed with
the first ruling's midpoint at the origin and the chord of the mid-curve along +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Development:
    """A developed strip: 2-D vertices ``A, B (m, 2)`` and its measures.

    ``strain`` is the largest relative length change ``|ℓ₂ − ℓ₃| / ℓ₃`` over the edges and both
    diagonals of every quad; ``straightness (2,)`` the largest distance of each developed
    boundary geodesic from its chord over the geodesic's length; ``length`` the mean length of
    the two geodesics. ``edges``, when given, are the cut edges along the two geodesics (a
    shared-outline template's curves, :mod:`dgpc_cli.strips.cut_edges`) from A_0 to A_(m−1)
    and B_0 to B_(m−1); else the part is cut along A and B.
    """

    A: np.ndarray
    B: np.ndarray
    strain: float
    straightness: np.ndarray
    length: float
    edges: tuple | None = None

    @property
    def cut_edges(self) -> tuple[np.ndarray, np.ndarray]:
        """The two edges the part is cut along: ``edges``, else the geodesics A and B."""
        return (self.A, self.B) if self.edges is None else self.edges

    @property
    def outline(self) -> np.ndarray:
        """Closed outline, counter-clockwise: the cut edge along A forwards, then along B
        backwards (``(2m, 2)`` without ``edges``)."""
        a, b = self.cut_edges
        ring = np.concatenate([a, b[::-1]])
        return ring if signed_area(ring) > 0 else ring[::-1]

    @property
    def rulings(self) -> np.ndarray:
        """Interior rulings (score/bend lines) ``(m−2, 2, 2)``: segments A_u → B_u, 0 < u < m−1."""
        return np.stack([self.A[1:-1], self.B[1:-1]], axis=1)

    @property
    def label_point(self) -> np.ndarray:
        """A point inside the part for its label: the centroid of the middle quad."""
        u = (self.A.shape[0] - 2) // 2
        return 0.25 * (self.A[u] + self.A[u + 1] + self.B[u] + self.B[u + 1])


def signed_area(ring: np.ndarray) -> float:
    """Signed area of a closed polygon ``(k, 2)`` (shoelace; > 0 counter-clockwise)."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _apex(base_a, base_b, to_a, to_b, side):
    """Third points of triangles with base ``base_a → base_b (k, 2)`` and side lengths
    ``to_a, to_b (k,)``, on the left (``side`` = +1) or right (−1) of the base. A violated
    triangle inequality puts the point on the base line (the gap shows up as strain)."""
    e = base_b - base_a
    ell = np.linalg.norm(e, axis=-1)
    ex = e / ell[:, None]
    ey = np.stack([-ex[:, 1], ex[:, 0]], axis=-1)
    xi = (to_a**2 - to_b**2 + ell**2) / (2 * ell)
    eta = np.sqrt(np.maximum(to_a**2 - xi**2, 0.0))
    return base_a + xi[:, None] * ex + (side * eta)[:, None] * ey


def _rotate(angle, vec):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * vec[..., 0] - s * vec[..., 1], s * vec[..., 0] + c * vec[..., 1]], -1)


def develop_strip(A3: np.ndarray, B3: np.ndarray) -> Development:
    """Develop the planar-quad strip ``A3, B3 (m, 3)`` into the plane (see the module)."""
    A3, B3 = np.asarray(A3, float), np.asarray(B3, float)
    m = A3.shape[0]
    L = np.linalg.norm(B3 - A3, axis=-1)                          # rulings (m,)
    d_aa = np.linalg.norm(A3[1:] - A3[:-1], axis=-1)
    d_bb = np.linalg.norm(B3[1:] - B3[:-1], axis=-1)
    d_ab = np.linalg.norm(A3[1:] - B3[:-1], axis=-1)              # cut diagonal B_u A_(u+1)
    k = m - 1
    # Sides from the 3-D quads: n_q = d1 × d2 of the diagonals is the oriented normal (twice the
    # vector area, valid for non-convex quads too), and the local frame below has +z = n_q.
    n_q = np.cross(B3[1:] - A3[:-1], B3[:-1] - A3[1:])
    side_a = np.sign(np.einsum("ui,ui->u", np.cross(B3[:-1] - A3[:-1], A3[1:] - A3[:-1]), n_q))
    side_b = np.sign(np.einsum("ui,ui->u", np.cross(B3[:-1] - A3[1:], B3[1:] - A3[1:]), n_q))
    # Local frame of quad u: A_u = 0, B_u = (L_u, 0); rulings along +x, u along −y, which is the
    # orientation of (T^u, T^v) seen from the side n_q points to.
    origin = np.zeros((k, 2))
    b_loc = np.stack([L[:-1], np.zeros(k)], axis=-1)
    a_next = _apex(origin, b_loc, d_aa, d_ab, np.where(side_a == 0, -1.0, side_a))
    b_next = _apex(a_next, b_loc, L[1:], d_bb, np.where(side_b == 0, -1.0, side_b))
    step = b_next - a_next
    phi = np.arctan2(step[:, 1], step[:, 0])
    theta = np.concatenate([[0.0], np.cumsum(phi)])               # frame angles (m,)
    t = np.concatenate([np.zeros((1, 2)), np.cumsum(_rotate(theta[:-1], a_next), axis=0)])
    A = t
    B = t + L[:, None] * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    A, B = _place(A, B)
    return Development(A=A, B=B, strain=_strain(A, B, A3, B3),
                       straightness=np.array([straightness(A), straightness(B)]),
                       length=0.5 * float(d_aa.sum() + d_bb.sum()))


def _place(A, B):
    """Canonical placement: first ruling's midpoint at the origin, mid-curve chord along +x."""
    mid = 0.5 * (A + B)
    chord = mid[-1] - mid[0]
    ang = -np.arctan2(chord[1], chord[0])
    return _rotate(ang, A - mid[0]), _rotate(ang, B - mid[0])


def _lengths(A, B):
    return np.concatenate([np.linalg.norm(B - A, axis=-1),
                           np.linalg.norm(np.diff(A, axis=0), axis=-1),
                           np.linalg.norm(np.diff(B, axis=0), axis=-1),
                           np.linalg.norm(A[1:] - B[:-1], axis=-1),
                           np.linalg.norm(B[1:] - A[:-1], axis=-1)])


def _strain(A, B, A3, B3) -> float:
    l3 = _lengths(A3, B3)
    l2 = _lengths(A, B)
    return float(np.max(np.abs(l2 - l3) / np.maximum(l3, np.finfo(float).tiny)))


def straightness(X: np.ndarray) -> float:
    """Largest distance of the polyline ``X (m, 2)`` from its chord, over its length."""
    chord = X[-1] - X[0]
    c = np.linalg.norm(chord)
    rel = X - X[0]
    dist = np.abs(chord[0] * rel[:, 1] - chord[1] * rel[:, 0]) / c
    return float(dist.max() / np.linalg.norm(np.diff(X, axis=0), axis=-1).sum())
