"""``DIR/batch.json`` and ``DIR/index.html`` of a batch.

``batch.json`` (sorted keys, deterministic but for ``this_run``):

* ``status`` (``ok``, ``not_converged``, ``failed``) and ``exit_code`` (0, 3, 1) of the batch;
* ``patches``: per patch its ``status``, ``message`` (the first failure, one line, with the
  task), key ``metrics`` of its artifacts, ``outputs`` (role → file in DIR) and ``tasks``;
  ``shared`` the same for the molds and the nesting;
* ``tasks``: per task the ``command`` (``dgpc`` arguments, run from the folder the batch was
  started in), ``fingerprint``, ``exit_code``, ``status``, ``message``, ``warnings`` and
  ``outputs`` (file → sha256) — what the next run compares to skip it;
* ``this_run``: what changes from run to run: wall times (per task, per patch as the sum of
  its tasks', and of the whole batch), which tasks ran and which were reused, the cluster.
"""

from __future__ import annotations

import html
import json
import os
from pathlib import Path

from dgpc_cli.io.artifact import created_by, dumps_json, sha256_file
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.jsonable import dotted

from .graph import Task, patch_outputs
from .project import SHARED, Project

#: Worst first: the status of a group is the worst of its tasks'.
ORDER = ("failed", "blocked", "not_converged", "ok")
#: Key metrics per role: name in batch.json → dotted path in the artifact's metrics.
KEY_METRICS = {
    "net": {"R": "R", "max_strain": "strain.max", "gpc_angle_defect_max":
            "gpc_angle_defect_max", "pleat_max": "pleat_max"},
    "base": {"R": "R"},
    "strips": {"max_planarity_diagonal_relative": "max_planarity_diagonal_relative"},
    "flat": {"n_parts": "n_parts", "n_classes": "n_classes",
             "max_congruence_error": "max_congruence_error"},
    "mold": {"isometry_error_max": "isometry_error_max", "pieces": "pieces",
             "panels": "panels", "panels_flat": "panels_flat"},
    "sheets": {"sheet_count": "sheet_count", "n_parts": "n_parts",
               "utilization": "utilization", "classes": "classes"},
}


def artifact_metrics(path: Path, role: str) -> dict:
    """Key metrics of the artifact ``path`` (its role picks them), with its ``state``."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return {}
    out = {name: dotted(doc.get("metrics", {}), path)
           for name, path in KEY_METRICS.get(role, {}).items()}
    out = {k: v for k, v in out.items() if v is not None}
    state = dotted(doc, "status.state")
    if state is not None:
        out["state"] = state
    return out


def _group(tasks: dict[str, Task], records: dict[str, dict], group: str, out: Path) -> dict:
    ids = [tid for tid, t in tasks.items() if t.group == group]
    status = min((records[t]["status"] for t in ids), key=ORDER.index)
    first = next((t for t in ids if records[t]["status"] == status and status != "ok"), None)
    message = f"{first}: {records[first]['message']}" if first else ""
    outputs = patch_outputs(tasks, group)
    metrics = {}
    for role, rel in outputs.items():
        task = next(t for t in ids if tasks[t].artifact == rel)
        if rel.endswith(".json") and records[task]["exit_code"] in (0, 3):
            kind = "mold" if role.startswith("mold-") else role
            metrics[role] = artifact_metrics(out / rel, kind)
    return {"status": status, "message": message, "metrics": metrics, "outputs": outputs,
            "tasks": ids}


def exit_code(records: dict[str, dict]) -> int:
    """0 when every task succeeded, 3 when some only missed a tolerance, 1 otherwise."""
    codes = {r["exit_code"] for r in records.values()}
    if codes <= {0}:
        return 0
    return 3 if codes <= {0, 3} else 1


def batch_doc(project: Project, tasks: dict[str, Task], records: dict[str, dict],
              executed: dict[str, bool], out: Path, *, wall_time_s: float,
              cluster: dict) -> dict:
    """The content of ``batch.json``; see the module."""
    out = Path(out)
    groups = list(dict.fromkeys(t.group for t in tasks.values()))
    code = exit_code(records)
    keep = ("command", "fingerprint", "exit_code", "status", "message", "warnings", "outputs")
    task_records = {tid: {k: records[tid].get(k) for k in keep} for tid in tasks}
    patches = {g: _group(tasks, records, g, out) for g in groups if g != SHARED}
    doc = {
        "created_by": created_by(),
        "project": {"path": Path(os.path.relpath(project.path.resolve(), out.resolve()))
                    .as_posix(), "sha256": sha256_file(project.path)},
        "status": {0: "ok", 3: "not_converged"}.get(code, "failed"),
        "exit_code": code,
        "patches": patches,
        "tasks": task_records,
        "this_run": {
            "about": "what changes from run to run: wall times in seconds (a reused task "
                     "keeps the time it took when it ran), which tasks ran, the cluster",
            "wall_time_s": wall_time_s,
            "cluster": cluster,
            "executed": [t for t in tasks if executed.get(t)],
            "reused": [t for t in tasks if not executed.get(t)
                       and records[t]["status"] != "blocked"],
            "patches": {g: {"wall_time_s": sum(records[t]["wall_time_s"]
                                               for t in patches[g]["tasks"])}
                        for g in patches},
            "tasks": {tid: {"wall_time_s": records[tid]["wall_time_s"],
                            "executed": bool(executed.get(tid))} for tid in tasks},
        },
    }
    if SHARED in groups:
        doc["shared"] = _group(tasks, records, SHARED, out)
    return doc


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, dict):
        return ", ".join(f"{k} × {v}" for k, v in value.items())
    return str(value)


def _row(name: str, group: dict, link: str | None) -> str:
    metrics = "; ".join(f"{role}: " + ", ".join(f"{k} {_cell(v)}" for k, v in m.items())
                        for role, m in group["metrics"].items() if m)
    label = (f'<a href="{html.escape(link)}">{html.escape(name)}</a>' if link
             else html.escape(name))
    return (f"<tr class=\"{group['status']}\"><td>{label}</td><td>{group['status']}</td>"
            f"<td>{html.escape(metrics)}</td><td>{html.escape(group['message'])}</td></tr>")


def index_html(doc: dict, out: Path) -> str:
    """A page linking every patch's report and the shared stages' reports."""
    rows = []
    for name, group in doc["patches"].items():
        link = group["outputs"].get("report")
        rows.append(_row(name, group, link if link and (out / link).is_file() else None))
    shared = []
    if "shared" in doc:
        group = doc["shared"]
        rows.append(_row(SHARED, group, None))
        for key, rel in group["outputs"].items():
            if key.endswith("_report") and (out / rel).is_file():
                shared.append(f'<li><a href="{html.escape(rel)}">{html.escape(key[:-7])}'
                              "</a></li>")
    title = html.escape(Path(doc["project"]["path"]).name)
    return "\n".join([
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        f"<title>dgpc batch: {title}</title>",
        "<style>body{font-family:sans-serif}td,th{padding:2px 8px;text-align:left;"
        "vertical-align:top}.failed td,.blocked td{color:#b00}.not_converged td{color:#a60}"
        "</style></head><body>",
        f"<h1>dgpc batch: {title}</h1>",
        f"<p>status: {doc['status']} (exit {doc['exit_code']}); {len(doc['patches'])} "
        "patches (each links to its figures); details in "
        '<a href="batch.json">batch.json</a>.</p>',
        "<table><tr><th>patch</th><th>status</th><th>key metrics</th><th>message</th></tr>",
        *rows, "</table>",
        *(["<h2>shared stages</h2><ul>", *shared, "</ul>"] if shared else []),
        "</body></html>", ""])


def write_summary(doc: dict, out: Path, announce=None) -> Path:
    """Write ``batch.json`` and ``index.html`` into ``out`` (atomically); the JSON's path.
    ``announce(path)`` prints the JSON's path at their commit (nothing is written when it
    fails)."""
    out = Path(out)
    path = out / "batch.json"
    write_files({path: dumps_json(doc), out / "index.html": index_html(doc, out).encode()},
                force=True, announce=None if announce is None else lambda: announce(path))
    return path
