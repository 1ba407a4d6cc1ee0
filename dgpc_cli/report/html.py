"""The ``index.html`` of ``dgpc report``: plain HTML (no script), deterministic.

The page, top to bottom:

* a short header: what the artifact is, the inputs it was made from (each marked present,
  missing or changed since), its status;
* the figures (``<img>`` with relative links) with their captions;
* the metrics in three tables, geometry, fabrication and solver (:mod:`.tables`), with the unit
  of every value; under solver the convergence plot of the solver history (instead of its rows);
  the per-item records (parts, strips, classes, geodesics) as tables of their own, folded;
* the status (without the history).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from html import escape

from .tables import GROUPS, item_tables, scalar_rows, status_rows

__all__ = ["Header", "Section", "index_html", "overview_html"]

STYLE = ("body{font-family:sans-serif;margin:2em;max-width:75em}"
         "img{max-width:100%;border:1px solid #ccc}"
         "table{border-collapse:collapse;margin-bottom:1em}"
         "td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;vertical-align:top}"
         "td.v{font-family:monospace}"
         "table.head td:first-child{font-weight:bold;border:none}table.head td{border:none}"
         ".ok{color:#070}.bad{color:#b00}figcaption{margin:0.3em 0 1.5em}")
#: Status states that are a success (any other is shown in red).
GOOD_STATES = {"converged", "ok"}


@dataclass
class Header:
    """What the page is about: a sentence on the artifact, its inputs ``(name, path, note)``."""

    what: str
    inputs: list[tuple[str, str, str]] = field(default_factory=list)


def _rows(rows: list[tuple[str, str, str]]) -> list[str]:
    out = ["<table>", "<tr><th>name</th><th>value</th><th>unit</th></tr>"]
    out += [f'<tr><td>{escape(k)}</td><td class="v">{escape(v)}</td><td>{escape(u)}</td></tr>'
            for k, v, u in rows]
    out.append("</table>")
    return out


def _figure(href: str, caption: str) -> list[str]:
    return ["<figure>",
            f'<a href="{escape(href)}"><img src="{escape(href)}" alt="{escape(caption)}"></a>',
            f"<figcaption>{escape(caption)}</figcaption>",
            "</figure>"]


def _head(kind: str, source: str, header: Header, status: dict, units: str) -> list[str]:
    state = str(status.get("state", "")) if isinstance(status, dict) else ""
    message = str(status.get("message", "")) if isinstance(status, dict) else ""
    cls = "ok" if state in GOOD_STATES else "bad"
    lines = [f"<p>{escape(header.what)}</p>", '<table class="head">',
             f"<tr><td>artifact</td><td><code>{escape(source)}</code> (kind <b>{escape(kind)}"
             f"</b>, lengths in <b>{escape(units)}</b>)</td></tr>"]
    if header.inputs:
        items = "<br>".join(f"{escape(name)}: <code>{escape(path)}</code>"
                            + (f" ({escape(note)})" if note else "")
                            for name, path, note in header.inputs)
        lines.append(f"<tr><td>inputs</td><td>{items}</td></tr>")
    else:
        lines.append("<tr><td>inputs</td><td>none (made from scratch)</td></tr>")
    if state or message:
        text = escape(state) + (f": {escape(message)}" if message and message != state else "")
        lines.append(f'<tr><td>status</td><td class="{cls}">{text}</td></tr>')
    lines.append("</table>")
    return lines


def index_html(*, title: str, kind: str, source: str, header: Header,
               figures: list[tuple[str, str]], metrics: dict, status: dict, units: str,
               convergence: tuple[str, str] | None = None) -> bytes:
    """The page: ``figures`` as ``(relative href, caption)``, the metrics grouped, lengths in
    ``units``; ``convergence`` the ``(href, caption)`` of the convergence plot, if any."""
    lines = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             f"<title>{escape(title)}</title>", f"<style>{STYLE}</style>", "</head>", "<body>",
             f"<h1>{escape(title)}</h1>"]
    lines += _head(kind, source, header, status, units)
    lines.append("<h2>Figures</h2>")
    if not figures:
        lines.append("<p>(none)</p>")
    for href, caption in figures:
        lines += _figure(href, caption)
    lines.append("<h2>Metrics</h2>")
    groups = scalar_rows(metrics, units)
    for group in GROUPS:
        if not groups[group] and not (group == "solver" and convergence):
            continue
        lines.append(f'<h3 id="{group}">{group}</h3>')
        if groups[group]:
            lines += _rows(groups[group])
        if group == "solver" and convergence:
            lines += _figure(*convergence)
    for item_title, header_row, rows in item_tables(metrics, units):
        lines += [f"<details><summary>{escape(item_title)} ({len(rows)})</summary>", "<table>",
                  "<tr>" + "".join(f"<th>{escape(h)}</th>" for h in header_row) + "</tr>"]
        lines += ["<tr>" + "".join(f'<td class="v">{escape(c)}</td>' for c in row) + "</tr>"
                  for row in rows]
        lines += ["</table>", "</details>"]
    lines.append("<h2>Status</h2>")
    rows = status_rows(status)
    lines += _rows([(k, v, "") for k, v in rows]) if rows else ["<p>(none)</p>"]
    lines += ["</body>", "</html>", ""]
    return "\n".join(lines).encode("utf-8")


@dataclass
class Section:
    """One artifact on an overview page: its ``name``, ``kind``, the sentence on what it is,
    the ``href`` of its own page and its ``figures`` as ``(href, caption)``."""

    name: str
    kind: str
    what: str
    href: str
    figures: list[tuple[str, str]] = field(default_factory=list)


def overview_html(*, title: str, sections: list[Section]) -> bytes:
    """The page of several artifacts (``dgpc report A B C``): per artifact, in the order given,
    a heading, what it is, its figures and a link to its own page with its metrics."""
    lines = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             f"<title>{escape(title)}</title>", f"<style>{STYLE}</style>", "</head>", "<body>",
             f"<h1>{escape(title)}</h1>", "<ul>"]
    lines += [f'<li><a href="#{escape(s.name)}">{escape(s.name)}</a> ({escape(s.kind)}): '
              f"{escape(s.what)}</li>" for s in sections]
    lines.append("</ul>")
    for s in sections:
        lines += [f'<h2 id="{escape(s.name)}">{escape(s.name)} ({escape(s.kind)})</h2>',
                  f"<p>{escape(s.what)} Metrics and inputs: "
                  f'<a href="{escape(s.href)}">{escape(s.href)}</a>.</p>']
        for href, caption in s.figures:
            lines += _figure(href, caption)
    lines += ["</body>", "</html>", ""]
    return "\n".join(lines).encode("utf-8")
