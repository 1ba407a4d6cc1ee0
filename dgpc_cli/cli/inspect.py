"""``dgpc inspect``: an artifact's metrics as JSON on stdout (SPEC §7)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.io.artifact import dumps_json
from dgpc_cli.metrics.clairaut import parse_axis
from dgpc_cli.stages.inspect_kinds import inspect_artifact


def _axis(ctx, param, value):
    if value is None:
        return None
    try:
        return parse_axis(value)
    except ValueError as err:
        raise click.BadParameter(str(err), ctx=ctx, param=param) from None


@click.command(short_help="Print an artifact's metrics as JSON.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--axis", callback=_axis, metavar="px,py,pz,dx,dy,dz",
              help="Axis of revolution for Clairaut's relation (default: the one the net "
                   "records, if any).")
@click.option("--against", type=click.Path(path_type=Path), metavar="STEM0",
              help="Reference net for the strain (same grid).")
@click.option("--coverage-tol", type=LengthParam(min=0, min_open=True), default=None,
              help=length_help("Net: a point of the reference counts as covered when the net "
                               "passes within this distance of it [default: 0.2 % of the "
                               "reference's bounding-box diagonal].",
                               plausible="up to 10 % of the reference's diagonal"))
def inspect(stem, axis, against, coverage_tol):
    """Print the metrics of the artifact STEM (docs/metrics.md) as JSON on stdout.

    For a net: R (the paper's constraint error at mean edge length 1), geometric residuals,
    Clairaut (with an axis), strain (with --against), Hausdorff distance (when the net records a
    reference mesh that is still there).
    """
    def check_kind(kind: str, json_path: Path):
        for name, value in (("--axis", axis), ("--against", against),
                            ("--coverage-tol", coverage_tol)):
            if value is not None and kind not in ("net", "patchset"):
                raise click.UsageError(f"{name} applies to a net; {json_path} is a {kind} "
                                       "artifact")

    metrics = inspect_artifact(stem, check_kind=check_kind, axis=axis, against=against,
                               coverage_tol=coverage_tol)
    click.echo(dumps_json(metrics).decode(), nl=False)
