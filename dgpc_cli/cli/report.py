"""``dgpc report``: figures of any artifact and an ``index.html`` with its metrics (SPEC §2)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.inspect import artifact_kind
from dgpc_cli.cli.output_path import OutputPath
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import write_files
from dgpc_cli.stages.report import previous_report_files, report_files


@click.command(short_help="Write figures of an artifact (PNG) and an index.html.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("-o", "--output", "output", required=True,
              type=OutputPath(),
              help="Prefix: writes PREFIX-<figure>.png and PREFIX-index.html.")
@click.option("--force", is_flag=True, help="Overwrite existing output files.")
def report(stem, output, force):
    """Figures of the artifact STEM and PREFIX-index.html showing them with the artifact's
    metrics as a table. Per kind:

    \b
    net     PREFIX-width.png (strip width), PREFIX-curvature.png (Gaussian curvature K, red
            positive / blue negative / white 0, Fig. 17), PREFIX-strain.png (isometric
            optimization with its input net at hand, Fig. 13), PREFIX-clairaut.png (net with
            a recorded axis of revolution, Fig. 11); 3-D views from one fixed angle
    strips  PREFIX-width.png (the planar-quad strips coloured by width)
    flat    PREFIX-overlay.png, PREFIX-strips.png (developed strips, Fig. 18)
    mold    PREFIX-profile.png (the meridian profile)
    laths   PREFIX-laths.png (the two lath families of a gridshell, Fig. 14)
    sheets  the index links the sheet previews written by dgpc nest

    Prints the paths written, the index last.
    """
    json_path, _ = artifact_paths(stem)
    kind = artifact_kind(json_path)
    files = report_files(json_path, kind, output)
    write_files(files, force=force, replaces=previous_report_files(output))
    for p in files:
        click.echo(str(p))
