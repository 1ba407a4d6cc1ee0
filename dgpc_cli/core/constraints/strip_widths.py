"""Terms on edge lengths: arc length, equal strip widths (7), equal u-edges per row, ratio form
(5), developable (8)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian, linear_difference


def arclength(x, layout):
    """Discrete arc length along the u-lines (§5.1): ``w_ij − w_li = 0`` for consecutive u-edges."""
    eu = layout.eu
    return linear_difference(x, layout, layout.w_cols(eu[1:].ravel()),
                             layout.w_cols(eu[:-1].ravel()))


def equal_strip_width(x, layout):
    """Equal strip widths, equation (7): ``w_ik − w_im = 0`` for consecutive v-edges of a row."""
    ev = layout.ev
    return linear_difference(x, layout, layout.w_cols(ev[:, 1:].ravel()),
                             layout.w_cols(ev[:, :-1].ravel()))


def equal_u_edges(x, layout):
    """Equal u-edges along each row: ``w(u, v+1) − w(u, v) = 0`` for the u-edges from row u.

    With (6) and (7) the strips are then congruent (§4.2.1, Lemma 4.1); added as a hard term
    the system is singular at meridian nets (its only finite flexes besides Minding's bending
    are period-2 pleats), so the modes use it only as a soft term that keeps the u-spread of a
    drag small.
    """
    eu = layout.eu
    return linear_difference(x, layout, layout.w_cols(eu[:, 1:].ravel()),
                             layout.w_cols(eu[:, :-1].ravel()))


def developable(x, layout):
    """Discrete Jacobi equation for K = 0, equation (8): ``w_(u−1) − 2 w_u + w_(u+1) = 0``.

    Applied to the v-edge lengths along each strip; it assumes arc length along u (use it
    with the arclength term).
    """
    ev = layout.ev
    return linear_difference(x, layout, layout.w_cols(ev[2:].ravel()),
                             layout.w_cols(ev[:-2].ravel()), (1.0, 1.0, -2.0),
                             middle=layout.w_cols(ev[1:-1].ravel()))


def ratio_revolution(x, layout):
    """Constant ratio of v-edge lengths between rows, equation (5), in quadratic form.

    ``w(a, v) w(a+1, v+1) − w(a, v+1) w(a+1, v) = 0`` for consecutive rows a, a+1 and
    consecutive v: the ratio ‖δ_v f(a, v)‖ / ‖δ_v f(a+1, v)‖ does not depend on v.
    """
    _, _, w = layout.split(x)
    ev = layout.ev
    p, q = ev[:-1, :-1].ravel(), ev[1:, 1:].ravel()        # w(a, v), w(a+1, v+1)
    r, s = ev[:-1, 1:].ravel(), ev[1:, :-1].ravel()        # w(a, v+1), w(a+1, v)
    phi = w[p] * w[q] - w[r] * w[s]
    k = phi.size
    rows = np.arange(k)
    J = jacobian(
        k, layout.size,
        (rows, layout.w_cols(p), w[q]),
        (rows, layout.w_cols(q), w[p]),
        (rows, layout.w_cols(r), -w[s]),
        (rows, layout.w_cols(s), -w[r]),
    )
    return phi, J
