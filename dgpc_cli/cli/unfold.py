"""``dgpc unfold``: develop planar-quad strips and find congruence classes (SPEC §6)."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    check_writable,
    force_opt,
    format_opt,
    label_style_opt,
    output_opt,
)
from dgpc_cli.cli.patch_set_members import on_members
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import FlatArtifact, csv_path, flat_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import mm_per_unit, to_mm
from dgpc_cli.stages.soundness import require_sound_strips
from dgpc_cli.stages.unfold import (
    CONGRUENCE_TOL_MM,
    STAGGER_FRACTION,
    flat_metrics,
    narrow_warnings,
    records_in_units,
    scale_warnings,
    template_dxfs,
    unfold_strips,
    unit_slip,
)

log = logging.getLogger(__name__)


@click.command(short_help="Develop strips into the plane; group them into cutting templates.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mirror-ok", is_flag=True,
              help="Count mirror images as congruent (parts that may be flipped over).")
@click.option("--congruence-tol", type=LengthParam(min=0, min_open=True),
              default=f"{CONGRUENCE_TOL_MM:g}mm", show_default=True,
              help=length_help("Parts are copies of one template (a congruence class) when, "
                               "optimally aligned, no point of their outlines is farther "
                               "apart than this (> 0)."))
@click.option("--stock-length", type=LengthParam(min=0, min_open=True),
              help=length_help("Cut every strip longer than this into boards no longer than "
                               "it (> 0): part ids S-v07.1, S-v07.2, ...; at rulings, or the "
                               "strips of one template at the same template lines."))
@click.option("--stagger", type=LengthParam(min=0),
              help=length_help("With --stock-length: no joint of a strip within this (>= 0, "
                               "along the geodesic) of a joint of the strips beside it "
                               f"[default: {STAGGER_FRACTION:g} × the stock length, "
                               "kept where the rulings allow it, with a warning where a "
                               "joint cannot keep it]."))
@label_style_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def unfold(ctx, stem, mirror_ok, congruence_tol, stock_length, stagger, label_style, output, force,
           fmt):
    """Develop the planar-quad strips of the strips artifact STEM into the plane (paper §6.2.4).

    Records per part the closed outline, the rulings (score lines), a label point, the edge
    strain and the straightness of the developed geodesics; groups the parts into congruence
    classes, the cutting templates (every two copies of a template within --congruence-tol,
    whatever the order of the parts), with each copy's deviation from its template in mm. With
    --stock-length, strips are cut at rulings into boards of stock length (straight across a
    planar quad where no ruling lies within the stock), the joints of neighbouring strips
    staggered (alternating between two patterns where the strips allow);
    the strips of one template are cut at the same straight lines of the template (not
    necessarily rulings), two joint patterns alternating, so their boards are copies of the
    boards of the two patterns; congruence classes are then per board. Writes the flat
    artifact -o STEM2, its cut list STEM2.parts.csv (one line per template: quantity and the
    copies' ids, mm), STEM2.assembly.csv (one line per part: where it goes) and per template
    STEM2.C01.dxf, ... (the part alone, mm, layers as on nest's cut sheets, labelled with the
    class, its quantity and its copies' ids in --label-style); where the copies of a template
    share its outline but not its score lines (a shared-outline template: each strip its own
    rulings), one DXF per copy instead, STEM2.C01.S-v03.dxf, ... (the outline, the copy's own
    score lines), and the cut list says "per copy" in its score_lines column. A patch set of
    strips is unfolded member by member (-o STEM2.pK, and STEM2 the set of them).
    """
    if on_members(ctx, stem, output, force, "unfold",
                  extra=lambda out: (csv_path(out), csv_path(out, "assembly"))):
        return
    if stagger is not None and stock_length is None:
        raise click.UsageError("--stagger goes with --stock-length")
    json_path, _ = artifact_paths(stem)
    check_writable(output, force, csv_path(output), csv_path(output, "assembly"))
    strips = read_strips(stem)
    require_sound_strips(strips.geometry, [r["id"] for r in strips.records], json_path,
                         [[p["rows"] for p in r["trim"]["parts"]] if r.get("trim") else None
                          for r in strips.records],
                         [[p["outline"] for p in r["trim"]["parts"]] if r.get("trim") else None
                          for r in strips.records])
    units = strips.units                 # computed in mm (dgpc_cli.io.units)
    stock_mm = None if stock_length is None else stock_length.to_mm(units)
    stagger_mm = (None if stock_length is None else stagger.to_mm(units) if stagger is not None
                  else STAGGER_FRACTION * stock_mm)
    geometry = [(to_mm(A, units), to_mm(B, units)) for A, B in strips.geometry]
    slip = unit_slip(geometry, units, stock_length, stagger)
    if slip is not None:
        raise click.UsageError(slip)
    parts, classes, joints = unfold_strips(
        geometry, [r["id"] for r in strips.records], [r["v"] for r in strips.records],
        congruence_tol=congruence_tol.to_mm(units), mirror_ok=mirror_ok,
        stock_length=stock_mm, stagger=None if stagger is None else stagger_mm,
        source=json_path,
        trims=[r.get("trim") for r in strips.records],
        cut_edges=[r.get("cut_edges") for r in strips.records],
        template=strips.template is not None and "rejected" not in strips.template,
        refine=strips.parameters.get("refine", 1))
    for line in scale_warnings(parts, geometry, units, stock_length) + narrow_warnings(parts,
                                                                                      units):
        log.warning("%s: %s", json_path, line)
    templates = template_dxfs(parts, classes, label_style)
    parts, classes, joints = records_in_units(parts, classes, joints, units)
    out_json, _ = artifact_paths(output)
    art = FlatArtifact(
        parts=parts, classes=classes, units=units, joints=joints, templates=templates,
        parameters={"mirror_ok": mirror_ok, "congruence_tol": congruence_tol.text(),
                    "label_style": label_style,
                    "congruence_tol_mm": congruence_tol.to_mm(units),
                    "stock_length": None if stock_mm is None else stock_mm / mm_per_unit(units),
                    "stagger": None if stagger_mm is None else stagger_mm / mm_per_unit(units)},
        inputs={"strips": file_input(json_path, out_json.resolve().parent)},
        metrics=flat_metrics(parts, classes, units), status={"n_classes": len(classes)})
    write_files(with_3dm(flat_files(output, art), output, fmt), force=force)
    click.echo(str(out_json))
