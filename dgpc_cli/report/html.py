"""The ``index.html`` of ``dgpc report``: plain HTML (no script), deterministic.

The page shows each figure (``<img>`` with a relative link) with its caption, then the
artifact's ``metrics`` and ``status`` flattened to rows ``dotted.key → value`` with the unit of
every length, area and curvature among them (:func:`metric_unit`, the artifact's ``data.units``).
"""

from __future__ import annotations

import math
from html import escape

#: Lists of numbers longer than this are summarised (count, min, max) rather than listed.
LIST_MAX = 12
#: Metrics (last part of the dotted key) that are lengths in the artifact's unit.
LENGTHS = {"length", "width", "height", "profile_length", "radius_max", "radius_min",
           "total_length", "length_total", "length_max", "crossing_gap_max", "diagonal",
           "jacobi_residual_max", "vertex_distance_max", "mean_radius", "mean_abs", "max_mad",
           "net_to_reference_max", "net_to_reference_mean", "reference_to_net_max",
           "reference_to_net_mean"}
#: ... that are areas.
AREAS = {"total_area", "covered_area", "reference_area"}


def metric_unit(key: str, units: str) -> str:
    """The unit of the metric at the dotted ``key`` (``""``: a count, a ratio, an angle …)."""
    parts = key.split(".")
    head, last = parts[0], parts[-1].split("[")[0]
    if last in AREAS:
        return f"{units}²"
    if head == "gaussian_curvature":
        return f"1/{units}²"
    if (last in LENGTHS or (head in ("edges", "hausdorff") and last in ("min", "max", "mean"))
            or (head == "clairaut" and last in ("mean", "mad"))):
        return units
    return ""


def format_value(value) -> str:
    """One table cell: floats to 6 significant digits, ``null`` for None / non-finite."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}" if math.isfinite(value) else "null"
    return str(value)


def flatten(obj, prefix: str = "") -> list[tuple[str, str]]:
    """``(dotted key, formatted value)`` rows of a JSON value, keys sorted; list items as
    ``key[i]``; lists longer than :data:`LIST_MAX` summarised (numbers: count, min, max;
    records: count and the last one)."""
    if isinstance(obj, dict):
        rows: list[tuple[str, str]] = []
        for key in sorted(obj):
            rows += flatten(obj[key], f"{prefix}.{key}" if prefix else str(key))
        if not rows and prefix:
            rows = [(prefix, "{}")]
        return rows
    if isinstance(obj, list):
        if all(not isinstance(x, dict | list) for x in obj):
            numbers = [x for x in obj if isinstance(x, int | float) and not isinstance(x, bool)
                       and math.isfinite(x)]
            if len(obj) > LIST_MAX and numbers:
                return [(prefix, f"{len(obj)} values, min {format_value(float(min(numbers)))}, "
                                 f"max {format_value(float(max(numbers)))}")]
            return [(prefix, "[" + ", ".join(format_value(x) for x in obj) + "]")]
        if len(obj) > LIST_MAX:                 # e.g. an iteration history: its last entry
            return [(prefix, f"{len(obj)} entries, the last one below")] + \
                flatten(obj[-1], f"{prefix}[{len(obj) - 1}]")
        rows = []
        for i, item in enumerate(obj):
            rows += flatten(item, f"{prefix}[{i}]")
        return rows
    return [(prefix, format_value(obj))]


def _table(rows: list[tuple[str, str]], units: str) -> list[str]:
    if not rows:
        return ["<p>(none)</p>"]
    out = ["<table>", "<tr><th>name</th><th>value</th><th>unit</th></tr>"]
    out += [f"<tr><td>{escape(k)}</td><td>{escape(v)}</td>"
            f"<td>{escape(metric_unit(k, units))}</td></tr>" for k, v in rows]
    out.append("</table>")
    return out


def index_html(*, title: str, kind: str, source: str, figures: list[tuple[str, str]],
               metrics: dict, status: dict, units: str) -> bytes:
    """The page: ``figures`` as ``(relative href, caption)``, then metrics and status, lengths
    in ``units``."""
    lines = [
        "<!DOCTYPE html>",
        '<html lang="en">',
        "<head>",
        '<meta charset="utf-8">',
        f"<title>{escape(title)}</title>",
        "<style>body{font-family:sans-serif;margin:2em}img{max-width:100%;"
        "border:1px solid #ccc}table{border-collapse:collapse}td,th{border:1px solid #ccc;"
        "padding:2px 8px;text-align:left}td+td{font-family:monospace}</style>",
        "</head>",
        "<body>",
        f"<h1>{escape(title)}</h1>",
        f"<p>Artifact <code>{escape(source)}</code>, kind <b>{escape(kind)}</b>, lengths in "
        f"<b>{escape(units)}</b>.</p>",
        "<h2>Figures</h2>",
    ]
    if not figures:
        lines.append("<p>(none)</p>")
    for href, caption in figures:
        lines += ["<figure>",
                  f'<a href="{escape(href)}"><img src="{escape(href)}" '
                  f'alt="{escape(caption)}"></a>',
                  f"<figcaption>{escape(caption)}</figcaption>",
                  "</figure>"]
    lines.append("<h2>Metrics</h2>")
    lines += _table(flatten(metrics), units)
    lines.append("<h2>Status</h2>")
    lines += _table(flatten(status), units)
    lines += ["</body>", "</html>", ""]
    return "\n".join(lines).encode("utf-8")
