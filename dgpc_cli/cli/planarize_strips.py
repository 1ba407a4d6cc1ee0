"""``dgpc planarize-strips``: geodesic strips as planar-quad strips (paper §6.2.4, SPEC §6)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import (
    accept_status_opt,
    check_writable,
    force_opt,
    format_opt,
    output_opt,
    progressbar,
)
from dgpc_cli.cli.patch_set_members import on_members
from dgpc_cli.cli.refine_option import RefineParam
from dgpc_cli.stages.planarize_run import PlanarizeOptions, run_planarize_strips
from dgpc_cli.strips.planarize import (
    FLAT_ANGLE,
    MAX_RULING_TURN,
    RULING_FAIRNESS,
    SEAM_WEIGHT,
)


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
@click.option("--refine", type=RefineParam(), default="auto", show_default=True, metavar="K|auto",
              help="Rulings per net row, K or auto: K − 1 more between every two rows, their "
                   "ends on a cubic through the net's geodesics (arc length); the strips follow "
                   "the net between its rows and their seams meet closer. The parts' rows in "
                   "unfold stay the net's (refined row t is net row t / K). auto: K = 1, and "
                   "K = 2 where one template's K = 1 strips miss the deviation (1.5 %) or seam "
                   "step (1 % of the mean width) target and K = 2 lowers the seam step without "
                   "raising the deviation (stderr says so; data.parameters.refine_auto).")
@accept_status_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def planarize_strips_cmd(ctx, stem, strip_range, flat_angle, trim, per_strip, seam_weight,
                         ruling_fairness, max_ruling_turn, refine, accept_status, output, force,
                         fmt):
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
    check_writable(output, force)
    opts = PlanarizeOptions(strip_range=strip_range, flat_angle=flat_angle, trim=trim,
                            per_strip=per_strip, seam_weight=seam_weight,
                            ruling_fairness=ruling_fairness, max_ruling_turn=max_ruling_turn,
                            refine=refine, accept_status=accept_status)
    run_planarize_strips(stem, output, opts, force=force, fmt=fmt,
                         progressbar=lambda length, label: progressbar(ctx, length, label),
                         written=lambda out_json: click.echo(str(out_json)))
