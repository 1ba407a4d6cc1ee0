"""How much the strips of a net vary in width along themselves (issue: "strip widths that vary
least"; a part whose width varies threefold is hard to clad with, one that pinches cannot be
made): the width of strip j at row u is the v-edge ``‖f(u, j+1) − f(u, j)‖`` (§3.1)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.curvature import strip_widths


def width_figures(f, keep: np.ndarray | None = None) -> dict | None:
    """``{"width_ratio": the largest over the strips of max/min width along the strip,
    "narrowest": the narrowest width / the mean width}`` of the net ``f (m, n, 3)``, over the
    v-edges where ``keep (m, n−1)`` is True (default: all; a strip with fewer than two kept
    edges is left out of the ratio). None when no strip has two kept edges or a kept width is
    zero."""
    w = strip_widths(f)
    keep = np.ones(w.shape, bool) if keep is None else np.asarray(keep, bool)
    counted = keep.sum(axis=0) >= 2
    if not counted.any():
        return None
    big = np.where(keep, w, -np.inf).max(axis=0)[counted]
    small = np.where(keep, w, np.inf).min(axis=0)[counted]
    if not (small > 0).all():
        return None
    return {"width_ratio": float((big / small).max()),
            "narrowest": float(w[keep].min() / w[keep].mean())}
