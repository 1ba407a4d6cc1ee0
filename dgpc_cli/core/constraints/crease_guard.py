"""Crease guard of a drag: the rows' third differences may not grow past a margin.

A drag bends the rows of a net (the geodesic parallels, "across the geodesics"). Where isometry
is weighed against the angle condition (6), the cheapest way for the net to take up a push is to
fold along a few meridians: a crease is nearly an exact deformation of (6) and the edge lengths
(the period-2 pleats of the isometry study are the extreme case), so the less smoothness a drag
keeps, the sharper a row bends three columns from a held corner. Smoothness on the displacement
spreads the push but costs strain everywhere, also where the net bends gently.

The guard acts only where a row bends sharply: for every run of four vertices ``f_a … f_d`` of a
row, with ``d₃ = f_d − 3 f_c + 3 f_b − f_a`` (its third difference along the row) and ``d₃⁰``
that of the start net, the residual is

    max(0, ‖d₃‖ − ‖d₃⁰‖ − max(margin, 2‖d₃⁰‖))

(in units of the start net's mean edge length): a row may bend by the margin, or by twice its
own third difference where a coarse net's rows are that sharp already. It is zero on every
smooth drag and grows linearly past that; the Jacobian ``d₃ᵀ/‖d₃‖ · (−1, 3, −3, 1)`` is kept
at every run (zeros where the guard is inactive) so that its pattern does not depend on x.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian

#: Growth of a row's third difference over the start net's (mean edge lengths) the guard allows
#: for free: below the crease the metrics flag (0.05, ``metrics.crease``), so that a guarded drag
#: of a smooth net stays unflagged (a 21×21 sphere net's rows have 0.016 of their own).
CREASE_MARGIN = 0.03
#: ... or this multiple of the run's own third difference, where that is more: a coarse net's
#: rows bend sharply at every vertex (0.05 to 0.08 mean edges on a 9×7 Gehry net), and a smooth
#: drag of it changes them by as much.
CREASE_RATIO = 2.0


def row_runs(layout):
    """Vertex ids ``(a, b, c, d)`` of every run of four consecutive vertices along the rows,
    each of shape ``(m·(n − 3),)`` (empty for n < 4)."""
    vid, n = layout.vid, layout.n
    return tuple(vid[:, k:n - 3 + k].ravel() for k in range(4))


def crease_guard(x, layout, f0, margin: float = CREASE_MARGIN):
    """Residuals ``max(0, ‖d₃‖ − ‖d₃⁰‖ − max(margin, CREASE_RATIO · ‖d₃⁰‖))``, one per run
    of four vertices of a row (see the module docstring), against the start net
    ``f0 (|V|, 3)`` or ``(m, n, 3)``."""
    f, _, _ = layout.split(x)
    g0 = np.asarray(f0, dtype=float).reshape(-1, 3)
    a, b, c, d = row_runs(layout)
    d3 = f[d] - 3.0 * f[c] + 3.0 * f[b] - f[a]
    length = np.linalg.norm(d3, axis=1)
    own = np.linalg.norm(g0[d] - 3.0 * g0[c] + 3.0 * g0[b] - g0[a], axis=1)
    allowed = own + np.maximum(margin, CREASE_RATIO * own)
    active = length > allowed
    phi = np.where(active, length - allowed, 0.0)
    unit = np.where(active[:, None], d3 / np.where(active, length, 1.0)[:, None], 0.0)
    rows = np.arange(phi.size)[:, None]
    J = jacobian(phi.size, layout.size,
                 (rows, layout.f_cols(a), -unit), (rows, layout.f_cols(b), 3.0 * unit),
                 (rows, layout.f_cols(c), -3.0 * unit), (rows, layout.f_cols(d), unit))
    return phi, J
