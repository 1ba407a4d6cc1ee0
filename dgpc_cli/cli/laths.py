"""``dgpc laths``: the laths of a geodesic gridshell and their cut list (paper §6.2.1)."""

from __future__ import annotations

import logging
from pathlib import Path

import click
import numpy as np

from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import check_writable, force_opt, format_opt
from dgpc_cli.cli.output_path import OutputPath
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.laths import laths_files
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import same_units
from dgpc_cli.stages.laths import GAP, crossing_gap, gap_slip, gridshell
from dgpc_cli.stages.soundness import require_sound_net

log = logging.getLogger(__name__)


@click.command(short_help="Gridshell laths of two nets and their cut list.")
@click.argument("net_a", type=click.Path(path_type=Path))
@click.argument("net_b", type=click.Path(path_type=Path))
@click.option("--gap", type=LengthParam(min=0, min_open=True), metavar="LENGTH",
              help=length_help(f"Largest distance between two laths at a crossing, > 0 "
                               f"[default: {GAP} × the mean edge length of the nets]."))
@click.option("-o", "--output", "output", required=True,
              type=OutputPath(),
              help="Output stem: writes STEM.json, STEM.obj (laths as polylines) and STEM.csv "
                   "(cut list).")
@force_opt
@format_opt
def laths(net_a, net_b, gap, output, force, fmt):
    """Laths of a geodesic gridshell (paper §6.2.1, Fig. 14) from two transversal nets NET_A
    and NET_B on one reference (e.g. `init --method geodesic` with two --direction values, each
    optimized with `--mode fit`).

    The laths are the u-lines (geodesics) of both nets, families A and B. STEM.csv lists per
    lath: id, family, length, the number of crossings with the other family, their arc-length
    positions from the lath's start (u = 0; where the joints are drilled) and the crossing
    laths' ids.
    """
    json_path, obj_path = artifact_paths(output)
    csv_path = json_path.with_suffix(".csv")
    check_writable(output, force, csv_path)
    a, b = read_net(net_a), read_net(net_b)
    if artifact_paths(net_a)[0].resolve() == artifact_paths(net_b)[0].resolve() \
            or np.array_equal(a.f, b.f):
        raise DgpcError("is the same net as NET_A: its laths would lie on their own copies; "
                        "give two transversal nets", source=artifact_paths(net_b)[0])
    require_sound_net(a.f, artifact_paths(net_a)[0])
    require_sound_net(b.f, artifact_paths(net_b)[0])
    units = same_units([(str(artifact_paths(net_a)[0]), a.units),
                        (str(artifact_paths(net_b)[0]), b.units)])
    ref_a, ref_b = a.data.get("reference"), b.data.get("reference")
    if ref_a and ref_b and ref_a.get("sha256") != ref_b.get("sha256"):
        log.warning("%s and %s record different references", net_a, net_b)
    slip = gap_slip(a.f, b.f, gap, units)
    if slip is not None:
        raise click.UsageError(slip)
    gap = crossing_gap(a.f, b.f, None if gap is None else gap.in_units(units, units))
    laths_a, laths_b, crossings = gridshell(a.f, b.f, gap=gap)
    if len(crossings.a) == 0:
        raise DgpcError("the laths of the two nets do not cross (are the nets on one reference, "
                        "in transversal directions?)", source=net_b)
    all_laths = laths_a + laths_b
    lengths = np.array([lt.length for lt in all_laths])
    folder = json_path.resolve().parent
    inputs = {"net_a": file_input(artifact_paths(net_a)[0], folder),
              "net_b": file_input(artifact_paths(net_b)[0], folder)}
    metrics = {"laths": len(all_laths), "crossings": int(len(crossings.a)),
               "crossing_gap_max": float(crossings.gap.max()),
               "length_total": float(lengths.sum()), "length_max": float(lengths.max())}
    files = laths_files(output, all_laths, crossings, units=units, inputs=inputs,
                        parameters={"gap": gap}, metrics=metrics)
    write_files(with_3dm(files, output, fmt), force=force)
    log.info("%d laths, %d crossings, largest gap %.3g", len(all_laths), len(crossings.a),
             metrics["crossing_gap_max"])
    click.echo(str(json_path))
