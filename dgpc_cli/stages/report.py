"""``dgpc report``: figures of an artifact and an ``index.html`` with its metrics (SPEC §2).

Files written for ``-o PREFIX`` (each kind also gets ``PREFIX-index.html``):

* net: ``PREFIX-width.png`` (strip width), ``PREFIX-curvature.png`` (discrete Gaussian
  curvature, red/blue/white as Fig. 17), ``PREFIX-strain.png`` when the net comes from
  ``optimize --mode isometric`` and its input net (``inputs.net``) is still there unchanged
  (Fig. 13), ``PREFIX-clairaut.png`` when the net records an axis in ``data.surface.axis``
  (Fig. 11) — see :mod:`dgpc_cli.report.net`;
* strips: ``PREFIX-width.png``, the planar-quad strips coloured by their width;
* flat: ``PREFIX-overlay.png`` and ``PREFIX-strips.png``:

  - overlay: every part aligned on its class representative (Fig. 18 bottom-right: "Overlay of
    all strips ... implying congruent strips"), one panel per class;
  - strips: the parts side by side, each with its rulings (score lines) and id (Fig. 18
    bottom-left);

* mold: ``PREFIX-profile.png``, the meridian profile;
* laths: ``PREFIX-laths.png``, the two lath families of a gridshell in 3-D (Fig. 14);
* sheets: no new figure; the index links the sheet previews that ``nest`` wrote.

Rendered with matplotlib's Agg backend, without metadata that would change between runs.
"""

from __future__ import annotations

import logging
import os
import re
from pathlib import Path

import numpy as np

from dgpc_cli.io.artifact import resolve_input, sha256_file
from dgpc_cli.report.html import index_html
from dgpc_cli.report.render import DPI, figure, png_bytes

__all__ = ["DPI", "overlay_png", "report_files", "strips_png"]

log = logging.getLogger(__name__)

def _closed(ring):
    ring = np.asarray(ring, float)
    return np.concatenate([ring, ring[:1]])


def _aligned_points(part, points):
    al = part["alignment"]
    R, t = np.asarray(al["matrix"], float), np.asarray(al["translation"], float)
    return np.asarray(points, float) @ R.T + t


def overlay_png(parts: list[dict], classes: list[dict], units: str) -> bytes:
    """PNG of all parts aligned on their class representatives, one panel per class."""
    by_id = {p["id"]: p for p in parts}
    k = len(classes)
    fig = figure(8.0, 2.2 * k + 0.6)
    for row, cls in enumerate(classes):
        ax = fig.add_subplot(k, 1, row + 1)
        for pid in cls["members"]:
            part = by_id[pid]
            ax.plot(*_closed(_aligned_points(part, part["outline"])).T, lw=0.6, alpha=0.7)
            for seg in part["score"]:
                ax.plot(*_aligned_points(part, seg).T, lw=0.3, color="0.5", alpha=0.5)
        ax.set_aspect("equal")
        ax.set_title(f"{cls['id']}: {cls['quantity']} × {cls['representative']}, max error "
                     f"{cls['max_relative_error']:.2e} of the length", fontsize=8)
        _length_axes(ax, units)
    fig.tight_layout()
    return png_bytes(fig)


def _length_axes(ax, units: str) -> None:
    ax.set_xlabel(f"x [{units}]", fontsize=7)
    ax.set_ylabel(f"y [{units}]", fontsize=7)
    ax.tick_params(labelsize=6)


def strips_png(parts: list[dict], units: str) -> bytes:
    """PNG of the parts side by side (as in the flat artifact's 3dm), with rulings and ids."""
    from dgpc_cli.io.flat import side_by_side

    fig = figure(8.0, min(2.0 + 0.35 * len(parts), 40.0))
    ax = fig.add_subplot(1, 1, 1)
    for part, shift in zip(parts, side_by_side([p["outline"] for p in parts]), strict=True):
        outline = np.asarray(part["outline"], float)
        ax.fill(*(outline + shift).T, facecolor="0.92", edgecolor="k", lw=0.5)
        for seg in part["score"]:
            ax.plot(*(np.asarray(seg, float) + shift).T, lw=0.3, color="tab:blue")
        lx, ly = np.asarray(part["label"], float) + shift
        ax.text(lx, ly, f"{part['id']} ({part['class']})", fontsize=5, ha="center",
                va="center")
    ax.set_aspect("equal")
    _length_axes(ax, units)
    fig.tight_layout()
    return png_bytes(fig)


# --------------------------------------------------------------------------------------------
# every kind: (name, caption, PNG bytes) figures, then the index


def _net_figures(json_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.net import read_net
    from dgpc_cli.metrics.clairaut import clairaut_values
    from dgpc_cli.metrics.strain import strain
    from dgpc_cli.report.net import (
        clairaut_png,
        curvature_per_quad,
        grids_png,
        vertex_to_quad,
        width_per_quad,
    )
    from dgpc_cli.stages.inspect import recorded_axis

    net = read_net(json_path)
    f, u = net.f, net.units
    m, n = net.shape
    figs = [
        ("width", "Strip width per quad (mean of its two v-edges), paper §3.1.",
         grids_png([f], [width_per_quad(f)], title=f"strip width, {m}×{n} net",
                   label=f"strip width [{u}]")),
        ("curvature", "Discrete Gaussian curvature K = −∂uu w / w (Jacobi equation (1)): red "
                      "positive, blue negative, white ≈ 0 (paper Fig. 17); grey: undefined.",
         grids_png([f], [curvature_per_quad(f)], title="discrete Gaussian curvature K",
                   label=f"K [1/{u}²]", diverging=True)),
    ]
    against = _isometry_input(net, json_path)
    if against is not None:
        amount, summary = strain(f, against.f)
        figs.append(("strain", "Strain |λ1| + |λ2| against the input net of the isometric "
                               f"optimization (paper Fig. 13), max {summary['max']:.3g}.",
                     grids_png([f], [vertex_to_quad(amount)],
                               title="strain against the input net", label="|λ1| + |λ2|")))
    axis = recorded_axis(net)
    if axis is not None:
        values = clairaut_values(f, axis)
        figs.append(("clairaut", "Clairaut's relation (9): r cos α along each geodesic, "
                                 "constant on a surface of revolution (paper Fig. 11).",
                     clairaut_png(values, f, title="r cos α along the geodesics", units=u)))
    return figs, net.metrics, net.status, u


def _isometry_input(net, json_path: Path):
    """The input net of an isometric optimization, if recorded and present unchanged."""
    from dgpc_cli.io.net import read_net

    record = net.inputs.get("net")
    if net.parameters.get("mode") != "isometric" or not record:
        return None
    path = resolve_input(record, json_path)
    if not path.is_file():
        log.warning("%s: input net %s is missing; no strain figure", json_path, record["path"])
        return None
    if record.get("sha256") and sha256_file(path) != record["sha256"]:
        log.warning("%s: input net %s changed since; no strain figure", json_path,
                    record["path"])
        return None
    other = read_net(path)
    if other.shape != net.shape:
        log.warning("%s: input net %s has another shape; no strain figure", json_path,
                    record["path"])
        return None
    return other


def _strips_figures(json_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.strips import read_strips
    from dgpc_cli.report.net import grids_png, width_per_quad

    art = read_strips(json_path)
    grids = [np.stack([np.asarray(A, float), np.asarray(B, float)], axis=1)
             for A, B in art.geometry]
    figs = [("width", "The planar-quad strips, each quad coloured by the strip width.",
             grids_png(grids, [width_per_quad(g) for g in grids],
                       title=f"{len(grids)} planar-quad strips",
                       label=f"strip width [{art.units}]"))]
    return figs, art.metrics, art.status, art.units


def _flat_figures(json_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.flat import read_flat

    flat = read_flat(json_path)
    figs = [("overlay", "Every part aligned on its class representative (paper Fig. 18 "
                        "bottom-right).", overlay_png(flat.parts, flat.classes, flat.units)),
            ("strips", "The developed parts side by side with their rulings (paper Fig. 18 "
                       "bottom-left).", strips_png(flat.parts, flat.units))]
    return figs, flat.metrics, flat.status, flat.units


def _mold_figures(json_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.mold import read_mold
    from dgpc_cli.report.net import profile_png

    mold = read_mold(json_path)
    figs = [("profile", f"The mold's meridian profile (r, h in {mold.units}) with the axis of "
                        "revolution.",
             profile_png(mold.r, mold.h, unit=mold.units, title="mold meridian profile"))]
    return figs, mold.metrics, mold.status, mold.units


def _sheets_links(json_path: Path, html_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.sheets import read_sheets

    art = read_sheets(json_path)
    links = []
    folder = html_path.resolve().parent
    for i, sheet in enumerate(art.data["sheets"]):
        target = art.file(sheet["png"])
        href = Path(os.path.relpath(target.resolve(), folder)).as_posix()
        links.append((href, f"Sheet {i + 1} of {len(art.data['sheets'])} (preview written by "
                            "dgpc nest)."))
    return links, art.metrics, art.status, art.data["units"]


def _laths_figures(json_path: Path) -> tuple[list, dict, dict, str]:
    from dgpc_cli.io.laths import read_laths
    from dgpc_cli.report.net import polylines_png

    art = read_laths(json_path)
    a, b = art.family("A"), art.family("B")
    title = (f"{len(a)} + {len(b)} laths, {art.data['crossings']} crossings (lengths in "
             f"{art.data['units']})")
    figs = [("laths", "The two lath families (the u-line geodesics of the two nets, paper "
                      "Fig. 14); the cut list is beside the artifact.",
             polylines_png([a, b], [f"family A ({len(a)})", f"family B ({len(b)})"],
                           title=title))]
    return figs, art.metrics, art.status, art.data["units"]


FIGURES = {"net": _net_figures, "strips": _strips_figures, "flat": _flat_figures,
           "mold": _mold_figures, "laths": _laths_figures}


def _prefix_text(prefix: Path) -> str:
    text = str(prefix)
    for suffix in (".png", ".html"):
        if text.lower().endswith(suffix):
            return text[: -len(suffix)]
    return text


def previous_report_files(prefix: Path) -> list[Path]:
    """The figures that an earlier report of ``-o PREFIX`` wrote: the ``PREFIX-*.png`` its
    ``PREFIX-index.html`` links (in its folder only; none when there is no such index), for
    ``--force`` to remove those the new report does not write."""
    html_path = Path(_prefix_text(prefix) + "-index.html")
    try:
        html = html_path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return []
    start = html_path.name[: -len("index.html")]
    names = set(re.findall(r'src="([^"/\\]+\.png)"', html))
    return [html_path.parent / n for n in sorted(names) if n.startswith(start)]


def report_files(json_path: Path, kind: str, prefix: Path) -> dict[Path, bytes]:
    """Every file of the report of the ``kind`` artifact ``json_path`` for ``-o PREFIX``:
    ``PREFIX-<figure>.png`` and last ``PREFIX-index.html`` (nothing written)."""
    text = _prefix_text(prefix)
    html_path = Path(text + "-index.html")
    files: dict[Path, bytes] = {}
    if kind == "sheets":
        links, metrics, status, units = _sheets_links(json_path, html_path)
    else:
        figs, metrics, status, units = FIGURES[kind](json_path)
        links = []
        for name, caption, data in figs:
            path = Path(f"{text}-{name}.png")
            files[path] = data
            links.append((path.name, caption))
    files[html_path] = index_html(title=f"dgpc report: {json_path.name}", kind=kind,
                                  source=json_path.name, figures=links, metrics=metrics,
                                  status=status, units=units)
    return files
