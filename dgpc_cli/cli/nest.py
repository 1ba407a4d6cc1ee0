"""``dgpc nest``: the flat parts on cut sheets, DXF + previews, and the panel-to-mold map."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    check_units,
    check_writable,
    force_opt,
    format_opt,
    label_style_opt,
    output_opt,
    progressbar,
    units_check_opt,
)
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.patch_set import with_members
from dgpc_cli.io.rhino import rhino_path, with_3dm
from dgpc_cli.io.sheets import extra_path, sheets_files
from dgpc_cli.io.units import mm_per_unit, same_units
from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.tools import TOOLS, resolve_tool
from dgpc_cli.stages.nest import (
    ENGINES,
    existing_sheet_files,
    mold_map,
    nest_parts,
    parse_rotations,
    parse_sheet,
    parts_csv,
    sheet_drawings,
    sheet_previews,
    sheets_data,
    sheets_metrics,
    sheets_obj,
)

log = logging.getLogger(__name__)


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
@click.option("--kerf", type=LengthParam(plain="mm", min=0, min_open=True), default=None,
              help=length_help("Cut width of a laser or water jet, > 0 (default 0.2 mm laser, "
                               "1 mm waterjet); the default spacing is the kerf plus the "
                               "tool's clearance.", plain="mm"))
@click.option("--tool-diameter", "tool_diameter",
              type=LengthParam(plain="mm", min=0, min_open=True), default=None,
              help=length_help("Router bit diameter, > 0 (default 6 mm); the default spacing "
                               "is the diameter plus 2 mm.", plain="mm"))
@click.option("--margin", type=LengthParam(plain="mm", min=0), default=None,
              help=length_help("Free border of each sheet, >= 0 [default: the tool's].",
                               plain="mm"))
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
@output_opt
@force_opt
@format_opt
@click.pass_context
def nest(ctx, stems, mold_stem, sheet_size, tool, kerf, tool_diameter, margin, spacing, border,
         label_style, rotations, units_check, scale, engine, time_limit, seed, no_preview, output,
         force, fmt):
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
    margin, spacing = cutter.margin, cutter.spacing
    stems = with_members(stems)
    json_paths = [artifact_paths(stem)[0] for stem in stems]
    check_writable(output, force, extra_path(output, "parts_csv"),
                   *([rhino_path(output)] if fmt == "3dm" else []),
                   *(existing_sheet_files(output) if not force else ()))
    flats = [read_flat(stem) for stem in stems]
    units = same_units([(str(p), f.units) for p, f in zip(json_paths, flats, strict=True)])
    check_units(units_check, units, json_paths[0])
    combined = None
    if len(flats) == 1:
        flat_parts = flats[0].parts
    else:
        from dgpc_cli.stages.combine_flats import combine_flats, flat_tags

        combined = combine_flats(list(zip(flat_tags(stems), flats, strict=True)))
        flat_parts = combined.parts
    mold = None
    if mold_stem is not None:
        from dgpc_cli.io.mold import read_mold

        mold = read_mold(mold_stem)
        same_units([(str(json_paths[0]), units),
                    (str(artifact_paths(mold_stem)[0]), mold.units)])
    sheet = Sheet(sheet_size[0], sheet_size[1], margin, spacing)
    n = len(flat_parts)
    with progressbar(ctx, length=(2 * n if engine == "fill" else n),
                     label="nesting") as bar:
        result = nest_parts(flat_parts, sheet, rotations, units=units, scale=scale,
                            engine=engine, time_limit=time_limit, seed=seed,
                            progress=bar.update)
    extra: dict[str, bytes] = {"parts_csv": parts_csv(result, flat_parts,
                                                      scale * mm_per_unit(units))}
    drawings = sheet_drawings(result, border=border, label_style=label_style)
    for s, (dxf, _) in enumerate(drawings):
        extra[f"sheet{s + 1:02d}_dxf"] = dxf
    if not no_preview:
        log.info("%d cut sheets drawn; rendering their previews", len(drawings))
        for s, (dxf, _) in enumerate(drawings):
            svg, png = sheet_previews(result, s, dxf)
            extra.update({f"sheet{s + 1:02d}_svg": svg, f"sheet{s + 1:02d}_png": png})
    out_json, _ = artifact_paths(output)
    folder = out_json.resolve().parent
    inputs = ({"flat": file_input(json_paths[0], folder)} if combined is None else
              {f"flat{k + 1}": file_input(p, folder) for k, p in enumerate(json_paths)})
    if mold is not None:
        extra["moldmap_dxf"], extra["moldmap_png"] = mold_map(mold, scale)
        inputs["mold"] = file_input(artifact_paths(mold_stem)[0], folder)
    data = sheets_data(result, [d[1] for d in drawings], units=units, scale=scale,
                       engine=engine, time_limit=time_limit, seed=seed,
                       previews=not no_preview)
    metrics = sheets_metrics(data)
    if combined is not None:
        data["combined"] = combined.record()
        metrics["classes"] = {c["id"]: c["quantity"] for c in combined.classes}
    parameters = {"sheet": f"{sheet.width:g}x{sheet.height:g}", "margin": margin,
                  "spacing": spacing, **cutter.record(), "border": border,
                  "label_style": label_style, "rotations": rotations, "units": units,
                  "scale": scale, "engine": engine, "time_limit": time_limit, "seed": seed,
                  "mold": mold_stem is not None}
    files = sheets_files(output, data=data, extra=extra, obj=sheets_obj(result),
                         inputs=inputs, parameters=parameters, metrics=metrics,
                         status={"sheet_count": result.sheet_count,
                                 "deterministic": engine == "fill"})
    write_files(with_3dm(files, output, fmt, parts=flat_parts), force=force)
    click.echo(str(out_json))
