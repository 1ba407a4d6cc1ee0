"""The rim keeps what the net covered (a companion of the approximation term, §5.1).

The approximation term lets every vertex slide along the reference, and fairness (second
differences, §5.1) is least for a smaller net: on a curved reference ``f_l − 2 f_i + f_j`` is
about h² times the curvature, so a fit with fairness draws the net in, and the reference area
its rim covered at the start is bared. The rim term lets each rim vertex move outwards,
along the reference or off its edge, but not inwards: with ``o`` the unit outward direction of
the net's rim at the start (the last edge of the grid line that ends there, continued; two rows
at a corner, one per side) and ``s`` the distance the start vertex lies beyond the reference
(a net traced past the reference's edge, ``init --extend``, may come in that far), the residual
is ``min(0, ⟨f − f⁰, o⟩ + s)``: zero wherever the rim stayed or went out.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.core.constraints.base import jacobian


def rim_directions(layout, f0) -> tuple[np.ndarray, np.ndarray]:
    """Rim vertex ids ``(r,)`` and their unit outward directions ``(r, 3)`` on the start net
    ``f0 (|V|, 3)`` or ``(m, n, 3)``: rows 0 and m−1, then columns 0 and n−1 (corners twice)."""
    f0 = np.asarray(f0, dtype=float).reshape(layout.m, layout.n, 3)
    vid = layout.vid
    sides = [(vid[0], f0[0] - f0[1]), (vid[-1], f0[-1] - f0[-2]),
             (vid[:, 0], f0[:, 0] - f0[:, 1]), (vid[:, -1], f0[:, -1] - f0[:, -2])]
    ids = np.concatenate([s[0] for s in sides])
    out = np.concatenate([s[1] for s in sides])
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return ids, out / np.where(length > 0, length, 1.0)


def rim(x, layout, ids, start, outward, slack):
    """Residuals ``min(0, ⟨f_i − f⁰_i, o_i⟩ + s_i)``, one per rim row: ``ids (r,)`` and
    ``outward (r, 3)`` as :func:`rim_directions` gives them, ``start (r, 3)`` the start
    positions ``f⁰`` of those vertices and ``slack (r,)`` how far each may come in (≥ 0). The
    Jacobian row is ``o_i`` where the residual is negative and explicit zeros elsewhere (a fixed
    pattern)."""
    f, _, _ = layout.split(x)
    ids = np.asarray(ids)
    reach = np.einsum("ij,ij->i", f[ids] - start, outward) + slack
    inward = reach < 0.0
    phi = np.where(inward, reach, 0.0)
    rows = np.arange(len(ids))[:, None]
    return phi, jacobian(len(ids), layout.size,
                         (rows, layout.f_cols(ids), outward * inward[:, None]))
