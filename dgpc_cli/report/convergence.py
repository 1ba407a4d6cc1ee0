"""The solver's convergence: the history ``dgpc optimize`` records in ``status.steps`` drawn as
a plot (the HTML page shows it instead of rows of numbers).

Every handle step, relaxation round and final projection is a guided-projection run; its
``history`` holds per iteration the paper's
R and the residual norm of every term. The plot puts the runs one after the other on the
iteration axis (a dotted line where a run begins), R thick and every term thin, on a
logarithmic scale (zeros are left out: a log scale has no room for them).
"""

from __future__ import annotations

import numpy as np

from .render import figure

__all__ = ["CONVERGENCE_SIZE", "convergence_figure", "has_history"]

#: Size of the figure (inches).
CONVERGENCE_SIZE = (8.0, 4.2)
LABEL_PT, TICK_PT = 9, 8


def has_history(status: dict) -> bool:
    """Whether ``status`` records a solver history (an optimized net's)."""
    return any(step.get("history") for step in status.get("steps") or [])


def _positive(values) -> np.ndarray:
    v = np.array([np.nan if x is None else x for x in values], float)
    return np.where(v > 0, v, np.nan)


def convergence_figure(status: dict, *, title: str):
    """R (line gid ``R``) and every term's residual norm (gid ``term-<name>``) per iteration
    over all steps of ``status["steps"]``."""
    from matplotlib import colormaps

    steps = [s for s in status["steps"] if s.get("history")]
    terms = sorted({t for s in steps for h in s["history"] for t in h.get("residuals", {})})
    x, R = [], []
    per_term: dict[str, list] = {t: [] for t in terms}
    starts = []
    for s in steps:
        starts.append(len(x))
        for h in s["history"]:
            x.append(len(x))
            R.append(h.get("R"))
            for t in terms:
                per_term[t].append(h.get("residuals", {}).get(t))
    fig = figure(*CONVERGENCE_SIZE)
    ax = fig.add_axes((0.1, 0.17, 0.62, 0.72))
    cmap = colormaps["tab10"]
    for k, t in enumerate(terms):
        ax.plot(x, _positive(per_term[t]), lw=0.8, color=cmap(k % 10), label=t,
                gid=f"term-{t}")
    ax.plot(x, _positive(R), lw=2.0, color="k", label="R (hard terms)", gid="R")
    for start in starts[1:]:
        ax.axvline(start - 0.5, color="0.6", lw=0.6, ls=":")
    ax.set_yscale("log")
    what = ("one solver run" if len(steps) == 1 else
            f"{len(steps)} solver runs in a row: handle steps, relaxation rounds,\n"
            "final projection; dotted: a run begins")
    ax.set_xlabel(f"iteration ({what})", fontsize=LABEL_PT)
    ax.set_ylabel("residual norm (mean edge 1)", fontsize=LABEL_PT)
    ax.grid(True, which="major", lw=0.3)
    ax.tick_params(labelsize=TICK_PT)
    ax.legend(fontsize=TICK_PT, loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    ax.set_title(title, fontsize=LABEL_PT + 1)
    return fig
