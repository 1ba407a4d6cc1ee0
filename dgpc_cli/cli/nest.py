"""``dgpc nest``: the flat parts on cut sheets, DXF + previews, and the panel-to-mold map."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    accept_status_opt,
    check_units,
    check_writable,
    force_opt,
    format_opt,
    label_style_opt,
    output_opt,
    progressbar,
    units_check_opt,
)
from dgpc_cli.nesting.tools import BIT_SPAN, KERF_SPAN, MARGIN_SPAN, TOOLS, resolve_tool
from dgpc_cli.stages.nest import ENGINES, parse_rotations, parse_sheet
from dgpc_cli.stages.nest_run import NestOptions, run_nest


def _parsed(parser):
    def callback(ctx, param, value):
        try:
            return parser(value)
        except ValueError as err:
            raise click.BadParameter(str(err), ctx=ctx, param=param) from None
    return callback


@click.command(short_help="Nest the flat parts on cut sheets (DXF, SVG, PNG).")
@click.argument("stems", metavar="FLAT [FLAT ...]", nargs=-1, required=True,
                type=click.Path(path_type=Path))
@click.option("--mold", "mold_stem", type=click.Path(path_type=Path), metavar="MOLD",
              help="A mold artifact: also write the panel-to-mold map DXF.")
@click.option("--sheet", "sheet_size", required=True, callback=_parsed(parse_sheet),
              metavar="WIDTHxHEIGHT",
              help="Sheet size, width x height: plain numbers in mm (2500x1250), or with a "
                   "unit (6.1mx2.5m, 6100x2500mm; one unit after the height is both sides').")
@click.option("--tool", type=click.Choice(list(TOOLS)), default=None,
              help="The cutter, for the spacing and margin defaults: laser (kerf 0.2 mm, "
                   "spacing 3 mm, margin 10 mm), router (bit 6 mm, spacing 8 mm, margin "
                   "20 mm), waterjet (kerf 1 mm, spacing 2 mm, margin 25 mm). [default: "
                   "laser; router with --tool-diameter]")
@click.option("--kerf", type=LengthParam(plain="mm", min=0, min_open=True, span=KERF_SPAN),
              default=None,
              help=length_help("Cut width of a laser or water jet, > 0 (default 0.2 mm laser, "
                               "1 mm waterjet); the default spacing is the kerf plus the "
                               "tool's clearance.", plain="mm", plausible=KERF_SPAN))
@click.option("--tool-diameter", "tool_diameter",
              type=LengthParam(plain="mm", min=0, min_open=True, span=BIT_SPAN), default=None,
              help=length_help("Router bit diameter, > 0 (default 6 mm); the default spacing "
                               "is the diameter plus 2 mm.", plain="mm", plausible=BIT_SPAN))
@click.option("--margin", type=LengthParam(plain="mm", min=0, span=MARGIN_SPAN), default=None,
              help=length_help("Free border of each sheet, >= 0 [default: the tool's].",
                               plain="mm", plausible="0, or at least 1 mm"))
@click.option("--spacing", type=LengthParam(plain="mm", min=0), default=None,
              help=length_help("Least distance between parts, at least the tool's cut width "
                               "[default: cut width + the tool's clearance].", plain="mm"))
@click.option("--border", is_flag=True,
              help="Also draw the sheet's border, one closed polyline on layer SHEET_BORDER "
                   "(plotted: a CAM cuts it; by default the cut file has no border).")
@label_style_opt
@click.option("--rotations", default="0,180", show_default=True,
              callback=_parsed(parse_rotations), metavar="DEG,DEG,...",
              help="Allowed rotations in degrees (grain or rolling direction).")
@units_check_opt
@click.option("--scale", type=FiniteFloat(min=0, min_open=True), default=1.0,
              show_default=True,
              help="Model scale (a scale model): 1 unit of the parts is SCALE units in the DXF "
                   "(mm).")
@click.option("--engine", type=click.Choice(ENGINES), default="fill", show_default=True,
              help="'fill': deterministic no-fit-polygon fill; 'spyrrow': spyrrow's strip "
                   "packer sheet by sheet (time-bounded, see --time-limit).")
@click.option("--time-limit", type=FiniteFloat(min=0, min_open=True), default=10.0,
              show_default=True, metavar="SEC",
              help="spyrrow's time budget per sheet (engine spyrrow).")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True,
              help="Random seed (engine spyrrow).")
@click.option("--no-preview", "no_preview", is_flag=True,
              help="Write no SVG/PNG previews of the sheets (the DXFs only: faster).")
@accept_status_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def nest(ctx, stems, mold_stem, sheet_size, tool, kerf, tool_diameter, margin, spacing, border,
         label_style, rotations, units_check, scale, engine, time_limit, seed, no_preview,
         accept_status, output, force, fmt):
    """Place every part of the flat artifact FLAT (each congruence class in its quantity) on
    as few sheets as it can, and write the sheets artifact -o SHEETS: SHEETS.json, .obj,
    .parts.csv and per sheet SHEETS.sheetNN.dxf/.svg/.png (with --mold, .moldmap.dxf).

    Several FLATs (the patches of one facade, or the members of a patch set of flats: `unfold`
    of `init --patches`) are nested together: part ids become TAG:ID,
    TAG the flat's name, or its folder's name when the names repeat (facade-2/flat →
    facade-2:S-v03), and congruent parts of different flats are one class, its quantity
    summed over them (recorded in the JSON's data.combined).

    The parts' unit is the flat artifact's (from `init --units`); every DXF is in mm (times
    SCALE); sheet, margin, spacing, kerf and tool diameter are in mm. Prints the written JSON
    path.
    """
    try:
        cutter = resolve_tool(tool, *(x.to_mm() if x is not None else None
                                      for x in (kerf, tool_diameter, spacing, margin)))
    except ValueError as err:
        option, message = err.args
        raise click.BadParameter(message, ctx=ctx, param_hint=f"'{option}'") from None
    opts = NestOptions(sheet_size=sheet_size, cutter=cutter, rotations=rotations, border=border,
                       label_style=label_style, scale=scale, engine=engine,
                       time_limit=time_limit, seed=seed, previews=not no_preview,
                       accept_status=accept_status)
    run_nest(stems, output, opts, mold_stem=mold_stem, force=force, fmt=fmt,
             check=check_writable,
             check_units=lambda units, source: check_units(units_check, units, source),
             progressbar=lambda length, label: progressbar(ctx, length, label),
             written=lambda out_json: click.echo(str(out_json)))
