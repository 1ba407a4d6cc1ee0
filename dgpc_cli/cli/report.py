"""``dgpc report``: figures of any artifact and an ``index.html`` with its metrics (SPEC §2)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.output_path import OutputPath


@click.command(short_help="Write figures of artifacts (PNG) and an index.html.")
@click.argument("stems", metavar="STEM [STEM ...]", nargs=-1, required=True,
                type=click.Path(path_type=Path))
@click.option("-o", "--output", "output", required=True,
              type=OutputPath(),
              help="Prefix: writes PREFIX-<figure>.png and PREFIX-index.html.")
@click.option("--force", is_flag=True, help="Overwrite existing output files.")
def report(stems, output, force):
    """Figures of the artifact STEM and PREFIX-index.html showing them with the artifact's
    metrics as a table. Several STEMs (a project's net, strips, flat parts, sheets, mold):
    each one's report under PREFIX-NAME (NAME its file name) and PREFIX-index.html showing
    all their figures, each with a link to its own page; a patch set (init --patches) counts
    as its members. Per kind:

    \b
    net     PREFIX-width.png (strip width), PREFIX-curvature.png (Gaussian curvature K, red
            positive / blue negative / white 0, Fig. 17), PREFIX-coverage.png (the net over
            its recorded reference, uncovered area orange), PREFIX-strain.png (isometric
            optimization with its input net at hand: principal directions over |λ1| + |λ2|,
            Fig. 13), PREFIX-clairaut.png (net with a recorded axis of revolution, Fig. 11),
            PREFIX-convergence.png (the solver history of an optimized net)
    strips  PREFIX-width.png (the planar-quad strips coloured by their width across),
            PREFIX-template.png (every developed strip overlaid on the template, its ends
            magnified, Fig. 18) and PREFIX-deviation.png (the strips coloured by their
            distance from the net in mm, seams stepping over 1 % of the width in red), both
            when the net is at hand
    flat    PREFIX-overlay.png (one cell per congruence class), PREFIX-strips.png (the
            developed parts laid out like a sheet, Fig. 18)
    mold    PREFIX-profile.png (the meridian profile), PREFIX-pairing-netK.png (each panel on
            the mold and on design net K in one colour, Fig. 16), PREFIX-pieces.png (mold
            pieces and flat panels, Fig. 17)
    laths   PREFIX-laths.png (the two lath families of a gridshell, Fig. 14)
    sheets  PREFIX-sheetNN.png, PREFIX-moldmap.png (the previews of dgpc nest with a legend
            of their layers)

    \b
    3-D figures show the model in three views (axonometric, plan, elevation), each framed
    on its bounding box, with a scale bar in the artifact's unit. The index has a header
    (what, from which inputs, status) and the metrics grouped into geometry, fabrication
    and solver with their units. Prints the paths written, the index last.
    """
    from dgpc_cli.stages.report_run import run_report

    run_report(stems, output, force=force, written=lambda p: click.echo(str(p)))
