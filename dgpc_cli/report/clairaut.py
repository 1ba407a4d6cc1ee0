"""Paper Fig. 11: Clairaut's relation (9), r cos α constant along each geodesic of a surface of
revolution, for the geodesics the metric checks.

The metric (:func:`~dgpc_cli.metrics.clairaut.clairaut`) takes the interior u-lines v = 1 … n−2
at the interior rows (where T^u exists). The figure plots, for exactly those, ``r cos α`` minus
the geodesic's mean against the arc length along it (one line per geodesic, gid
``clairaut-v<j>``, coloured by v), the band ± the largest MAD, and below it each geodesic's mean
with its MAD as an error bar. The deviation axis is scaled to the data, but never below
:data:`FLOOR` × the mean radius, so that a meridian net (r cos α = 0 up to rounding) shows a flat
line, not its rounding noise at full scale.
"""

from __future__ import annotations

import numpy as np

from .render import figure

__all__ = ["CLAIRAUT_SIZE", "FLOOR", "clairaut_figure"]

#: Size of the figure (inches).
CLAIRAUT_SIZE = (8.0, 6.4)
#: Smallest half-range of the deviation axis, as a fraction of the mean radius.
FLOOR = 1e-6
LABEL_PT, TICK_PT = 9, 8


def _title(metric: dict, unit: str, count: int) -> str:
    mad, rel = metric.get("max_mad"), metric.get("max_relative_mad")
    head = f"Clairaut's relation (9) on {count} interior geodesics"
    if mad is None:
        return head
    tail = f"max MAD {mad:.3g} {unit}"
    if rel is not None:
        tail += f" = {100 * rel:.3g} % of |mean r cos α|"
    else:
        tail += f" = {mad / metric['mean_radius']:.2g} of the mean radius (r cos α ≈ 0)"
    return f"{head}\n{tail}"


def clairaut_figure(values: np.ndarray, f: np.ndarray, metric: dict, *, unit: str):
    """The figure of ``values (m, n)`` (:func:`~dgpc_cli.metrics.clairaut.clairaut_values`)
    along the geodesics of ``f (m, n, 3)``, for the geodesics of ``metric`` (the
    :func:`~dgpc_cli.metrics.clairaut.clairaut` record of the same net and axis)."""
    from matplotlib import colormaps
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.ticker import MaxNLocator

    values = np.asarray(values, float)
    f = np.asarray(f, float)
    per = metric["per_geodesic"]
    geodesics = list(per["v"])
    cmap = colormaps["viridis"]
    fig = figure(*CLAIRAUT_SIZE)
    ax = fig.add_axes((0.1, 0.42, 0.86, 0.45))
    bottom = fig.add_axes((0.1, 0.08, 0.86, 0.24))
    ax.set_gid("clairaut-deviation")
    bottom.set_gid("clairaut-means")
    lo, hi = (0, 1) if len(geodesics) < 2 else (geodesics[0], geodesics[-1])
    biggest = 0.0
    handles = []
    for k, j in enumerate(geodesics):
        mean = per["mean"][k]
        if mean is None:
            continue
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(f[:, j], axis=0),
                                                            axis=-1))])[1:-1]
        dev = values[1:-1, j] - mean
        biggest = max(biggest, float(np.abs(dev).max(initial=0.0)))
        colour = cmap((j - lo) / max(hi - lo, 1))
        (line,) = ax.plot(s, dev, lw=0.9, marker=".", ms=2.5, color=colour,
                          gid=f"clairaut-v{j}")
        if k in (0, len(geodesics) // 2, len(geodesics) - 1):
            line.set_label(f"geodesic v = {j}")
            handles.append(line)
    mad = metric.get("max_mad") or 0.0
    floor = FLOOR * metric.get("mean_radius", 1.0)
    half = max(1.15 * biggest, 1.15 * mad, floor)
    ax.axhspan(-mad, mad, color="0.85", zorder=0)
    ax.axhline(0.0, color="0.3", lw=0.6, zorder=0)
    handles.append(Patch(color="0.85", label=f"± max MAD ({mad:.3g} {unit})"))
    handles.append(Line2D([], [], color="none",
                          label=f"colour: v = {lo} … {hi} ({len(geodesics)} geodesics)"))
    ax.set_ylim(-half, half)
    ax.set_xlabel(f"arc length along the geodesic [{unit}]", fontsize=LABEL_PT)
    ax.set_ylabel(f"r cos α − its mean [{unit}]", fontsize=LABEL_PT)
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4))
    ax.legend(handles=handles, fontsize=TICK_PT, loc="upper right", ncol=2, framealpha=0.9)
    ax.grid(True, lw=0.3)
    ax.tick_params(labelsize=TICK_PT)
    means = np.array([np.nan if x is None else x for x in per["mean"]], float)
    mads = np.array([np.nan if x is None else x for x in per["mad"]], float)
    bottom.errorbar(geodesics, means, yerr=mads, fmt="o", ms=3, color="tab:blue", capsize=2,
                    lw=0.8, gid="clairaut-mean")
    bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
    bottom.set_xlabel("geodesic v", fontsize=LABEL_PT)
    bottom.set_ylabel(f"mean r cos α [{unit}]", fontsize=LABEL_PT)
    bottom.set_title("each geodesic's constant, MAD as error bar", fontsize=LABEL_PT)
    finite = means[np.isfinite(means)]
    if finite.size:
        spread = max(float(np.ptp(finite)), floor)
        mid = 0.5 * (float(finite.max()) + float(finite.min()))
        bottom.set_ylim(mid - 0.7 * spread - float(np.nanmax(mads, initial=0.0)),
                        mid + 0.7 * spread + float(np.nanmax(mads, initial=0.0)))
    bottom.grid(True, lw=0.3)
    bottom.tick_params(labelsize=TICK_PT)
    fig.suptitle(_title(metric, unit, len(geodesics)), fontsize=11, y=0.98)
    return fig
