"""Colours of a per-vertex field on the edit page: 0 → blue, the tolerance → yellow, twice it
and above → red (viridis up to the tolerance, then towards red); undefined → grey."""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps

#: Undefined values (nan): grey.
UNDEFINED = (128, 128, 128)
_MAP = colormaps["viridis"]


def field_colours(values: np.ndarray, limit: float) -> np.ndarray:
    """RGB ``(k, 3)`` uint8 of ``values`` (any shape, flattened) against the tolerance
    ``limit``: viridis on [0, limit], then blended to red up to 2 × limit."""
    x = np.asarray(values, dtype=float).reshape(-1) / limit
    ok = np.isfinite(x)
    t = np.clip(np.where(ok, x, 0.0), 0.0, 2.0)
    rgb = _MAP(np.minimum(t, 1.0))[:, :3]
    over = np.clip(t - 1.0, 0.0, 1.0)[:, None]
    rgb = (1.0 - over) * rgb + over * np.array([0.85, 0.1, 0.1])
    out = np.round(255 * rgb).astype(np.uint8)
    out[~ok] = UNDEFINED
    return out


def legend(limit: float) -> str:
    """A one-line legend of :func:`field_colours`."""
    return f"blue 0, yellow {limit:g}, red ≥ {2 * limit:g}"
