"""Ruling directions and ruling planes of geodesic strips (paper §6.1 "Ruling vector field",
§6.2.4, Fig. 12, 18).

A geodesic strip lies between the u-lines v and v+1 of a net f (m, n, 3). Its tangent plane at
row u contains the v-edge and has the strip normal ``N_s(u)`` (the normal N = T^u × T^v of
§2.2.1 at the middle of the v-edge). The rulings of a developable strip are the intersections of
neighbouring tangent planes, so their directions are ``N × N₁`` (§6.1); we take the central
difference ``N_s(u−1) × N_s(u+1)`` (one-sided at the ends). Where the normals are almost parallel
(flat parts) the direction is undefined; there we average the directions of the nearest
non-flat rows on either side, weighted by their distance in rows (§6.2.4). A strip that is flat
everywhere keeps its v-edges as rulings.

Each ruling plane is spanned by the ruling direction and N_s and passes through the midpoint of
the v-edge; it cuts the two boundary geodesics (polylines) in the new vertices, giving an
almost planar quad strip (§6.2.4).

All functions are vectorized over a batch of strips: boundary polylines ``P, Q (S, m, 3)``.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import unit


def strip_boundaries(f: np.ndarray, columns) -> tuple[np.ndarray, np.ndarray]:
    """Boundary geodesics ``P = f[:, v]`` and ``Q = f[:, v+1]`` of the strips v in ``columns``,
    each ``(S, m, 3)``."""
    columns = np.asarray(columns, dtype=int)
    f = np.asarray(f, dtype=float)
    return np.moveaxis(f[:, columns], 1, 0), np.moveaxis(f[:, columns + 1], 1, 0)


def strip_normals(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Strip normals ``N_s = unit(T^u × T^v)`` at the midpoints of the v-edges, ``(S, m, 3)``.

    T^u is the mean of the two boundary geodesics' tangents ``unit(e1 − e3)`` (paper §2.2.1,
    one-sided at the ends) and T^v the direction of the v-edge ``Q − P``: the normal N of
    §2.2.1 taken at the middle of the strip, from the strip's own vertices (so a strip's rulings
    do not depend on its neighbours, and are symmetric where the strip is).
    """
    def tangent(X):
        e = unit(np.diff(X, axis=1))                                         # (S, m-1, 3)
        return unit(np.concatenate([e[:, :1], e[:, :-1] + e[:, 1:], e[:, -1:]], axis=1))

    return unit(np.cross(tangent(P) + tangent(Q), Q - P))


def raw_rulings(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cross products of neighbouring strip normals, ``N_s(u−1) × N_s(u+1)`` (one-sided
    ``N_s(0) × N_s(1)``, ``N_s(m−2) × N_s(m−1)`` at the ends), ``(S, m, 3)``, and the sine of the
    normals' angle per row step ``(S, m)`` (the flatness measure)."""
    lo = np.concatenate([normals[:, :1], normals[:, :-2], normals[:, -2:-1]], axis=1)
    hi = np.concatenate([normals[:, 1:2], normals[:, 2:], normals[:, -1:]], axis=1)
    steps = np.full(normals.shape[1], 2.0)
    steps[[0, -1]] = 1.0
    cross = np.cross(lo, hi)
    return cross, np.linalg.norm(cross, axis=-1) / steps


def ruling_directions(P, Q, normals, flat_angle: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit ruling directions ``(S, m, 3)`` oriented from P to Q, and the flat rows ``(S, m)``.

    A row is flat where the strip normals turn by less than ``flat_angle`` (radians) per row.
    Flat rows get the distance-weighted mean of the nearest non-flat rows' directions on both
    sides (one side at the ends); strips without any non-flat row keep their v-edges.
    """
    cross, sine = raw_rulings(normals)
    edge = Q - P
    flat = ~(sine > np.sin(flat_angle))
    sign = np.where(np.einsum("sui,sui->su", cross, edge) < 0, -1.0, 1.0)
    r = unit(cross * sign[..., None])
    S, m = flat.shape
    rows = np.broadcast_to(np.arange(m), (S, m))
    prev = np.maximum.accumulate(np.where(flat, -1, rows), axis=1)              # (S, m)
    nxt = np.minimum.accumulate(np.where(flat, m, rows)[:, ::-1], axis=1)[:, ::-1]
    has_prev, has_next = prev >= 0, nxt < m
    d_prev = np.where(has_prev, rows - prev, np.inf)
    d_next = np.where(has_next, nxt - rows, np.inf)
    w_prev = np.where(has_prev, 1.0 / np.maximum(d_prev, 1), 0.0)
    w_next = np.where(has_next, 1.0 / np.maximum(d_next, 1), 0.0)
    s_idx = np.arange(S)[:, None]
    r_prev = r[s_idx, np.clip(prev, 0, m - 1)]
    r_next = r[s_idx, np.clip(nxt, 0, m - 1)]
    averaged = unit(w_prev[..., None] * r_prev + w_next[..., None] * r_next)
    fallback = unit(edge)
    r = np.where(flat[..., None], averaged, r)
    r = np.where(np.isfinite(r).all(axis=-1, keepdims=True), r, fallback)
    return r, flat


def limit_obliqueness(P, Q, rulings, normals, max_shift: float) -> tuple[np.ndarray, np.ndarray]:
    """Rulings turned towards the v-edges where they are too oblique for the quad strip.

    A ruling at the angle ψ to the v-edge (in the tangent plane) through the v-edge's midpoint
    meets the boundary geodesics about ``(w/2) tan ψ / ℓ`` rows away (w the strip width, ℓ the
    u-edge length). Where N × N₁ runs almost along the strip (the normal turns mostly about the
    geodesic), that would leave the neighbouring rows and make consecutive rulings cross; such
    rulings are turned until they cut within ``max_shift`` rows. Returns the rulings ``(S, m, 3)``
    and where they were limited ``(S, m)``.
    """
    edge = Q - P
    w = np.linalg.norm(edge, axis=-1)
    e = unit(edge - np.einsum("sui,sui->su", edge, normals)[..., None] * normals)
    t = np.cross(normals, e)
    cos_psi = np.einsum("sui,sui->su", rulings, e)
    sin_psi = np.einsum("sui,sui->su", rulings, t)
    psi = np.arctan2(sin_psi, cos_psi)
    seg = 0.5 * (np.linalg.norm(np.diff(P, axis=1), axis=-1)
                 + np.linalg.norm(np.diff(Q, axis=1), axis=-1))           # (S, m-1)
    ell = np.concatenate([seg[:, :1], np.minimum(seg[:, :-1], seg[:, 1:]), seg[:, -1:]], axis=1)
    psi_max = np.arctan(2.0 * ell * max_shift / w)
    limited = np.abs(psi) > psi_max
    psi = np.clip(psi, -psi_max, psi_max)
    return np.cos(psi)[..., None] * e + np.sin(psi)[..., None] * t, limited


def plane_cut(X: np.ndarray, point: np.ndarray, normal: np.ndarray, near: np.ndarray):
    """Parameters ``s (S, r)`` where planes cut the polylines ``X (S, m, 3)``.

    Plane i of strip s passes through ``point[s, i]`` with normal ``normal[s, i]``; among its
    crossings with the polyline the one whose parameter (segment index + fraction) is nearest to
    ``near[i]`` is taken. Without a crossing the line of the nearest end segment is cut
    (extrapolation; NaN if that segment is parallel to the plane).
    """
    d = np.einsum("skj,sij->sik", X, normal) - np.einsum("sij,sij->si", point, normal)[..., None]
    d0, d1 = d[..., :-1], d[..., 1:]                                            # (S, r, m-1)
    denom = d0 - d1
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(denom != 0, d0 / denom, np.nan)
    m1 = X.shape[1] - 1
    seg = np.arange(m1)
    s = seg + frac
    crossing = (d0 * d1 <= 0) & (denom != 0)
    dist = np.where(crossing, np.abs(s - np.asarray(near, float)[None, :, None]), np.inf)
    best = np.argmin(dist, axis=-1)
    found = np.isfinite(np.take_along_axis(dist, best[..., None], -1)[..., 0])
    s_cross = np.take_along_axis(s, best[..., None], -1)[..., 0]
    s_first, s_last = s[..., 0], s[..., -1]
    near_b = np.broadcast_to(np.asarray(near, float), s_first.shape)
    s_extra = np.where(np.abs(s_first - near_b) <= np.abs(s_last - near_b), s_first, s_last)
    return np.where(found, s_cross, s_extra)


def point_at(X: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points of the polylines ``X (S, m, 3)`` at parameters ``s (S, r)`` (linear on the
    segments, extrapolated along the end segments), ``(S, r, 3)``."""
    k = np.clip(np.floor(s), 0, X.shape[1] - 2).astype(int)
    t = (s - k)[..., None]
    a = np.take_along_axis(X, k[..., None], 1)
    b = np.take_along_axis(X, k[..., None] + 1, 1)
    return a + t * (b - a)


def cut_rulings(P, Q, rulings, normals) -> tuple[np.ndarray, np.ndarray]:
    """New vertices ``A, B (S, m, 3)`` where the ruling planes (spanned by the ruling and N_s,
    through the v-edge midpoints) cut the boundary geodesics P and Q (paper §6.2.4), and their
    parameters on P and Q ``(S, m, 2)``.

    The end rulings are the net's end v-edges (SPEC §6: every strip starts and ends on the
    net's boundary rows, so the parts cover the design edge to edge); the polish makes the end
    quads planar.
    """
    m = P.shape[1]
    plane_n = unit(np.cross(rulings, normals))
    rows = np.arange(m, dtype=float)
    mid = 0.5 * (P + Q)
    sP = plane_cut(P, mid, plane_n, rows)
    sQ = plane_cut(Q, mid, plane_n, rows)
    for u in (0, m - 1):
        sP[:, u] = sQ[:, u] = float(u)
    return point_at(P, sP), point_at(Q, sQ), np.stack([sP, sQ], axis=-1)


def cut_tangents(P: np.ndarray, Q: np.ndarray, params: np.ndarray) -> np.ndarray:
    """Unit tangents ``(m, 2, 3)`` of the boundary polylines ``P, Q (m, 3)`` at the parameters
    ``params (m, 2)``: the segment's direction, or the vertex tangent T^u = unit(e1 − e3) where
    a parameter falls on a polyline vertex (within 1e-9)."""
    out = []
    for X, s in ((P, params[:, 0]), (Q, params[:, 1])):
        e = unit(np.diff(X, axis=0))                                         # (m-1, 3)
        vert = unit(np.concatenate([e[:1], e[:-1] + e[1:], e[-1:]]))          # (m, 3)
        k = np.clip(np.floor(s), 0, X.shape[0] - 2).astype(int)
        r = np.rint(s)
        on_vertex = (np.abs(s - r) <= 1e-9) & (r >= 0) & (r <= X.shape[0] - 1)
        out.append(np.where(on_vertex[:, None], vert[np.clip(r, 0, X.shape[0] - 1).astype(int)],
                            e[k]))
    return np.stack(out, axis=1)
