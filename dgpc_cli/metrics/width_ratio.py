"""How much the strips of a net vary in width along themselves (issue: "strip widths that vary
least"; a part whose width varies threefold is hard to clad with, one that pinches cannot be
made): the width of strip j at row u is the v-edge ``‖f(u, j+1) − f(u, j)‖`` (§3.1)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.curvature import strip_widths


def strip_width_ratios(f, keep: np.ndarray | None = None) -> np.ndarray:
    """``(n−1,)``: per strip of the net ``f (m, n, 3)``, its widest over its narrowest width
    over the v-edges where ``keep (m, n−1)`` is True (default: all); NaN for a strip with fewer
    than two kept edges, inf where a kept width is zero."""
    w = strip_widths(f)
    keep = np.ones(w.shape, bool) if keep is None else np.asarray(keep, bool)
    big = np.where(keep, w, -np.inf).max(axis=0)
    small = np.where(keep, w, np.inf).min(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(small > 0, big / np.where(small > 0, small, 1.0), np.inf)
    return np.where(keep.sum(axis=0) >= 2, ratio, np.nan)


def width_figures(f, keep: np.ndarray | None = None) -> dict | None:
    """``{"width_ratio": the largest over the strips of max/min width along the strip,
    "narrowest": the narrowest width / the mean width}`` of the net ``f (m, n, 3)``, over the
    v-edges where ``keep (m, n−1)`` is True (default: all; a strip with fewer than two kept
    edges is left out of the ratio). None when no strip has two kept edges or a kept width is
    zero."""
    ratio = strip_width_ratios(f, keep)
    counted = ratio[~np.isnan(ratio)]
    if not counted.size or not np.isfinite(counted).all():
        return None
    w = strip_widths(f)
    keep = np.ones(w.shape, bool) if keep is None else np.asarray(keep, bool)
    return {"width_ratio": float(counted.max()),
            "narrowest": float(w[keep].min() / w[keep].mean())}


def widest_strip(f, keep: np.ndarray | None = None) -> tuple[float, int] | None:
    """The widest v-edge of the net ``f (m, n, 3)`` where ``keep (m, n−1)`` is True (default:
    all): its length (the strip's width at that row, in the net's unit) and the strip ``j`` it
    belongs to; None when nothing is kept."""
    w = strip_widths(f)
    if keep is not None:
        w = np.where(np.asarray(keep, bool), w, -np.inf)
    k = int(np.argmax(w))
    if not np.isfinite(w.flat[k]):
        return None
    return float(w.flat[k]), int(np.unravel_index(k, w.shape)[1])
