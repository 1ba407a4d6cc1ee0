"""The metrics of an artifact as tables: grouped, with units, per-item records as their own tables.

* :func:`group_of` puts every top-level metric into ``geometry`` (the shape and how well it
  meets the paper's conditions), ``fabrication`` (what a fabricator checks: strain against the
  input, panel errors against the mold, u-spread, pleats, departure from a surface of revolution,
  handle misses, planarity, congruence, sheets) or ``solver`` (R and the residual per term).
* :func:`metric_unit` names the unit of a metric (``data.units`` for lengths).
* :func:`scalar_rows` flattens a group to ``dotted key → value`` rows; records per item
  (``per_part``, ``per_strip``, ``classes``, ``clairaut.per_geodesic``) are left out of it and
  become tables of their own (:func:`item_tables`), one row per item.
"""

from __future__ import annotations

import math

from ..io.jsonable import dotted

__all__ = ["GROUPS", "flatten", "format_value", "group_of", "item_tables", "metric_unit",
           "scalar_rows", "status_rows"]

GROUPS = ("geometry", "fabrication", "solver")
#: Top-level metrics of the solver group.
SOLVER = {"R", "residuals", "polished"}
#: Top-level metrics of the fabrication group (of every kind).
FABRICATION = {
    # nets
    "u_spread_max", "pleat_max", "crease_max", "parallel_departure", "mold_panel_error",
    "panel_error_against", "handle_miss", "strain",
    # strips, flat parts
    "max_planarity_diagonal_relative", "max_deviation_relative", "max_congruence_error",
    "max_congruence_deviation_mm", "max_strain", "max_straightness_relative", "n_classes",
    "n_parts", "classes", "per_part", "per_strip", "total_area_m2", "total_length_mm",
    "fabrication",
    # molds
    "pieces", "panels", "panels_flat", "panels_curved", "isometry_error_max",
    "sector_angle_deg",
    # sheets, laths
    "sheet_count", "utilization", "utilization_per_sheet", "laths", "crossings",
    "crossing_gap_max", "length_max", "length_total",
}
#: Records per item: (dotted key, title); dicts of records, or a dict of equally long lists.
ITEMS = {"per_part": "per part", "per_strip": "per strip", "classes": "congruence classes",
         "clairaut.per_geodesic": "Clairaut per geodesic",
         "fabrication.per_strip": "fabrication per strip"}
#: Lists of numbers longer than this are summarised (count, min, max) rather than listed.
LIST_MAX = 12
#: Metrics (last part of the dotted key) that are lengths in the artifact's unit; the strips'
#: and flat parts' metrics name their unit instead (``_mm``, ``_deg``, ``_m2``, ``_relative``).
LENGTHS = {"length", "width", "height", "profile_length", "radius_max", "radius_min",
           "length_total", "length_max", "crossing_gap_max", "diagonal",
           "jacobi_residual_max", "vertex_distance_max", "mean_radius", "mean_abs", "max_mad",
           "net_to_reference_max", "net_to_reference_mean", "reference_to_net_max",
           "reference_to_net_mean", "mad", "meridian_length"}
#: ... that are areas.
AREAS = {"covered_area", "reference_area", "area"}
#: Metrics relative to a length other than the strip's width (``_relative`` alone: a share
#: of the (mean) strip width, or a plain ratio): the planarity defect over the quad's mean
#: diagonal, the straightness of a developed geodesic over its length.
RELATIVE = {"_diagonal_relative": "× diagonal", "straightness_relative": "× length",
            "deviation_relative": "× width", "planarity_relative": "× width",
            "seam_step_relative": "× width"}
#: Heads whose min / max / mean are lengths.
LENGTH_STATS = {"edges", "hausdorff", "parallel_departure", "handle_miss"}


def group_of(key: str) -> str:
    """The group of the top-level metric ``key``."""
    if key in SOLVER:
        return "solver"
    if key in FABRICATION:
        return "fabrication"
    return "geometry"


def metric_unit(key: str, units: str) -> str:
    """The unit of the metric at the dotted ``key`` (``""``: a count, a ratio, an index …)."""
    parts = key.split(".")
    head, last = parts[0], parts[-1].split("[")[0]
    relative = next((unit for end, unit in RELATIVE.items() if last.endswith(end)), None)
    if relative is not None:
        return relative
    if last in AREAS:
        return f"{units}²"
    if head == "gaussian_curvature":
        return f"1/{units}²"
    if last in ("relative", "relative_mad", "max_relative_mad", "max_mad_over_radius",
                "relative_error", "max_relative_error", "min_ratio") or last.endswith("_relative"):
        return ""
    if (last in LENGTHS or (head in LENGTH_STATS and last in ("min", "max", "mean"))
            or (head == "clairaut" and last == "mean")):
        return units
    if last == "gpc_angle_defect_max":
        return "rad"
    if last.endswith("_deg"):
        return "°"
    if last.endswith("_mm"):
        return "mm"
    if last.endswith("_m2"):
        return "m²"
    if last in ("pleat_max", "crease_max"):
        return "mean edges"
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


def _without_items(metrics: dict) -> dict:
    out = {k: v for k, v in metrics.items() if k not in ITEMS}
    for key in ITEMS:
        head, _, rest = key.partition(".")
        if rest and isinstance(out.get(head), dict):
            out[head] = {k: v for k, v in out[head].items() if k != rest}
    return out


def scalar_rows(metrics: dict, units: str) -> dict[str, list[tuple[str, str, str]]]:
    """Per group (:data:`GROUPS`, in order) the rows ``(dotted key, value, unit)`` of the
    metrics, without the per-item records."""
    rest = _without_items(metrics)
    out: dict[str, list] = {g: [] for g in GROUPS}
    for key in sorted(rest):
        for name, value in flatten(rest[key], key):
            out[group_of(key)].append((name, value, metric_unit(name, units)))
    return out


def item_tables(metrics: dict, units: str) -> list[tuple[str, list[str], list[list[str]]]]:
    """The per-item records as tables ``(title, header, rows)``: one row per item, a column per
    field (header ``field [unit]``)."""
    tables = []
    for key, title in ITEMS.items():
        node = dotted(metrics, key)
        if isinstance(node, dict) and node and all(isinstance(v, dict) for v in node.values()):
            fields = sorted({f for v in node.values() for f in v})
            rows = [[item] + [_cell(v.get(f)) for f in fields] for item, v in sorted(node.items())]
            name = "id"
        elif isinstance(node, dict) and node and all(isinstance(v, list) for v in node.values()):
            fields = [f for f in sorted(node) if f != "v"]
            count = max(len(v) for v in node.values())
            items = node.get("v", list(range(count)))
            rows = [[format_value(items[i])] + [_cell(node[f][i] if i < len(node[f]) else None)
                                               for f in fields] for i in range(count)]
            name = "v"
        else:
            continue
        header = [name] + [_with_unit(f, metric_unit(f"{key}.{f}", units)) for f in fields]
        tables.append((title, header, rows))
    return tables


def _with_unit(field: str, unit: str) -> str:
    return f"{field} [{unit}]" if unit else field


def _cell(value) -> str:
    if isinstance(value, list):
        return ", ".join(format_value(x) for x in value)
    return format_value(value)


def status_rows(status: dict) -> list[tuple[str, str]]:
    """The status without the solver history (the convergence plot shows it): the steps as
    their count and iterations."""
    rest = {k: v for k, v in status.items() if k != "steps"}
    rows = flatten(rest)
    steps = status.get("steps")
    if isinstance(steps, list) and steps:
        its = [s.get("iterations") for s in steps if isinstance(s, dict)]
        text = ", ".join(format_value(i) for i in its[:LIST_MAX])
        more = ", …" if len(its) > LIST_MAX else ""
        rows.append(("steps", f"{len(steps)} (iterations {text}{more})"))
    return rows
