"""The section of a triangle mesh by a plane, as ordered polylines (SPEC §5 base curve).

Every edge whose end points lie strictly on opposite sides of the plane (a signed distance of 0
counts as the positive side) carries one crossing point; every face with two crossing edges
contributes a segment between them. In a manifold mesh each crossing point belongs to at most
two segments, so the segments chain into open or closed polylines, ordered here by a
depth-first traversal of the (path or cycle) graph — no Python loop over segments.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from dgpc_cli.errors import DgpcError


@dataclass(frozen=True)
class SectionCurve:
    """One piece of a plane section.

    ``points (k, 3)`` in order; ``faces (k-1,)`` the mesh face that carries segment
    ``points[i] → points[i+1]``; ``closed`` whether the last point joins the first (then the
    closing segment is included: ``points[-1] == points[0]``).
    """

    points: np.ndarray
    faces: np.ndarray
    closed: bool

    @property
    def arclength(self) -> np.ndarray:
        """Cumulative arc length at the points, ``(k,)``, starting at 0."""
        seg = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        return np.concatenate([[0.0], np.cumsum(seg)])

    @property
    def length(self) -> float:
        return float(self.arclength[-1])


def plane_section(vertices: np.ndarray, faces: np.ndarray, point, normal) -> list[SectionCurve]:
    """Pieces of the section of the mesh ``vertices (k, 3)``, ``faces (t, 3)`` by the plane
    through ``point`` orthogonal to ``normal``, longest first (empty list: no section).

    Raises DgpcError when a crossing point belongs to more than two segments (a non-manifold
    edge on the plane): the section is then not a curve.
    """
    V = np.asarray(vertices, dtype=float)
    F = np.asarray(faces, dtype=np.int64)
    nrm = np.asarray(normal, dtype=float)
    nrm = nrm / np.linalg.norm(nrm)
    d = (V - np.asarray(point, dtype=float)) @ nrm
    pos = d >= 0.0
    # the three edges of every face, keyed by their sorted vertex pair
    he = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 3, 2)
    crossing = pos[he[..., 0]] != pos[he[..., 1]]                     # (t, 3)
    n_cross = crossing.sum(axis=1)
    cut = np.flatnonzero(n_cross == 2)
    if cut.size == 0:
        return []
    key = np.sort(he[cut][crossing[cut]].reshape(-1, 2), axis=1)      # (2c, 2) edges of segments
    edges, node = np.unique(key, axis=0, return_inverse=True)
    node = node.reshape(-1, 2)                                        # segment → two nodes
    a, b = edges[:, 0], edges[:, 1]
    lam = d[a] / (d[a] - d[b])
    xyz = V[a] + lam[:, None] * (V[b] - V[a])                         # crossing points
    k = len(edges)
    degree = np.bincount(node.ravel(), minlength=k)
    if degree.max() > 2:
        raise DgpcError("the plane section is not a simple curve (a non-manifold edge lies on "
                        "the section plane)", source="--direction")
    seg_ids = np.arange(len(cut))
    adj = sparse.coo_matrix((np.ones(2 * len(cut)),
                             (np.concatenate([node[:, 0], node[:, 1]]),
                              np.concatenate([node[:, 1], node[:, 0]]))), shape=(k, k)).tocsr()
    # segment id by node pair, to recover the face of each step along a traversal
    pair = sparse.coo_matrix((seg_ids + 1, (node[:, 0], node[:, 1])), shape=(k, k)).tocsr()
    pair = pair + pair.T
    n_comp, labels = csgraph.connected_components(adj, directed=False)
    pieces = []
    for c in range(n_comp):  # one traversal per piece (a handful)
        members = np.flatnonzero(labels == c)
        ends = members[degree[members] == 1]
        closed = ends.size == 0
        start = int(ends.min()) if ends.size else int(members.min())
        order = csgraph.depth_first_order(adj, start, directed=False,
                                          return_predecessors=False)
        if closed:
            order = np.append(order, start)
        seg = np.asarray(pair[order[:-1], order[1:]]).ravel().astype(np.int64) - 1
        pieces.append(SectionCurve(points=xyz[order], faces=cut[seg],
                                   closed=closed))
    pieces.sort(key=lambda p: -p.length)
    return pieces


def sample_curve(curve: SectionCurve, s: np.ndarray):
    """Points at arc lengths ``s (n,)`` on ``curve``: ``(points (n, 3), faces (n,),
    tangents (n, 3))`` — the face and unit direction of the segment each point lies on."""
    cum = curve.arclength
    s = np.clip(np.asarray(s, dtype=float), 0.0, cum[-1])
    seg_len = np.diff(cum)
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg_len) - 1)
    # skip zero-length segments (a vertex on the plane): move to the next one with length
    good = np.flatnonzero(seg_len > 0)
    j = good[np.clip(np.searchsorted(good, i), 0, len(good) - 1)]
    i = np.where(seg_len[i] > 0, i, j)
    t = np.clip((s - cum[i]) / seg_len[i], 0.0, 1.0)
    p0, p1 = curve.points[i], curve.points[i + 1]
    tangent = (p1 - p0) / seg_len[i, None]
    return p0 + t[:, None] * (p1 - p0), curve.faces[i], tangent
