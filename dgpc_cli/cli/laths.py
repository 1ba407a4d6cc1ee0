"""``dgpc laths``: the laths of a geodesic gridshell and their cut list (paper §6.2.1)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import accept_status_opt, check_writable, force_opt, format_opt
from dgpc_cli.cli.output_path import OutputPath
from dgpc_cli.geodesics.laths import GAP
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.stages.laths_run import run_laths


@click.command(short_help="Gridshell laths of two nets and their cut list.")
@click.argument("net_a", type=click.Path(path_type=Path))
@click.argument("net_b", type=click.Path(path_type=Path))
@click.option("--gap", type=LengthParam(min=0, min_open=True), metavar="LENGTH",
              help=length_help(f"Largest distance between two laths at a crossing, > 0 "
                               f"[default: {GAP} × the mean edge length of the nets].",
                               plausible="up to the nets' mean edge"))
@click.option("-o", "--output", "output", required=True,
              type=OutputPath(),
              help="Output stem: writes STEM.json, STEM.obj (laths as polylines) and STEM.csv "
                   "(cut list).")
@accept_status_opt
@force_opt
@format_opt
def laths(net_a, net_b, gap, output, accept_status, force, fmt):
    """Laths of a geodesic gridshell (paper §6.2.1, Fig. 14) from two transversal nets NET_A
    and NET_B on one reference (e.g. `init --method geodesic` with two --direction values, each
    optimized with `--mode fit`).

    The laths are the u-lines (geodesics) of both nets, families A and B. STEM.csv lists per
    lath: id, family, length, the number of crossings with the other family, their arc-length
    positions from the lath's start (u = 0; where the joints are drilled) and the crossing
    laths' ids.
    """
    json_path, _ = artifact_paths(output)
    check_writable(output, force, json_path.with_suffix(".csv"))
    run_laths(net_a, net_b, output, gap, force=force, fmt=fmt,
              written=lambda out_json: click.echo(str(out_json)), accept_status=accept_status)
