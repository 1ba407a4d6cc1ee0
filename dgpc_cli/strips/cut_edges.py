"""The cut edges of a shared-outline template (``planarize-strips``, ``unfold``; issue "Strips that
build the design": one template, outlines identical).

A template fitted with a shared outline (:mod:`dgpc_cli.strips.template`) gives every strip its
own rulings, whose end points lie on the template's two outline curves. Cut along the polyline
through its own ruling ends, each part would differ from the others by the curves' sag between
them. Instead every part is cut along the curves themselves, sampled at the same points for
every strip (so the parts' outlines are one outline, to round-off): between two neighbouring
rulings the template region bounded by the curve is flat, and the strip's quad there is its
rigid image, so each sample is carried to the strip by the map of the quad it falls in.

A sample is stored in the strip's ``(t, s)`` (:func:`dgpc_cli.strips.trim.strip_points`: row u
at t = u, A at s = 0, B at s = 1, bilinear on the quad ``floor(t)``). The bilinear map of a
planar quad is the rigid image of the map of its development (affine combinations commute with
rigid motions), so the same ``(t, s)`` gives the sample on the 3-D strip (in its quad's plane)
and on its development; points on a curve bulge slightly beyond their quad's boundary edge
(``s`` a little below 0 or above 1). Only the samples strictly between the end rows are
stored: an edge between rows r0 and r1 is the vertex at r0, the samples in between, the vertex
at r1 (:func:`edges_between`), so boards cut at rulings keep their cut edges too.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import chebyshev

from dgpc_cli.strips.trim import strip_points

#: The curves are sampled so that their sag between two samples stays below this (mm).
SAG_MM = 1e-3
#: Samples per quad along the strip, at least and at most.
MIN_PER_QUAD, MAX_PER_QUAD = 2, 32
#: Newton steps of the inverse bilinear map, and the residual (relative to the quad) accepted.
NEWTON_STEPS = 12
NEWTON_TOL = 1e-11


def curve_x(curves: tuple, y: np.ndarray, side: int, derivative: int = 0) -> np.ndarray:
    """The x of outline curve ``side`` (0: A, 1: B) of ``curves = (y0, h, c)`` at ``y``, or its
    ``derivative``-th derivative."""
    y0, h, c = curves
    coef = np.asarray(c, float)[side]
    if derivative:
        coef = chebyshev.chebder(coef, derivative) / h ** derivative
    return chebyshev.chebval((np.asarray(y, float) - y0) / h, coef)


def curve_samples(curves: tuple, ends: np.ndarray, m: int, sag: float = SAG_MM) -> np.ndarray:
    """The sample points ``(2, k, 2)`` of the two outline curves, from their start ``ends[0, j]``
    to their end ``ends[1, j]`` (each ``(x, y)``, the template's end vertices), at equal steps
    of y, k the same for both curves: enough that the sag stays below ``sag``
    (curvature × step² / 8), between :data:`MIN_PER_QUAD` and :data:`MAX_PER_QUAD` per quad of
    the ``m``-row strip. The end points are the given ends."""
    fine = np.linspace(0.0, 1.0, 64 * (m - 1) + 1)
    count = MIN_PER_QUAD * (m - 1)
    for j in (0, 1):
        y = ends[0, j, 1] + fine * (ends[1, j, 1] - ends[0, j, 1])
        d1, d2 = curve_x(curves, y, j, 1), curve_x(curves, y, j, 2)
        kappa = float(np.max(np.abs(d2) / (1.0 + d1 ** 2) ** 1.5))
        length = float(np.sum(np.hypot(np.diff(curve_x(curves, y, j)), np.diff(y))))
        if kappa > 0:
            count = max(count, int(np.ceil(length / np.sqrt(8.0 * sag / kappa))))
    count = min(count, MAX_PER_QUAD * (m - 1))
    out = []
    for j in (0, 1):
        y = np.linspace(ends[0, j, 1], ends[1, j, 1], count + 1)
        pts = np.stack([curve_x(curves, y, j), y], axis=-1)
        pts[0], pts[-1] = ends[0, j], ends[1, j]
        out.append(pts)
    return np.stack(out)


def inverse_bilinear(A: np.ndarray, B: np.ndarray, u: np.ndarray, p: np.ndarray,
                     guess: np.ndarray) -> np.ndarray:
    """``(t, s)`` ``(k, 2)`` of the points ``p (k, 2)`` in the quads ``u (k,)`` of the developed
    strip ``A, B (m, 2)`` (the inverse of :func:`~dgpc_cli.strips.trim.strip_points` there),
    by Newton's method from ``guess (k, 2)`` (the fraction along the quad and s). ValueError
    if a point is not reached."""
    A0, A1, B0, B1 = A[u], A[u + 1], B[u], B[u + 1]
    a, s = guess[:, 0].copy(), guess[:, 1].copy()
    size = np.linalg.norm(A1 - A0, axis=1) + np.linalg.norm(B0 - A0, axis=1)
    for _ in range(NEWTON_STEPS):
        lo = (1 - s)[:, None] * A0 + s[:, None] * B0
        hi = (1 - s)[:, None] * A1 + s[:, None] * B1
        r = (1 - a)[:, None] * lo + a[:, None] * hi - p
        ja = hi - lo
        js = (1 - a)[:, None] * (B0 - A0) + a[:, None] * (B1 - A1)
        det = ja[:, 0] * js[:, 1] - ja[:, 1] * js[:, 0]
        a = a - (js[:, 1] * r[:, 0] - js[:, 0] * r[:, 1]) / det
        s = s - (ja[:, 0] * r[:, 1] - ja[:, 1] * r[:, 0]) / det
    ts = np.stack([u + a, s], axis=-1)
    miss = np.linalg.norm(strip_points(A, B, ts) - p, axis=1)
    if not np.all(miss <= NEWTON_TOL * size):
        raise ValueError(f"a cut-edge sample is {miss.max():.3g} from its quad's map")
    return ts


def strip_cut_edges(development: np.ndarray, samples: np.ndarray) -> tuple[np.ndarray,
                                                                           np.ndarray] | None:
    """The ``(t, s)`` of the interior ``samples (2, k, 2)`` (:func:`curve_samples`) on the
    strip whose development is ``development (m, 2, 2)`` in the curves' frame (``[u, 0] = A_u``,
    ``[u, 1] = B_u``): each sample in the quad between the two rulings whose ends on its curve
    enclose it (in y). None when a boundary does not run monotonically in y (no quad is
    defined)."""
    A, B = development[:, 0], development[:, 1]
    m = A.shape[0]
    out = []
    for j, X in enumerate((A, B)):
        sign = 1.0 if X[-1, 1] >= X[0, 1] else -1.0
        y = sign * X[:, 1]
        if not np.all(np.diff(y) > 0):
            return None
        p = samples[j, 1:-1]
        u = np.clip(np.searchsorted(y, sign * p[:, 1], side="right") - 1, 0, m - 2)
        frac = (sign * p[:, 1] - y[u]) / (y[u + 1] - y[u])
        out.append(inverse_bilinear(A, B, u, p, np.stack([frac, np.full_like(frac, j)], -1)))
    return out[0], out[1]


def edges_between(A: np.ndarray, B: np.ndarray, cut: tuple, r0: int, r1: int
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The cut edges ``(A', B')`` of the rows ``r0..r1`` of the strip (or development) ``A, B
    (m, d)`` with the interior cut-edge samples ``cut = (ts_A, ts_B)`` (see the module): on
    each side the vertex at r0, the samples strictly between, the vertex at r1."""
    out = []
    for X, ts in zip((A, B), cut, strict=True):
        ts = np.asarray(ts, float).reshape(-1, 2)
        inside = ts[(ts[:, 0] > r0) & (ts[:, 0] < r1)]
        out.append(np.concatenate([X[r0:r0 + 1], strip_points(A, B, inside), X[r1:r1 + 1]]))
    return out[0], out[1]


def template_cut_edges(developments: np.ndarray, curves: tuple) -> list | None:
    """For the developments ``(S, m, 2, 2)`` of a shared-outline template fit (every strip's,
    in the curves' frame, mm) and its ``curves`` (:attr:`~.template.TemplateFit.outline`), each
    strip's interior cut-edge samples ``(ts_A, ts_B)``, the same curve points for every strip
    (:func:`curve_samples` between the first development's end vertices, which every strip
    shares); None when a strip's boundary does not run monotonically along the curves or a
    sample is not reached in its quad."""
    devs = np.asarray(developments, float)
    ends = np.stack([devs[0, 0], devs[0, -1]])                           # (2, 2 sides, 2)
    samples = curve_samples(curves, ends, devs.shape[1])
    out = []
    for dev in devs:
        try:
            cut = strip_cut_edges(dev, samples)
        except ValueError:
            return None
        if cut is None:
            return None
        out.append(cut)
    return out
