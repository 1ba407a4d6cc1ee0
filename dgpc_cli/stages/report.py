"""``dgpc report``: figures of an artifact and an ``index.html`` with its metrics (SPEC §2).

Files written for ``-o PREFIX`` (every kind also gets ``PREFIX-index.html``); the 3-D figures
show the model in three framed views with a scale bar (:mod:`dgpc_cli.report.views`):

* net: ``PREFIX-width.png`` (strip width), ``PREFIX-curvature.png`` (discrete Gaussian
  curvature, red/blue/white as Fig. 17), ``PREFIX-coverage.png`` when the net records a
  reference mesh that is still there (``data.reference``): the net over the reference, the
  uncovered part of the reference in orange; ``PREFIX-strain.png`` when the net comes from
  ``optimize --mode isometric`` and its input net (``inputs.net``) is still there unchanged
  (Fig. 13: principal directions over |λ1| + |λ2|); ``PREFIX-patches.png`` when the net was
  made on one patch of a split reference (``init --patches``, ``data.patches``): its patch
  in the whole mesh and the cut curves in red; ``PREFIX-clairaut.png`` when the net
  records an axis in ``data.surface.axis`` (Fig. 11, the geodesics the metric checks);
  ``PREFIX-convergence.png`` when it records a solver history (``status.steps``);
* strips: ``PREFIX-width.png``, the planar-quad strips coloured by their width; when the net
  (``inputs.net``) is there unchanged, paper Fig. 18: ``PREFIX-template.png`` (every developed
  strip overlaid on the template, the first one, its ends magnified) and
  ``PREFIX-deviation.png`` (the strips coloured by their deviation from the net in mm, the
  seams stepping more than 1 % of the strip width in red);
* flat: ``PREFIX-overlay.png`` (every part on its class representative, one cell per class,
  Fig. 18 bottom-right) and ``PREFIX-strips.png`` (the parts laid out like a sheet, Fig. 18
  bottom-left);
* mold: ``PREFIX-profile.png`` (the meridian), ``PREFIX-pairing-netK.png`` per design net (its
  panels on the mold and on the design in one colour each, Fig. 16) and ``PREFIX-pieces.png``
  (the mold pieces and the flat panels, Fig. 17);
* laths: ``PREFIX-laths.png``, the two lath families of a gridshell (Fig. 14);
* sheets: ``PREFIX-sheetNN.png`` per sheet and ``PREFIX-moldmap.png`` (with ``nest --mold``):
  the previews ``nest`` wrote, at 100 %, with a legend of their layers.

Figures are made with matplotlib's Agg backend in its default style
(:func:`dgpc_cli.report.render.style`); the same artifact gives the same bytes on every run.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dgpc_cli.io.artifact import listed_path, resolve_input, sha256_file
from dgpc_cli.report.html import Header, Section, index_html, overview_html
from dgpc_cli.report.render import png_bytes, style
from dgpc_cli.report.words import counted

__all__ = ["overview_files", "report_files"]

log = logging.getLogger(__name__)


@dataclass
class Page:
    """What the report of one artifact shows: ``figures`` as ``(name, caption, make)`` with
    ``make()`` returning a matplotlib Figure, the envelope's fields and a header."""

    figures: list[tuple[str, str, Callable]]
    metrics: dict
    status: dict
    units: str
    header: Header
    convergence: tuple[str, str, Callable] | None = None
    inputs: dict = field(default_factory=dict)


def _input_notes(inputs: dict, json_path: Path) -> list[tuple[str, str, str]]:
    out = []
    for name in sorted(inputs):
        record = inputs[name]
        if not isinstance(record, dict) or "path" not in record:
            continue
        path = resolve_input(record, json_path)
        if not path.is_file():
            note = "missing"
        elif record.get("sha256") and sha256_file(path) != record["sha256"]:
            note = "changed since"
        else:
            note = "present"
        out.append((name, record["path"], note))
    return out


def _convergence(status: dict):
    from dgpc_cli.report.convergence import convergence_figure, has_history

    if not has_history(status):
        return None
    return ("convergence", "The solver's convergence: R and every term's residual norm per "
                           "iteration, handle steps one after the other.",
            lambda: convergence_figure(status, title="solver convergence"))


# --------------------------------------------------------------------------------------------
# nets


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


def _reference(net, json_path: Path):
    """The net's recorded reference with the share of each face the net covers, or None."""
    from dgpc_cli.metrics.coverage import covered_faces
    from dgpc_cli.report.net import Reference
    from dgpc_cli.stages.inspect import recorded_reference

    mesh = recorded_reference(net, json_path)
    if mesh is None:
        return None
    record = net.metrics.get("coverage") or {}
    # the faces covered to the tolerance the recorded figure was measured with
    return Reference(mesh.vertices, mesh.faces,
                     covered_faces(net.f, mesh.vertices, mesh.faces,
                                   tolerance=record.get("tolerance")),
                     record.get("area_fraction"))


def _whole_mesh(net, json_path: Path, depth: int = 4):
    """The whole mesh a patch net was cut from (``inputs.mesh``, of the net or of the nets it
    was made from), if it is there unchanged; else None."""
    from dgpc_cli.io.artifact import recorded_file, resolve_input
    from dgpc_cli.io.mesh import load_mesh
    from dgpc_cli.io.net import read_net

    for _ in range(depth):
        record = net.inputs.get("mesh")
        if isinstance(record, dict) and resolve_input(record, json_path).is_file():
            return load_mesh(recorded_file(record, json_path, "inputs.mesh"))
        record = net.inputs.get("net")
        if not isinstance(record, dict) or not resolve_input(record, json_path).is_file():
            return None
        json_path = recorded_file(record, json_path, "inputs.net")
        net = read_net(json_path)
    return None


def _patches_entry(net, json_path: Path, split: dict, view: dict):
    """The figure of a patch net (``init --patches``): its patch in the whole mesh, the cuts."""
    from dgpc_cli.report.patches import patches_figure
    from dgpc_cli.stages.inspect import recorded_reference

    patch = recorded_reference(net, json_path)
    whole = _whole_mesh(net, json_path)
    curves = [c for cut in split["cuts"] for c in cut.get("curves", [])]
    single = split.get("single") or {}
    ratio = single.get("width_ratio")
    caption = (f"The reference split into {split.get('count')} patches along the red curves: "
               f"{split.get('reason', '')}. This net ({split.get('name', '?')}) clads the blue "
               "patch; `planarize-strips --trim` clips its strips to that patch's outline.")
    title = (f"patch {split.get('name', '?')} of {split.get('count')}"
             + (f" (one net: strips vary {ratio:.2f}x)" if isinstance(ratio, float) else ""))
    return ("patches", caption,
            lambda: patches_figure(net.f, None if patch is None else (patch.vertices,
                                                                       patch.faces),
                                   None if whole is None else (whole.vertices, whole.faces),
                                   curves, title=title, **view))


def _recorded_clairaut(metrics: dict) -> dict | None:
    """The artifact's own Clairaut metric (the figure shows its numbers), if it has one."""
    record = metrics.get("clairaut")
    if isinstance(record, dict) and isinstance(record.get("per_geodesic"), dict):
        return record
    return None


def _net_page(json_path: Path) -> Page:
    from dgpc_cli.io.net import read_net
    from dgpc_cli.metrics.clairaut import clairaut, clairaut_values
    from dgpc_cli.report import net as fig
    from dgpc_cli.report.camera import outward_front
    from dgpc_cli.report.clairaut import clairaut_figure
    from dgpc_cli.report.scene import grid_quads
    from dgpc_cli.stages.inspect import recorded_axis

    net = read_net(json_path)
    f, u = net.f, net.units
    m, n = net.shape
    axis = recorded_axis(net)
    up = axis[1] if axis is not None else (0.0, 0.0, 1.0)
    front = outward_front(grid_quads(f), up)
    view = {"up": up, "front": front, "unit": u}
    figs = [
        ("width", "Strip width per quad (mean of its two v-edges), paper §3.1.",
         lambda: fig.field_figure([f], [fig.width_per_quad(f)], label=f"strip width [{u}]",
                                  title=f"strip width, {m}×{n} net", **view)),
        ("curvature", "Discrete Gaussian curvature K = −∂uu w / w (Jacobi equation (1)): red "
                      "positive, blue negative, white ≈ 0 (paper Fig. 17); grey: undefined.",
         lambda: fig.field_figure([f], [fig.curvature_per_quad(f)], label=f"K [1/{u}²]",
                                  title="discrete Gaussian curvature K", diverging=True,
                                  **view)),
    ]
    reference = _reference(net, json_path)
    if reference is not None:
        share = 100 * reference.share
        figs.append(("coverage", f"The net over its reference mesh: {share:.1f} % of the "
                                 "reference is covered (grey), the rest (orange) is not.",
                     lambda: fig.field_figure([f], [fig.width_per_quad(f)],
                                              label=f"strip width [{u}]",
                                              title=f"net over its reference ({share:.1f} % "
                                                    "covered)", reference=reference, **view)))
    split = net.data.get("patches")
    if isinstance(split, dict) and split.get("cuts"):
        figs.append(_patches_entry(net, json_path, split, view))
    against = _isometry_input(net, json_path)
    if against is not None:
        figs.append(("strain", "Strain against the input net of the isometric optimization "
                               "(paper Fig. 13): principal directions at the interior vertices, "
                               "as long as their eigenvalues (the longest capped), over the "
                               "colour of |λ1| + |λ2|, the handles marked; beside it the start "
                               "shape with each handle's move.",
                     lambda: fig.strain_figure(f, against.f, title="strain against the input "
                                                                   "net",
                                               handles=net.data.get("handles"),
                                               tolerance=_strain_tolerance(net), **view)))
    if axis is not None:
        metric = _recorded_clairaut(net.metrics) or clairaut(f, axis)
        figs.append(("clairaut", "Clairaut's relation (9): r cos α minus its mean along each "
                                 "interior geodesic (the ones the metric checks), and each "
                                 "geodesic's mean (paper Fig. 11).",
                     lambda: clairaut_figure(clairaut_values(f, axis), f, metric, unit=u)))
    mode = net.parameters.get("mode")
    made = f"dgpc optimize --mode {mode}" if mode else "dgpc init"
    header = Header(f"A net of discrete geodesic parallel coordinates, {m} × {n} vertices "
                    f"({(m - 1) * (n - 1)} quads), made by {made}.",
                    _input_notes(net.inputs, json_path))
    return Page(figs, net.metrics, net.status, u, header, _convergence(net.status))


# --------------------------------------------------------------------------------------------
# strips, flat parts, laths


def _input_up(inputs: dict, json_path: Path):
    """The axis direction of the input net (``inputs.net``) when it records one, else z."""
    from dgpc_cli.io.net import read_net
    from dgpc_cli.stages.inspect import recorded_axis

    record = inputs.get("net")
    if isinstance(record, dict) and "path" in record:
        path = resolve_input(record, json_path)
        if path.is_file():
            axis = recorded_axis(read_net(path))
            if axis is not None:
                return axis[1]
    return (0.0, 0.0, 1.0)


def _strain_tolerance(net) -> float:
    """The strain the net was asked to keep within (its ``--max-strain``, else the default)."""
    from dgpc_cli.tolerances import tol

    value = net.parameters.get("max_strain")
    return float(value) if isinstance(value, (int, float)) and value > 0 else tol.max_strain


def _strips_page(json_path: Path) -> Page:
    from dgpc_cli.io.strips import read_strips
    from dgpc_cli.report.camera import outward_front
    from dgpc_cli.report.net import field_figure
    from dgpc_cli.report.scene import grid_quads
    from dgpc_cli.report.strips import quad_widths

    art = read_strips(json_path)
    grids = [np.stack([np.asarray(A, float), np.asarray(B, float)], axis=1)
             for A, B in art.geometry]
    # seen from where the net's figures are seen: its axis up, from the outside of the strips
    up = _input_up(art.inputs, json_path)
    front = outward_front(np.concatenate([grid_quads(g) for g in grids]), up)
    figs = [("width", "The planar-quad strips, each quad coloured by the strip's width there "
             "(the quad's area over its mean length along the strip: across the strip, not "
             "along its slanted rulings).",
             lambda: field_figure(grids, [quad_widths(g) for g in grids],
                                  title=f"{len(grids)} planar-quad strips",
                                  label=f"strip width [{art.units}]", unit=art.units,
                                  up=up, front=front))]
    figs += _fabrication_figures(art, json_path)
    header = Header(f"{len(grids)} geodesic strips made of planar quads "
                    "(dgpc planarize-strips).", _input_notes(art.inputs, json_path))
    return Page(figs, art.metrics, art.status, art.units, header)


#: Seams are marked where their step exceeds this share of the mean strip width (issue
#: "Strips that build the design": seam step ≤ 1 % of the width).
SEAM_STEP_MARK = 0.01


def _fabrication_figures(art, json_path: Path) -> list:
    """Paper Fig. 18 for a strips artifact whose net is there: the developments overlaid on
    the template, the deviation from the net and the seams (none without the net)."""
    from dgpc_cli.report.flat import error_text
    from dgpc_cli.report.strips import deviation_figure, template_overlay_figure
    from dgpc_cli.stages.inspect import recorded_axis
    from dgpc_cli.stages.strip_fabrication import figure_data, recorded_net

    found = recorded_net(art, json_path)
    if found is None:
        return []
    net = found[0]
    data = figure_data(art, net.f)
    mark = SEAM_STEP_MARK * data.width
    axis = recorded_axis(net)
    up = axis[1] if axis is not None else (0.0, 0.0, 1.0)
    count = len(data.developed)
    worst = max(float(d.max()) for d in data.deviation)
    return [
        ("template", f"Paper Fig. 18 bottom-right: the {count} developed strips, each moved "
                     f"onto the template (the first strip, {data.developed[0][0]}) by the best "
                     "rigid motion of its outline; the ends magnified below.",
         lambda: template_overlay_figure(
             data.developed, outlines=data.outlines,
             title=f"{counted(count, 'developed strip')} overlaid on the template "
                   f"{data.developed[0][0]}: outlines up to "
                   f"{error_text(data.template_error, 'mm')} apart")),
        ("deviation", "The strips in 3-D, each quad coloured by its largest distance from the "
                      "net strip (mm); the seams (the geodesics neighbouring strips share) in "
                      f"red where the two strips' copies step more than {mark:.3g} mm apart "
                      "along the surface normal (1 % of the mean strip width).",
         lambda: deviation_figure(
             [(np.asarray(A, float), np.asarray(B, float)) for A, B in art.geometry],
             data.deviation, data.seams, threshold_mm=mark, unit=art.units, up=up,
             title=f"deviation from the net, up to {worst:.3g} mm, and seams")),
    ]


def _flat_page(json_path: Path) -> Page:
    from dgpc_cli.io.flat import read_flat
    from dgpc_cli.report.flat import layout_figure, overlay_figure

    flat = read_flat(json_path)
    figs = [("overlay", "Every part aligned on its class representative, one cell per "
                        "congruence class (paper Fig. 18 bottom-right).",
             lambda: overlay_figure(flat.parts, flat.classes, flat.units)),
            ("strips", "The developed parts laid out like a sheet, with their rulings (score "
                       "lines), ids and classes (paper Fig. 18 bottom-left).",
             lambda: layout_figure(flat.parts, flat.units))]
    header = Header(f"{counted(len(flat.parts), 'developed part')} in "
                    f"{counted(len(flat.classes), 'congruence class', 'congruence classes')} "
                    "(dgpc unfold).", _input_notes(flat.inputs, json_path))
    return Page(figs, flat.metrics, flat.status, flat.units, header)


def _laths_page(json_path: Path) -> Page:
    from dgpc_cli.io.laths import read_laths
    from dgpc_cli.report.net import laths_figure

    art = read_laths(json_path)
    a, b = art.family("A"), art.family("B")
    units = art.data["units"]
    title = f"{len(a)} + {len(b)} laths, {art.data['crossings']} crossings"
    figs = [("laths", "The two lath families (the u-line geodesics of the two nets, paper "
                      "Fig. 14); the cut list is beside the artifact.",
             lambda: laths_figure([a, b], [f"family A ({len(a)})", f"family B ({len(b)})"],
                                  title=title, unit=units))]
    header = Header(f"The laths of a gridshell: {len(a)} + {len(b)} geodesics of two nets, "
                    f"{art.data['crossings']} crossings (dgpc laths).",
                    _input_notes(art.inputs, json_path))
    return Page(figs, art.metrics, art.status, units, header)


# --------------------------------------------------------------------------------------------
# molds and sheets


def _design_nets(mold, json_path: Path) -> list[np.ndarray]:
    """The design nets of a mold, from its ``panels_obj`` (vertices of every net in order)."""
    from dgpc_cli.io.obj import parse_net_obj

    shapes = [tuple(x["shape"]) for x in mold.data["nets"]]
    path = listed_path(mold.data["files"]["panels_obj"]["path"], json_path,
                       "data.files.panels_obj")
    total = sum(m * n for m, n in shapes)
    vertices = parse_net_obj(path.read_bytes(), total, 1, path).reshape(-1, 3)
    out, start = [], 0
    for m, n in shapes:
        out.append(vertices[start:start + m * n].reshape(m, n, 3))
        start += m * n
    return out


def _mold_page(json_path: Path) -> Page:
    from dgpc_cli.io.mold import read_mold
    from dgpc_cli.report.mold import pairing_figure, pieces_figure, profile_figure

    mold = read_mold(json_path)
    u, data = mold.units, mold.data
    names = [mold.inputs.get(x["input"], {}).get("path", x["input"]) for x in data["nets"]]
    nets = _design_nets(mold, json_path)
    panels = data["panels"]
    figs = [("profile", f"The mold's meridian profile (r, h in {u}) with the axis of "
                        "revolution.",
             lambda: profile_figure(mold.r, mold.h, unit=u, title="mold meridian profile"))]
    for k, f in enumerate(nets):
        mine = [p for p in panels if p["net"] == k]
        figs.append((f"pairing-net{k + 1}",
                     f"Net {k + 1} ({names[k]}): each panel on the mold (left) and on the "
                     "design (right) in one colour, labelled with its id; hatched: flat panels "
                     "(paper Fig. 16).",
                     lambda f=f, mine=mine, k=k: pairing_figure(
                         f, mine, mold.r, mold.h, unit=u,
                         title=f"net {k + 1} ({names[k]}): {len(mine)} panels on the mold and "
                               "on the design")))
    flat = sum(p["flat"] for p in panels)
    figs.append(("pieces", "The mold sector cut into its pieces and where their panels are on "
                           "the design; flat panels (K ≈ 0) need no mold (paper Fig. 17).",
                 lambda: pieces_figure(nets, panels, data["pieces"], mold.r, mold.h,
                                       data["sector"]["angle_deg"], unit=u,
                                       names=[f"net {k + 1}" for k in range(len(nets))],
                                       title=f"{counted(len(data['pieces']), 'mold piece')} "
                                             f"for {counted(len(panels) - flat, 'curved panel')}"
                                             f"; {counted(flat, 'flat panel')} "
                                             f"need{'s' if flat == 1 else ''} none")))
    header = Header(f"A mold: the surface of revolution of {counted(len(nets), 'design net')}, "
                    f"{counted(len(panels), 'panel')} ({flat} flat) on "
                    f"{counted(len(data['pieces']), 'mold piece')} (dgpc extract-mold).",
                    _input_notes(mold.inputs, json_path))
    return Page(figs, mold.metrics, mold.status, u, header)


def _layer_legend(layers: dict, what: dict) -> list[tuple[str, tuple, str]]:
    """``(name, rgb, what)`` per DXF layer of ``what``, in the layers' ACI colours (ACI 7,
    white on black, is drawn black on the white previews)."""
    from ezdxf.colors import aci2rgb

    out = []
    for name, text in what.items():
        aci = layers[name].color
        rgb = (0.0, 0.0, 0.0) if aci == 7 else tuple(c / 255 for c in aci2rgb(aci))
        out.append((name, rgb, text))
    return out


#: What each layer of a cut sheet and of the mold map holds.
SHEET_LEGEND = {"CUT": "outlines, cut", "SCORE": "rulings, score or bend",
                "LABEL": "part ids (text)", "ENGRAVE": "part ids, engraved",
                "SHEET_BORDER": "sheet border (--border)"}
MAP_LEGEND = {"PROFILE": "meridian profile", "AXIS": "axis", "SECTOR": "developed sector",
              "PIECES": "mold pieces", "PANELS": "where panels are pressed",
              "LABEL": "labels", "TABLE": "table"}


def _dxf_layers(path: Path) -> set[str]:
    """The layers a DXF draws on (its legend lists those only)."""
    import ezdxf

    return {e.dxf.layer for e in ezdxf.readfile(path).modelspace()}


def _sheets_page(json_path: Path) -> Page:
    from dgpc_cli.io.dxf import SHEET_LAYERS
    from dgpc_cli.io.sheets import read_sheets
    from dgpc_cli.nesting.drawing import MAP_LAYERS
    from dgpc_cli.report.sheets import preview_figure

    art = read_sheets(json_path)
    data = art.data
    W, H, unit = data["sheet"]["width"], data["sheet"]["height"], data["units"]
    count = len(data["sheets"])
    figs = []
    for i, sheet in enumerate(data["sheets"]):
        if "png" not in sheet:                      # nest --no-preview
            continue
        png = art.file(sheet["png"]).read_bytes()
        drawn = _dxf_layers(art.file(sheet["dxf"]))
        legend = _layer_legend(SHEET_LAYERS, {k: v for k, v in SHEET_LEGEND.items()
                                              if k in drawn})
        title = (f"{sheet['id']} ({i + 1} of {count}), {W:g} × {H:g} {unit}: "
                 f"{counted(len(sheet['parts']), 'part')}, "
                 f"{100 * sheet['utilization']:.1f} % used")
        # the preview has its title (sheet, size, parts, use) and scale bar: none added here
        figs.append((f"sheet{i + 1:02d}", f"Sheet {title}: the cut sheet's preview (written "
                                          "by dgpc nest) with its layers.",
                     lambda png=png, legend=legend: preview_figure(png, legend)))
    if "moldmap_png" in data["files"]:
        png = art.file("moldmap_png").read_bytes()
        figs.append(("moldmap", "The panel-to-mold map sheet (written by dgpc nest --mold) "
                                "with its layers.",
                     lambda: preview_figure(png, _layer_legend(MAP_LAYERS, MAP_LEGEND))))
    header = Header(f"{counted(len(data['placements']), 'part')} nested on "
                    f"{counted(count, 'sheet')} of {W:g} × {H:g} {unit}, "
                    f"{100 * art.metrics.get('utilization', 0.0):.1f} % used (dgpc nest).",
                    _input_notes(art.inputs, json_path))
    return Page(figs, art.metrics, art.status, data["units"], header)


PAGES = {"net": _net_page, "strips": _strips_page, "flat": _flat_page, "mold": _mold_page,
         "laths": _laths_page, "sheets": _sheets_page}


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


def overview_files(artifacts: list[tuple[Path, str]], prefix: Path) -> dict[Path, bytes]:
    """Every file of the report of several artifacts ``(json_path, kind)`` for ``-o PREFIX``:
    each artifact's report under ``PREFIX-<its name>`` (:func:`report_files`), and last
    ``PREFIX-index.html``, one page showing all their figures, linking each one's own page."""
    text = _prefix_text(prefix)
    names = [p.stem for p, _ in artifacts]
    if len(set(names)) < len(names):            # the same name in two folders: number them
        names = [f"{k + 1}-{n}" for k, n in enumerate(names)]
    files: dict[Path, bytes] = {}
    sections = []
    for (json_path, kind), name in zip(artifacts, names, strict=True):
        page = PAGES[kind](json_path)
        sub = Path(f"{text}-{name}")
        files.update(report_files(json_path, kind, sub, page=page))
        figures = [(Path(f"{sub}-{fig}.png").name, caption)
                   for fig, caption, _ in page.figures]
        sections.append(Section(name, kind, page.header.what,
                                Path(f"{sub}-index.html").name, figures))
    folder_title = Path(text).parent.name or "dgpc"
    files[Path(text + "-index.html")] = overview_html(
        title=f"dgpc report: {folder_title} ({', '.join(names)})", sections=sections)
    return files


def report_files(json_path: Path, kind: str, prefix: Path, page: Page | None = None
                 ) -> dict[Path, bytes]:
    """Every file of the report of the ``kind`` artifact ``json_path`` for ``-o PREFIX``:
    ``PREFIX-<figure>.png`` and last ``PREFIX-index.html`` (nothing written)."""
    text = _prefix_text(prefix)
    html_path = Path(text + "-index.html")
    page = PAGES[kind](json_path) if page is None else page
    files: dict[Path, bytes] = {}
    links = []
    convergence = None
    with style():
        for name, caption, make in page.figures:
            path = Path(f"{text}-{name}.png")
            files[path] = png_bytes(make())
            links.append((path.name, caption))
        if page.convergence is not None:
            name, caption, make = page.convergence
            path = Path(f"{text}-{name}.png")
            files[path] = png_bytes(make())
            convergence = (path.name, caption)
    files[html_path] = index_html(title=f"dgpc report: {json_path.name}", kind=kind,
                                  source=json_path.name, header=page.header, figures=links,
                                  metrics=page.metrics, status=page.status, units=page.units,
                                  convergence=convergence)
    return files
