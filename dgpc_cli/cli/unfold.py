"""``dgpc unfold``: develop planar-quad strips and find congruence classes (SPEC §6)."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import FlatArtifact, csv_path, flat_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import mm_per_unit, to_mm
from dgpc_cli.stages.soundness import require_sound_strips
from dgpc_cli.stages.unfold import (
    CONGRUENCE_TOL,
    STAGGER_FRACTION,
    flat_metrics,
    records_in_units,
    unfold_strips,
)

log = logging.getLogger(__name__)


@click.command(short_help="Develop strips into the plane; group them into congruence classes.")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mirror-ok", is_flag=True,
              help="Count mirror images as congruent (parts that may be flipped over).")
@click.option("--congruence-tol", type=FiniteFloat(min=0, min_open=True),
              default=CONGRUENCE_TOL, show_default=True,
              help="Strips are congruent when, optimally aligned, no point of their outlines "
                   "is farther apart than this fraction of the strip length.")
@click.option("--stock-length", type=FiniteFloat(min=0, min_open=True), metavar="L",
              help="Cut every strip longer than L (in the strips' unit) at rulings into boards "
                   "no longer than L: part ids S-v07.1, S-v07.2, ...")
@click.option("--stagger", type=FiniteFloat(min=0), metavar="D",
              help="With --stock-length: no joint of a strip within D (along the geodesic) of "
                   f"a joint of the strips beside it [default: {STAGGER_FRACTION:g} L].")
@output_opt
@force_opt
@format_opt
def unfold(stem, mirror_ok, congruence_tol, stock_length, stagger, output, force, fmt):
    """Develop the planar-quad strips of the strips artifact STEM into the plane (paper §6.2.4).

    Records per part the closed outline, the rulings (score lines), a label point, the edge
    strain and the straightness of the developed geodesics; groups the parts into congruence
    classes with a representative and each member's alignment error. With --stock-length,
    strips are cut at rulings into boards of stock length, the joints of neighbouring strips
    staggered; congruence classes are then per board. Writes the flat artifact -o STEM2 and its
    cut list STEM2.parts.csv (mm).
    """
    if stagger is not None and stock_length is None:
        raise click.UsageError("--stagger goes with --stock-length")
    json_path, _ = artifact_paths(stem)
    check_writable(output, force, csv_path(output))
    strips = read_strips(stem)
    require_sound_strips(strips.geometry, [r["id"] for r in strips.records], json_path)
    mm = mm_per_unit(strips.units)       # computed in mm (dgpc_cli.io.units)
    parts, classes, joints = unfold_strips(
        [(to_mm(A, strips.units), to_mm(B, strips.units)) for A, B in strips.geometry],
        [r["id"] for r in strips.records], [r["v"] for r in strips.records],
        congruence_tol=congruence_tol, mirror_ok=mirror_ok,
        stock_length=None if stock_length is None else stock_length * mm,
        stagger=None if stagger is None else stagger * mm, source=json_path,
        trims=[r.get("trim") for r in strips.records])
    parts, classes, joints = records_in_units(parts, classes, joints, strips.units)
    out_json, _ = artifact_paths(output)
    art = FlatArtifact(
        parts=parts, classes=classes, units=strips.units, joints=joints,
        parameters={"mirror_ok": mirror_ok, "congruence_tol": congruence_tol,
                    "stock_length": stock_length,
                    "stagger": (stagger if stagger is not None or stock_length is None
                                else STAGGER_FRACTION * stock_length)},
        inputs={"strips": file_input(json_path, out_json.resolve().parent)},
        metrics=flat_metrics(parts, classes), status={"n_classes": len(classes)})
    write_files(with_3dm(flat_files(output, art), output, fmt), force=force)
    click.echo(str(out_json))
