"""``dgpc report``: figures of an artifact (SPEC §2). So far: flat artifacts (paper Fig. 18)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.inspect import artifact_kind
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import read_flat
from dgpc_cli.stages.report import overlay_png, strips_png


def report_paths(prefix: Path) -> tuple[Path, Path]:
    """``PREFIX-overlay.png`` and ``PREFIX-strips.png``."""
    text = str(prefix)
    if text.lower().endswith(".png"):
        text = text[:-4]
    return Path(text + "-overlay.png"), Path(text + "-strips.png")


@click.command(short_help="Write figures of an artifact (PNG).")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("-o", "--output", "output", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Figure prefix: writes PREFIX-overlay.png and PREFIX-strips.png.")
@click.option("--force", is_flag=True, help="Overwrite existing output files.")
def report(stem, output, force):
    """Figures of the artifact STEM. For a flat artifact: the developed strips aligned on their
    class representatives (paper Fig. 18 bottom-right) and side by side (Fig. 18 bottom-left).
    Prints the paths written."""
    json_path, _ = artifact_paths(stem)
    kind = artifact_kind(json_path)
    if kind != "flat":
        raise DgpcError(f"reports of '{kind}' artifacts are not supported yet (only 'flat')",
                        source=json_path)
    paths = report_paths(output)
    if not force:
        for p in paths:
            if p.exists():
                raise DgpcError("already exists; use --force to overwrite", source=p)
    flat = read_flat(json_path)
    overlay, side = paths
    write_files({overlay: overlay_png(flat.parts, flat.classes), side: strips_png(flat.parts)},
                force=force)
    for p in paths:
        click.echo(str(p))
