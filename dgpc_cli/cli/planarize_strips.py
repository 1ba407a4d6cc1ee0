"""``dgpc planarize-strips``: geodesic strips as planar-quad strips (paper §6.2.4, SPEC §6)."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt, progressbar
from dgpc_cli.cli.patch_set_members import on_members
from dgpc_cli.errors import DgpcError, NotConverged
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.stages.planarize import (
    FLAT_ANGLE,
    MAX_RULING_TURN,
    POLISH_ABOVE,
    RULING_FAIRNESS,
    SEAM_WEIGHT,
    crossed_strips,
    parse_strip_range,
    planarize_strips,
    refine_rows,
    strips_metrics,
    template_qualifies,
    template_strips,
    trim_records,
)
from dgpc_cli.stages.soundness import require_sound_net
from dgpc_cli.stages.strip_fabrication import fabrication_metrics, fabrication_warnings

log = logging.getLogger(__name__)


def _outline(net, json_path):
    """The reference the net records, for --trim; DgpcError naming --trim without one."""
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.stages.inspect import recorded_reference

    mesh = recorded_reference(net, json_path)
    if mesh is None:
        raise DgpcError(f"--trim clips to the reference the net records, and {json_path} "
                        "records none that is there", source="--trim")
    return ReferenceSurface.from_mesh(mesh)


@click.command("planarize-strips", short_help="Make every geodesic strip a strip of planar quads.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--strips", "strip_range", metavar="V0:V1",
              help="Only the strips V0 to V1, both included (strip v lies between the u-lines "
                   "v and v+1; default: all).")
@click.option("--flat-angle", type=FiniteFloat(min=0), default=FLAT_ANGLE,
              show_default=True,
              help="Rows where the strip normals turn by less than this (radians per row) are "
                   "flat: their rulings are averaged from the nearest non-flat rows.")
@click.option("--trim", is_flag=True,
              help="Clip every strip to the outline of the reference the net records (a net "
                   "made with init --extend runs past it): the parts end where the reference "
                   "ends; parts shorter than one quad are dropped (stderr says which).")
@click.option("--per-strip", is_flag=True,
              help="Planarize every strip on its own (its own rulings and outline) instead of "
                   "fitting one template shared by all strips, the default for a net "
                   "isometric to a surface of revolution with equal strip widths.")
@click.option("--seam-weight", type=FiniteFloat(min=0), default=SEAM_WEIGHT,
              show_default=True,
              help="Template fit: weight of the seams (each strip's copy of a shared geodesic "
                   "on its neighbour's, no step along the normal, no gap across) against the "
                   "closeness to the net; 0 lets the strips follow the net more closely.")
@click.option("--ruling-fairness", type=FiniteFloat(min=0), default=RULING_FAIRNESS,
              show_default=True,
              help="Template fit: weight of the rulings' smoothness (second differences of the "
                   "ruling vectors): higher keeps neighbouring score lines closer to parallel, "
                   "lower lets the strips follow the net more closely.")
@click.option("--max-ruling-turn", type=FiniteFloat(min=1, max=89), default=MAX_RULING_TURN,
              show_default=True,
              help="Template fit: largest angle in degrees between neighbouring rulings (score "
                   "lines); a larger angle lets the strips follow the net more closely.")
@click.option("--refine", type=click.IntRange(min=1), default=1, show_default=True,
              help="Rulings per net row: K − 1 more between every two rows, their ends on a "
                   "cubic through the net's geodesics (arc length); the strips follow the net "
                   "between its rows and their seams meet closer. The parts' rows in unfold "
                   "stay the net's (refined row t is net row t / K).")
@output_opt
@force_opt
@format_opt
@click.pass_context
def planarize_strips_cmd(ctx, stem, strip_range, flat_angle, trim, per_strip, seam_weight,
                         ruling_fairness, max_ruling_turn, refine, output, force, fmt):
    """Turn the geodesic strips of the net STEM into discrete developable strips (paper §6.2.4).

    Rulings follow the cross products N × N1 of neighbouring normals (averaged across flat
    parts); the plane of each ruling and the normal, through the midpoint of the v-edge, cuts
    the two boundary geodesics. Strips whose quads stay measurably non-planar get a short
    guided-projection polish. Writes the strips artifact -o STEM2 (one OBJ object per strip,
    ids S-v00, S-v01, ...). With --trim each strip's record lists its parts inside the
    reference's outline (data.strips[].trim); unfold develops those. Every strip starts and
    ends on the net's boundary rows.

    A net isometric to a surface of revolution (extract-mold accepts it) with equally wide
    strips gets one template: a flat strip shared by all strips, each strip an exact bending
    of it fitted to its net strip (data.template records it); --per-strip keeps every strip
    on its own. A patch set (init --patches) is planarized member by member (-o STEM2.pK, and
    STEM2 the set of them).
    """
    if on_members(ctx, stem, output, force, "planarize-strips"):
        return
    json_path, _ = artifact_paths(stem)
    check_writable(output, force)
    net = read_net(stem)
    require_sound_net(net.f, json_path, gpc=False)
    m, n = net.shape
    columns = parse_strip_range(strip_range, n)
    outline = _outline(net, json_path) if trim else None
    reason = "--per-strip" if per_strip else template_qualifies(net.f_mm, columns)
    f_mm = refine_rows(net.f_mm, refine)
    with progressbar(ctx, len(columns), "planarize strips") as bar:
        strips = planarize_strips(f_mm, columns, flat_angle=flat_angle, progress=bar.update)
    template = fallback = None
    if reason is None:
        log.info("planarize-strips: one template for all strips (the net is isometric to a "
                 "surface of revolution with equal strip widths)")
        fitted, record = template_strips(f_mm, strips, net.units,
                                         seam_weight=seam_weight,
                                         ruling_fairness=ruling_fairness,
                                         max_ruling_turn=max_ruling_turn)
        if fitted is None:
            log.warning("planarize-strips: every strip on its own, no shared template: %s",
                        record["rejected"])
            fallback = record
        else:
            template = record
        strips = fitted or strips
    elif not per_strip:
        log.warning("planarize-strips: every strip on its own, no shared template: the net %s",
                    reason)
    strips = [s.in_units(net.units) for s in strips]
    records = [s.record() for s in strips]
    if outline is not None:
        trims, notes = trim_records(strips, outline)
        for record, cut in zip(records, trims, strict=True):
            record["trim"] = cut
        for note in notes:
            log.warning("%s", note)
    out_json, _ = artifact_paths(output)
    polished = [s for s in strips if s.polish.get("applied")]
    failed = [s.id for s in polished if s.polish.get("status") != "converged"]
    crossed = crossed_strips(strips, records, net.f)
    art = StripsArtifact(
        geometry=[(s.A, s.B) for s in strips], records=records,
        source_shape=(m, n), units=net.units,
        parameters={"strips": [columns[0], columns[-1]], "flat_angle": flat_angle,
                    "polish_above": POLISH_ABOVE, "trim": trim,
                    "method": "per-strip" if template is None else "template",
                    "seam_weight": seam_weight, "ruling_fairness": ruling_fairness,
                    "max_ruling_turn": max_ruling_turn,
                    **({"refine": refine} if refine > 1 else {}),
                    **({"template_rejected": fallback} if fallback else {})},
        template=template,
        inputs={"net": file_input(json_path, out_json.resolve().parent)},
        metrics={**strips_metrics(records, net.units),
                 "fabrication": fabrication_metrics(net.f, net.units, records,
                                                    [(s.A, s.B) for s in strips], outline,
                                                    refine=refine)},
        status={"polished": len(polished), "polish_not_converged": failed,
                "rulings_cross": crossed})
    write_files(with_3dm(strips_files(output, art), output, fmt), force=force)
    click.echo(str(out_json))
    for note in fabrication_warnings(art.metrics["fabrication"]):
        log.warning("%s: %s", out_json, note)
    log.info("%s: %d strips, max planarity %.3g of the diagonal, max deviation %.3g of the "
             "width", out_json, len(strips), art.metrics["max_planarity_diagonal_relative"],
             art.metrics["max_deviation_relative"])
    if failed:
        raise NotConverged(f"the polish of {', '.join(failed)} did not reach its tolerance "
                           f"(max planarity {art.metrics['max_planarity_diagonal_relative']:.3g}"
                           " of the diagonal); written anyway",
                           source=out_json)
    if crossed:
        raise NotConverged(f"the rulings of {', '.join(crossed)} cross (folded quads, the "
                           "strip cannot be unfolded); written anyway", source=out_json)
