"""``dgpc unfold``: develop planar-quad strips and find congruence classes (SPEC §6)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    accept_status_opt,
    check_writable,
    force_opt,
    format_opt,
    label_style_opt,
    output_opt,
)
from dgpc_cli.cli.patch_set_members import on_members
from dgpc_cli.io.flat import csv_path
from dgpc_cli.stages.unfold import CONGRUENCE_TOL_MM, STAGGER_FRACTION
from dgpc_cli.stages.unfold_run import UnfoldOptions, run_unfold


@click.command(short_help="Develop strips into the plane; group them into cutting templates.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mirror-ok", is_flag=True,
              help="Count mirror images as congruent (parts that may be flipped over).")
@click.option("--congruence-tol", type=LengthParam(min=0, min_open=True),
              default=f"{CONGRUENCE_TOL_MM:g}mm", show_default=True,
              help=length_help("Parts are copies of one template (a congruence class) when, "
                               "optimally aligned, no point of their outlines is farther "
                               "apart than this (> 0).",
                               plausible="up to 1 % of the parts' mean width"))
@click.option("--stock-length", type=LengthParam(min=0, min_open=True),
              help=length_help("Cut every strip longer than this into boards no longer than "
                               "it (> 0): part ids S-v07.1, S-v07.2, ...; at rulings, or the "
                               "strips of one template at the same template lines.",
                               plausible="longer than the widest part, up to the longest "
                                         "strip"))
@click.option("--stagger", type=LengthParam(min=0),
              help=length_help("With --stock-length: no joint of a strip within this (>= 0, "
                               "along the geodesic) of a joint of the strips beside it "
                               f"[default: {STAGGER_FRACTION:g} × the stock length, "
                               "kept where the rulings allow it, with a warning where a "
                               "joint cannot keep it].",
                               plausible="up to the stock length"))
@label_style_opt
@accept_status_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def unfold(ctx, stem, mirror_ok, congruence_tol, stock_length, stagger, label_style,
           accept_status, output, force, fmt):
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
    check_writable(output, force, csv_path(output), csv_path(output, "assembly"))
    opts = UnfoldOptions(congruence_tol=congruence_tol, label_style=label_style,
                         mirror_ok=mirror_ok, stock_length=stock_length, stagger=stagger,
                         accept_status=accept_status)
    run_unfold(stem, output, opts, force=force, fmt=fmt,
               written=lambda out_json: click.echo(str(out_json)))
