"""``dgpc unfold``: develop planar-quad strips and find congruence classes (SPEC §6)."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import FlatArtifact, flat_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import read_strips
from dgpc_cli.stages.soundness import require_sound_strips
from dgpc_cli.stages.unfold import CONGRUENCE_TOL, unfold_strips

log = logging.getLogger(__name__)


@click.command(short_help="Develop strips into the plane; group them into congruence classes.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mirror-ok", is_flag=True,
              help="Count mirror images as congruent (parts that may be flipped over).")
@click.option("--congruence-tol", type=click.FloatRange(min=0, min_open=True),
              default=CONGRUENCE_TOL, show_default=True,
              help="Strips are congruent when, optimally aligned, no point of their outlines "
                   "is farther apart than this fraction of the strip length.")
@output_opt
@force_opt
@format_opt
def unfold(stem, mirror_ok, congruence_tol, output, force, fmt):
    """Develop the planar-quad strips of the strips artifact STEM into the plane (paper §6.2.4).

    Records per part the closed outline, the rulings (score lines), a label point, the edge
    strain and the straightness of the developed geodesics; groups the parts into congruence
    classes with a representative and each member's alignment error. Writes the flat artifact
    -o STEM2.
    """
    json_path, _ = artifact_paths(stem)
    check_writable(output, force)
    strips = read_strips(stem)
    require_sound_strips(strips.geometry, [r["id"] for r in strips.records], json_path)
    parts, classes, metrics = unfold_strips(
        strips.geometry, [r["id"] for r in strips.records], [r["v"] for r in strips.records],
        congruence_tol=congruence_tol, mirror_ok=mirror_ok, source=json_path,
        trims=[r.get("trim") for r in strips.records])
    out_json, _ = artifact_paths(output)
    art = FlatArtifact(
        parts=parts, classes=classes,
        parameters={"mirror_ok": mirror_ok, "congruence_tol": congruence_tol},
        inputs={"strips": file_input(json_path, out_json.resolve().parent)},
        metrics=metrics, status={"n_classes": len(classes)})
    write_files(with_3dm(flat_files(output, art), output, fmt), force=force)
    click.echo(str(out_json))
