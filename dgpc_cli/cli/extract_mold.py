"""``dgpc extract-mold``: the surface of revolution, mold pieces and panel-to-mold map (SPEC §6)."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    check_units,
    check_writable,
    force_opt,
    format_opt,
    from_old_name,
    old_name,
    output_opt,
    show_progress,
    units_check_opt,
)
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.mold import mold_files, mold_paths
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import same_units
from dgpc_cli.mold.dxf import profile_dxf
from dgpc_cli.stages.extract_mold import (
    DEFAULT_FLAT_TOL,
    DEFAULT_MAX_STRAIN,
    DEFAULT_PANEL_SIZE,
    DEFAULT_TOL_FACTOR,
    LAMBDA_CHOICES,
    extract_mold,
    max_length_slip,
)
from dgpc_cli.stages.soundness import require_sound_net

log = logging.getLogger(__name__)


class LambdaParam(click.ParamType):
    """``design``, ``compact`` or a finite number > 0 (Minding's λ)."""

    name = "lambda"

    def get_metavar(self, param, ctx=None) -> str:
        return "|".join(LAMBDA_CHOICES) + "|VALUE"

    def convert(self, value, param, ctx):
        if value in LAMBDA_CHOICES or isinstance(value, float):
            return value
        try:
            return FiniteFloat(min=0, min_open=True).convert(value, param, ctx)
        except click.BadParameter:
            self.fail(f"{value!r} is not a finite number > 0, nor "
                      f"{' or '.join(LAMBDA_CHOICES)}.", param, ctx)


@click.command("extract-mold", short_help="Extract the mold (surface of revolution) of nets.")
@click.argument("nets", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--segments", type=click.IntRange(min=2), default=None,
              help="N, segments of the surface of revolution per full turn, instead of "
                   "--lambda.")
@click.option("--lambda", "lam", type=LambdaParam(), default=None,
              help="Which of the isometric surfaces of revolution (Minding's bending, Prop. "
                   "4.3) is the mold: 'design' (default): the design's own surface, the one "
                   "whose parallels turn as the nets' rows do (λ = 360°/span for a net made "
                   "on it); 'compact': the full-turn surface (λ = 1, N = n−1), smaller, a "
                   "mold to turn on a lathe; VALUE > 0: λ relative to the full turn, "
                   "N = λ·(n−1). stderr says which, with the radii of the other.")
@click.option("--panel-size", type=click.IntRange(min=1), default=DEFAULT_PANEL_SIZE,
              show_default=True, help="K: a panel is a K×K block of net quads.")
@click.option("--flat-tol", type=FiniteFloat(min=0), default=DEFAULT_FLAT_TOL,
              show_default=True,
              help="A panel is flat (no mold) where |K|·l² = |δ_uu w / w| ≤ T on all of it.")
@click.option("--mold-max-length", type=LengthParam(min=0, min_open=True), default=None,
              metavar="LENGTH",
              help=length_help("Longest mold piece along the meridian, > 0 [default: no "
                               "limit]."))
@click.option("--revolution-tol", "tol", type=FiniteFloat(min=0, min_open=True), default=None,
              callback=from_old_name("--revolution-tol"),
              help="Relative tolerance (a ratio, no unit) of equation (5) and of the "
                   "comparison between nets [default: twice --max-strain].")
@old_name("--tol", "--revolution-tol", type=FiniteFloat(min=0, min_open=True))
@click.option("--max-strain", type=FiniteFloat(min=0, min_open=True),
              default=DEFAULT_MAX_STRAIN, show_default=True,
              help="Largest relative difference of a panel's edges and diagonals from its "
                   "mold patch; a net with a panel further off is refused.")
@units_check_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def extract_mold_cmd(ctx, nets, segments, lam, panel_size, flat_tol, mold_max_length, tol,
                     max_strain, units_check, output, force, fmt):
    """Extract the surface of revolution that the nets NET… are isometric to (paper §4.2.2).

    Writes the mold artifact -o MOLD: MOLD.json, MOLD.obj (the surface of revolution and one
    sector), MOLD.profile.csv (r,h), MOLD.profile.dxf (mm, with the axis) and
    MOLD.panels.csv (the panel-to-mold map). Several nets must be isometric to the same
    surface of revolution (one mold for all). stderr says in one line which surface of
    revolution the mold is (--lambda) and why. When x(u) would be imaginary, λ is lowered to
    the largest value that keeps it real (a warning on stderr says to what).
    """
    if segments is not None and lam is not None:
        raise click.UsageError("--segments and --lambda are mutually exclusive")
    if tol is None:
        tol = DEFAULT_TOL_FACTOR * max_strain
    paths = mold_paths(output)
    check_writable(output, force, *(paths[k] for k in ("profile_csv", "profile_dxf",
                                                        "panels_csv", "panels_obj")))
    loaded = [(str(artifact_paths(stem)[0]), read_net(stem)) for stem in nets]
    for name, net in loaded:
        require_sound_net(net.f, name)
    unit = same_units([(name, net.units) for name, net in loaded])
    check_units(units_check, unit, loaded[0][0])
    given = mold_max_length
    if mold_max_length is not None:
        mold_max_length = mold_max_length.in_units(unit, unit)
    mold = extract_mold([(name, net.f) for name, net in loaded], segments=segments, lam=lam,
                        panel_size=panel_size, flat_tol=flat_tol, max_length=mold_max_length,
                        tol=tol, max_strain=max_strain)
    slip = max_length_slip(mold, given, unit)
    if slip is not None:
        raise click.UsageError(slip)
    if show_progress(ctx):
        click.echo(mold.choice_line(unit), err=True)
    folder = paths["json"].resolve().parent
    inputs = {f"net{k + 1}": file_input(name, folder) for k, (name, _) in enumerate(loaded)}
    mer = mold.meridian
    metrics = mold.metrics()
    message = (f"λ lowered from {mer.requested * mer.lam / mer.segments:.6g} to {mer.lam:.6g} "
               "so that every x(u) is real" if mer.lowered else "ok")
    files = mold_files(
        output,
        profile={"r": mer.r, "h": mer.h, "d": mer.d, "l": mer.l, "x": mer.x},
        units=unit,
        profile_dxf=profile_dxf(mer.r, mer.h, unit, [(p.id, p.start, p.stop)
                                                     for p in mold.pieces]),
        segments={"segments": mer.segments, "segments_requested": mer.requested,
                  "lambda": mer.lam, "lambda_lowered": mer.lowered},
        sector_deg=math.degrees(mold.sector_angle),
        pieces=[{"id": p.id, "rows": [p.start, p.stop], "meridian_length": p.length}
                for p in mold.pieces],
        nets=[{"input": f"net{k + 1}", "shape": list(p.shape),
               "column_angles_deg": [math.degrees(t) for t in p.theta.tolist()],
               "revolution_residual_max": p.residual_max} for k, p in enumerate(mold.nets)],
        net_geometry=[net.f for _, net in loaded],
        panels=mold.panel_records(),
        panel_size=panel_size,
        inputs=inputs,
        parameters={"segments": segments, "lambda": mold.choice.how if segments is None
                    and mold.choice.how != "value" else lam, "panel_size": panel_size,
                    "flat_tol": flat_tol, "mold_max_length": mold_max_length,
                    "revolution_tol": tol, "max_strain": max_strain, "units": unit},
        metrics=metrics,
        status={"state": "ok", "lambda_lowered": mer.lowered, "message": message},
    )
    write_files(with_3dm(files, output, fmt), force=force)
    click.echo(str(paths["json"]))
    log.info("%s: N = %.6g (λ = %.6g), %d mold pieces, %d curved and %d flat panels, isometry "
             "error ≤ %.3g", paths["json"], mer.segments, mer.lam, metrics["pieces"],
             metrics["panels_curved"], metrics["panels_flat"], metrics["isometry_error_max"])
