"""Fairness (§5.1): vanishing second differences ``f_l − 2 f_i + f_j = 0`` along u and v, of the
vertices or of their displacement from a start net; and the displacement itself.

A handle drag (§5.2: "interactive editing") keeps the rest of the net smooth by fairness on the
*displacement* ``g = f − f⁰`` from the net the drag started from: it vanishes for translations
and for every affine change of a flat grid, so a drag bends the net smoothly instead of
flattening it as fairness on f does. Scalings and large rotations are affine too, and the
flexible systems (6) + (7) allow them: the ``closeness`` term ``f − f⁰`` (a far smaller weight)
keeps the drag from drifting along them.

Second differences alone leave a crease at a held vertex: their least-squares energy is a discrete
thin plate, whose response to a point displacement (the Green's function r² log r) has a
logarithmically unbounded curvature there. ``displacement_smoothness``, the third differences of
the displacement, is the next order (r⁴ log r: bounded curvature), and spreads a push smoothly.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def _second_difference_stencil(layout):
    """Vertex ids ``(lo, mid, hi)`` of every second difference along u, then along v."""
    vid = layout.vid
    triples = [(vid[:-2], vid[1:-1], vid[2:]), (vid[:, :-2], vid[:, 1:-1], vid[:, 2:])]
    return tuple(np.concatenate([t[k].ravel() for t in triples]) for k in range(3))


def _second_differences(f, layout):
    lo, mid, hi = _second_difference_stencil(layout)
    phi = (f[lo] - 2.0 * f[mid] + f[hi]).ravel()
    rows = np.arange(phi.size).reshape(-1, 3)
    J = jacobian(phi.size, layout.size,
                 (rows, layout.f_cols(lo), 1.0),
                 (rows, layout.f_cols(mid), -2.0),
                 (rows, layout.f_cols(hi), 1.0))
    return phi, J


def _third_differences(g, layout):
    """Third differences ``g_a − 3 g_b + 3 g_c − g_d`` of ``g (|V|, 3)`` along u, then along v."""
    vid = layout.vid
    quads = [(vid[:-3], vid[1:-2], vid[2:-1], vid[3:]),
             (vid[:, :-3], vid[:, 1:-2], vid[:, 2:-1], vid[:, 3:])]
    a, b, c, d = (np.concatenate([q[k].ravel() for q in quads]) for k in range(4))
    phi = (g[a] - 3.0 * g[b] + 3.0 * g[c] - g[d]).ravel()
    rows = np.arange(phi.size).reshape(-1, 3)
    J = jacobian(phi.size, layout.size,
                 (rows, layout.f_cols(a), 1.0), (rows, layout.f_cols(b), -3.0),
                 (rows, layout.f_cols(c), 3.0), (rows, layout.f_cols(d), -1.0))
    return phi, J


def fairness(x, layout):
    """Second differences of the vertices along the u-lines, then along the v-lines (xyz rows),
    §5.1."""
    f, _, _ = layout.split(x)
    return _second_differences(f, layout)


def displacement_fairness(x, layout, f0):
    """Second differences of the displacement ``f − f⁰`` from the start net ``f0 (|V|, 3)`` or
    ``(m, n, 3)``, along u then v (xyz rows): §5.1 fairness applied to a drag."""
    f, _, _ = layout.split(x)
    return _second_differences(f - np.asarray(f0, dtype=float).reshape(-1, 3), layout)


def displacement_smoothness(x, layout, f0):
    """Third differences of the displacement ``f − f⁰`` along u then v (xyz rows): the drag's
    smoothness of the next order, which spreads the push of a held vertex without a crease."""
    f, _, _ = layout.split(x)
    return _third_differences(f - np.asarray(f0, dtype=float).reshape(-1, 3), layout)


def closeness(x, layout, f0):
    """The displacement ``f_i − f⁰_i`` of every vertex (xyz rows) from the start net ``f0``."""
    f, _, _ = layout.split(x)
    phi = (f - np.asarray(f0, dtype=float).reshape(-1, 3)).ravel()
    rows = np.arange(phi.size)
    cols = layout.f_cols(np.arange(layout.n_vertices)).ravel()
    return phi, jacobian(phi.size, layout.size, (rows, cols, 1.0))
