"""Figures of nets and molds: quads coloured by a field, the Clairaut plot, the mold profile,
and the laths of a gridshell.

Nets are drawn in 3-D (``mpl_toolkits.mplot3d``) from one fixed view (elevation
:data:`ELEVATION`, azimuth :data:`AZIMUTH`, equal axis scales, axes hidden), every quad filled
with the colour of its value; quads without a value (NaN) are light grey. Fields per quad:

* strip width (§3.1): the mean of the quad's two v-edge lengths (viridis);
* discrete Gaussian curvature K (Jacobi equation (1), :func:`gaussian_curvature`): the mean of
  the finite K at the quad's two v-edges, red positive, blue negative, white ≈ 0 (``bwr`` on a
  range symmetric about 0, as the paper's Fig. 17);
* strain |λ1| + |λ2| against the input net (Fig. 13): the mean over the quad's finite corners.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.curvature import gaussian_curvature, strip_widths

from .render import figure, png_bytes

#: The fixed 3-D view of every net figure (degrees).
ELEVATION, AZIMUTH = 28.0, -60.0
#: Colour of quads without a value.
MISSING = (0.85, 0.85, 0.85, 1.0)


def _nanmean(*arrays: np.ndarray) -> np.ndarray:
    stack = np.stack(arrays)
    ok = np.isfinite(stack)
    count = ok.sum(axis=0)
    total = np.where(ok, stack, 0.0).sum(axis=0)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def width_per_quad(f: np.ndarray) -> np.ndarray:
    """Strip width per quad ``(m − 1, n − 1)`` of a net ``f (m, n, 3)``."""
    w = strip_widths(f)
    return 0.5 * (w[:-1] + w[1:])


def curvature_per_quad(f: np.ndarray) -> np.ndarray:
    """Discrete Gaussian curvature per quad ``(m − 1, n − 1)`` (NaN where none is defined)."""
    K = gaussian_curvature(f)
    return _nanmean(K[:-1], K[1:])


def vertex_to_quad(values: np.ndarray) -> np.ndarray:
    """Per-vertex values ``(m, n)`` averaged to the quads ``(m − 1, n − 1)``, NaN-aware."""
    v = np.asarray(values, float)
    return _nanmean(v[:-1, :-1], v[1:, :-1], v[1:, 1:], v[:-1, 1:])


def _quads(f: np.ndarray) -> np.ndarray:
    """The quads of a grid ``f (m, n, 3)`` as ``((m − 1)(n − 1), 4, 3)``, row-major."""
    q = np.stack([f[:-1, :-1], f[1:, :-1], f[1:, 1:], f[:-1, 1:]], axis=2)
    return q.reshape(-1, 4, 3)


def _equal_limits(ax, points: np.ndarray) -> None:
    """Axis limits on the bounding box with one scale on all three axes (box aspect = the
    box's extents, each at least 5 % of the largest, so flat nets stay visible)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    extent = hi - lo
    big = float(extent.max()) or 1.0
    extent = np.maximum(extent, 0.05 * big)
    mid = 0.5 * (lo + hi)
    ax.set_xlim(mid[0] - extent[0] / 2, mid[0] + extent[0] / 2)
    ax.set_ylim(mid[1] - extent[1] / 2, mid[1] + extent[1] / 2)
    ax.set_zlim(mid[2] - extent[2] / 2, mid[2] + extent[2] / 2)
    ax.set_box_aspect(tuple(float(e) for e in extent))


def grids_png(grids: list[np.ndarray], values: list[np.ndarray], *, title: str, label: str,
              diverging: bool = False) -> bytes:
    """PNG of the quad grids ``grids[i] (m_i, n_i, 3)`` in the fixed 3-D view, quad colours
    from ``values[i] (m_i − 1, n_i − 1)`` with a colour bar labelled ``label``. ``diverging``:
    red positive / blue negative / white 0 on a range symmetric about 0."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    flat = np.concatenate([np.asarray(v, float).ravel() for v in values])
    finite = flat[np.isfinite(flat)]
    if diverging:
        a = float(np.abs(finite).max()) if finite.size else 0.0
        a = a if a > 0 else 1.0
        norm, cmap = Normalize(-a, a), colormaps["bwr"]
    else:
        lo = float(finite.min()) if finite.size else 0.0
        hi = float(finite.max()) if finite.size else 1.0
        if hi <= lo:
            hi = lo + (abs(lo) or 1.0) * 1e-9 + 1e-300
        norm, cmap = Normalize(lo, hi), colormaps["viridis"]

    fig = figure(6.4, 5.2)
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    for f, v in zip(grids, values, strict=True):
        f = np.asarray(f, float)
        v = np.asarray(v, float).ravel()
        colours = np.array([cmap(norm(x)) if np.isfinite(x) else MISSING for x in v])
        ax.add_collection3d(Poly3DCollection(_quads(f), facecolors=colours,
                                             edgecolors=(0.2, 0.2, 0.2, 0.6),
                                             linewidths=0.2))
    _equal_limits(ax, np.concatenate([np.asarray(f, float).reshape(-1, 3) for f in grids]))
    ax.view_init(elev=ELEVATION, azim=AZIMUTH)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.7, pad=0.02)
    bar.set_label(label, fontsize=8)
    bar.ax.tick_params(labelsize=7)
    return png_bytes(fig)


def polylines_png(families: list[list[np.ndarray]], names: list[str], *, title: str) -> bytes:
    """PNG of 3-D polylines (``(k, 3)`` each) in the fixed view of the net figures, one colour
    per family, with a legend of ``names`` (the two lath families of a gridshell, Fig. 14)."""
    fig = figure(6.4, 5.2)
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    colours = ["tab:blue", "tab:red", "tab:green", "tab:orange"]
    for k, (lines, name) in enumerate(zip(families, names, strict=True)):
        for i, line in enumerate(lines):
            p = np.asarray(line, float)
            ax.plot(p[:, 0], p[:, 1], p[:, 2], color=colours[k % len(colours)], lw=0.8,
                    label=name if i == 0 else None)
    _equal_limits(ax, np.concatenate([np.asarray(p, float) for lines in families
                                      for p in lines]))
    ax.view_init(elev=ELEVATION, azim=AZIMUTH)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="upper right")
    return png_bytes(fig)


def clairaut_png(values: np.ndarray, f: np.ndarray, *, title: str, units: str) -> bytes:
    """Paper Fig. 11: ``r cos α`` (``values (m, n)``) along every geodesic (u-line, column j of
    ``f (m, n, 3)``) against the arclength along it; constant for a geodesic (9)."""
    from matplotlib import colormaps

    values = np.asarray(values, float)
    f = np.asarray(f, float)
    n = values.shape[1]
    cmap = colormaps["viridis"]
    fig = figure(6.4, 4.0)
    ax = fig.add_subplot(1, 1, 1)
    for j in range(n):
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(f[:, j], axis=0),
                                                            axis=-1))])
        ax.plot(s, values[:, j], lw=0.8, marker=".", ms=2,
                color=cmap(j / max(n - 1, 1)))
    ax.set_xlabel(f"arclength along the geodesic [{units}]", fontsize=8)
    ax.set_ylabel(f"r cos α [{units}]", fontsize=8)
    ax.set_title(title, fontsize=9)
    ax.grid(True, lw=0.3)
    ax.tick_params(labelsize=7)
    fig.tight_layout()
    return png_bytes(fig)


def profile_png(r: np.ndarray, h: np.ndarray, *, unit: str, title: str) -> bytes:
    """PNG of :func:`profile_figure`."""
    return png_bytes(profile_figure(r, h, unit=unit, title=title))


def profile_figure(r: np.ndarray, h: np.ndarray, *, unit: str, title: str):
    """The mold's meridian ``(r, h)`` with its mirror image and the axis, equal scales, the
    axes labelled in ``unit``."""
    r, h = np.asarray(r, float), np.asarray(h, float)
    fig = figure(5.0, 6.0)
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(r, h, lw=1.2, marker=".", ms=3, color="tab:blue", label="meridian")
    ax.plot(-r, h, lw=0.6, ls="--", color="0.6")
    ax.axvline(0.0, lw=0.6, ls="-.", color="k", label="axis")
    ax.set_aspect("equal")
    ax.set_xlabel(f"r [{unit}]", fontsize=8)
    ax.set_ylabel(f"h [{unit}]", fontsize=8)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(True, lw=0.3)
    ax.tick_params(labelsize=7)
    fig.tight_layout()
    return fig
