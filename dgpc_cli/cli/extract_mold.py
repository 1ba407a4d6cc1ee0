"""``dgpc extract-mold``: the surface of revolution, mold pieces and panel-to-mold map (SPEC §6)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    accept_status_opt,
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
from dgpc_cli.io.mold import mold_paths
from dgpc_cli.mold.extract import (
    DEFAULT_FLAT_TOL,
    DEFAULT_MAX_STRAIN,
    DEFAULT_PANEL_SIZE,
    LAMBDA_CHOICES,
)
from dgpc_cli.stages.extract_mold_run import MoldOptions, run_extract_mold


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
                               "limit].", plausible="up to the whole mold's length along its "
                                                    "meridian"))
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
@accept_status_opt
@output_opt
@force_opt
@format_opt
@click.pass_context
def extract_mold_cmd(ctx, nets, segments, lam, panel_size, flat_tol, mold_max_length, tol,
                     max_strain, units_check, accept_status, output, force, fmt):
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
    paths = mold_paths(output)
    check_writable(output, force, *(paths[k] for k in ("profile_csv", "profile_dxf",
                                                        "panels_csv", "panels_obj")))
    opts = MoldOptions(segments=segments, lam=lam, panel_size=panel_size, flat_tol=flat_tol,
                       max_length=mold_max_length, tol=tol, max_strain=max_strain,
                       accept_status=accept_status)

    def chosen(line: str):
        if show_progress(ctx):
            click.echo(line, err=True)

    run_extract_mold(nets, output, opts, force=force, fmt=fmt,
                     check_units=lambda unit, source: check_units(units_check, unit, source),
                     chosen=chosen, written=lambda json_path: click.echo(str(json_path)))
