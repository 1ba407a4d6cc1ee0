"""``dgpc init``: an initial net on an analytic surface (SPEC §5)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.options import check_writable, force_opt, output_opt
from dgpc_cli.io.artifact import artifact_paths, file_input, relative_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import net_files
from dgpc_cli.stages.init import init_revolution
from dgpc_cli.stages.inspect import summarize
from dgpc_cli.surfaces.profiles import describe_builtins


@click.command(short_help="Make an initial net.",
               epilog="Built-in profiles:\n\n\b\n" + describe_builtins())
@click.option("--surface", type=click.Choice(["revolution"]), required=True,
              help="Analytic surface: 'revolution' (profile revolved about the z axis).")
@click.option("--profile", required=True, metavar="NAME|FILE",
              help="Built-in profile name, or a CSV file with header 'r,h'.")
@click.option("--rows", "rows", type=click.IntRange(min=3), required=True,
              help="m: vertices along the geodesics (the meridians).")
@click.option("--cols", "cols", type=click.IntRange(min=3), required=True,
              help="n: vertices across (along the parallels).")
@click.option("--span", "span", type=float, default=180.0, show_default=True,
              help="Angle covered by the v-lines, degrees (360: a full ring).")
@click.option("--twist", type=float, default=0.0, show_default=True,
              help="Shear T, radians: the angle of f(u, v) gets T·s(u)/s_total added, so the "
                   "initial u-lines are not meridians (paper Fig. 11).")
@click.option("--reference-out", type=click.Path(dir_okay=False, path_type=Path),
              help="Also write the triangulated surface (OBJ), fine enough to be the "
                   "reference for `optimize --mode fit`.")
@output_opt
@force_opt
def init(surface, profile, rows, cols, span, twist, reference_out, output, force):
    """Make an m×n net on a surface of revolution, meridians as u-lines.

    The z axis is the axis of revolution. A CSV profile is resampled by arc length.
    """
    check_writable(output, force, *([reference_out] if reference_out else []))
    result = init_revolution(profile, rows, cols, span_deg=span, twist=twist,
                             reference_out=reference_out)
    net = result.net
    json_path, _ = artifact_paths(output)
    folder = json_path.resolve().parent
    if "profile" in net.inputs:
        net.inputs["profile"] = file_input(net.inputs["profile"], folder)
    files = {}
    if result.reference_obj is not None:
        record = relative_input(reference_out, folder, result.reference_obj)
        net.data["reference"] = record
        files[reference_out] = result.reference_obj
    net.metrics = summarize(net)
    files.update(net_files(output, net))
    write_files(files, force=force)
    click.echo(str(json_path))
