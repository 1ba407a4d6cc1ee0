"""The ``nest`` run: read the flats (combined where several), nest their parts on cut sheets,
draw the sheets and their previews (and the panel-to-mold map), and write the sheets
artifact."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.patch_set import with_members
from dgpc_cli.io.rhino import rhino_path, with_3dm
from dgpc_cli.io.sheets import extra_path, sheets_files
from dgpc_cli.io.units import mm_per_unit, same_units
from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.tools import ToolSettings
from dgpc_cli.stages.input_status import check_inputs, with_accepted
from dgpc_cli.stages.nest import (
    existing_sheet_files,
    mold_map,
    nest_parts,
    parts_csv,
    sheet_drawings,
    sheet_previews,
    sheets_data,
    sheets_metrics,
    sheets_obj,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class NestOptions:
    """The options of ``nest`` (see its help); the sheet size and the cutter's margin and
    spacing in mm."""

    sheet_size: tuple[float, float]
    cutter: ToolSettings
    rotations: list[float]
    border: bool = False
    label_style: str = "text"
    scale: float = 1.0
    engine: str = "fill"
    time_limit: float = 10.0
    seed: int = 0
    previews: bool = True
    accept_status: bool = False     # go on with flats that fell short (stages.input_status)


def _flat_parts(stems: list[Path], flats: list):
    """The parts to nest: the one flat's, else the flats combined (and the combination)."""
    if len(flats) == 1:
        return flats[0].parts, None
    from dgpc_cli.stages.combine_flats import combine_flats, flat_tags

    combined = combine_flats(list(zip(flat_tags(stems), flats, strict=True)))
    return combined.parts, combined


def _parameters(opts: NestOptions, sheet: Sheet, units: str, mold: bool) -> dict:
    return {"sheet": f"{sheet.width:g}x{sheet.height:g}", "margin": opts.cutter.margin,
            "spacing": opts.cutter.spacing, **opts.cutter.record(), "border": opts.border,
            "label_style": opts.label_style, "rotations": opts.rotations, "units": units,
            "scale": opts.scale, "engine": opts.engine, "time_limit": opts.time_limit,
            "seed": opts.seed, "mold": mold}


def run_nest(stems, output: Path, opts: NestOptions, *, mold_stem: Path | None, force: bool,
             fmt, check: Callable, check_units: Callable[[str, Path], None],
             progressbar: Callable, written: Callable[[Path], None]) -> None:
    """Nest the parts of the flat artifacts ``stems`` (patch sets standing for their members)
    into the sheets artifact ``output``; with ``mold_stem``, also the panel-to-mold map.

    ``check(stem, force, *extra)`` refuses the outputs before any is read;
    ``check_units(units, json_path)`` checks the flats' unit against the command's;
    ``progressbar(length, label)`` is a context manager with ``update``;
    ``written(out_json)`` is called once the files are written."""
    stems = with_members(stems)
    json_paths = [artifact_paths(stem)[0] for stem in stems]
    check(output, force, extra_path(output, "parts_csv"),
          *([rhino_path(output)] if fmt == "3dm" else []),
          *(existing_sheet_files(output) if not force else ()))
    flats = [read_flat(stem) for stem in stems]
    names = ["flat"] if len(flats) == 1 else [f"flat{k + 1}" for k in range(len(flats))]
    statuses = [(name, p, f.status) for name, p, f in zip(names, json_paths, flats, strict=True)]
    units = same_units([(str(p), f.units) for p, f in zip(json_paths, flats, strict=True)])
    check_units(units, json_paths[0])
    flat_parts, combined = _flat_parts(stems, flats)
    mold = None
    if mold_stem is not None:
        from dgpc_cli.io.mold import read_mold

        mold = read_mold(mold_stem)
        statuses.append(("mold", artifact_paths(mold_stem)[0], mold.status))
        same_units([(str(json_paths[0]), units),
                    (str(artifact_paths(mold_stem)[0]), mold.units)])
    carried = check_inputs(statuses, "nest", opts.accept_status)
    sheet = Sheet(opts.sheet_size[0], opts.sheet_size[1], opts.cutter.margin,
                  opts.cutter.spacing)
    n = len(flat_parts)
    with progressbar(2 * n if opts.engine == "fill" else n, "nesting") as bar:
        result = nest_parts(flat_parts, sheet, opts.rotations, units=units, scale=opts.scale,
                            engine=opts.engine, time_limit=opts.time_limit, seed=opts.seed,
                            progress=bar.update)
    extra: dict[str, bytes] = {"parts_csv": parts_csv(result, flat_parts,
                                                      opts.scale * mm_per_unit(units))}
    drawings = sheet_drawings(result, border=opts.border, label_style=opts.label_style)
    for s, (dxf, _) in enumerate(drawings):
        extra[f"sheet{s + 1:02d}_dxf"] = dxf
    if opts.previews:
        log.info("%d cut sheets drawn; rendering their previews", len(drawings))
        for s, (dxf, _) in enumerate(drawings):
            svg, png = sheet_previews(result, s, dxf)
            extra.update({f"sheet{s + 1:02d}_svg": svg, f"sheet{s + 1:02d}_png": png})
    out_json, _ = artifact_paths(output)
    folder = out_json.resolve().parent
    inputs = ({"flat": file_input(json_paths[0], folder)} if combined is None else
              {f"flat{k + 1}": file_input(p, folder) for k, p in enumerate(json_paths)})
    if mold is not None:
        extra["moldmap_dxf"], extra["moldmap_png"] = mold_map(mold, opts.scale)
        inputs["mold"] = file_input(artifact_paths(mold_stem)[0], folder)
    data = sheets_data(result, [d[1] for d in drawings], units=units, scale=opts.scale,
                       engine=opts.engine, time_limit=opts.time_limit, seed=opts.seed,
                       previews=opts.previews)
    metrics = sheets_metrics(data)
    if combined is not None:
        data["combined"] = combined.record()
        metrics["classes"] = {c["id"]: c["quantity"] for c in combined.classes}
    files = sheets_files(output, data=data, extra=extra, obj=sheets_obj(result),
                         inputs=inputs, parameters=_parameters(opts, sheet, units,
                                                               mold_stem is not None),
                         metrics=metrics,
                         status=with_accepted({"sheet_count": result.sheet_count,
                                              "deterministic": opts.engine == "fill"}, carried))
    write_files(with_3dm(files, output, fmt, parts=flat_parts), force=force)
    written(out_json)
