"""``dgpc optimize``: guided projection in one of the modes of SPEC §4."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt
from dgpc_cli.cli.patch_set_members import on_members
from dgpc_cli.cli.progress import SolverProgress
from dgpc_cli.core.solver.linear import BACKENDS
from dgpc_cli.fitting.modes import MODES, mode_weights
from dgpc_cli.stages.optimize_artifact import OptimizeSettings
from dgpc_cli.stages.optimize_run import run_optimize
from dgpc_cli.tolerances import tol as TOL


@click.command(short_help="Optimize a net (fit, developable, revolution, isometric).")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mode", type=click.Choice(list(MODES)), required=True,
              help="fit: gpc on a reference; developable: nearly developable (Jacobi (8)); "
                   "revolution: isometric to a surface of revolution (7); isometric: "
                   "isometric deformation by handles.")
@click.option("--reference", type=click.Path(path_type=Path),
              help="Reference triangle mesh (OBJ/PLY/STL/OFF) for the approximation term "
                   "[default: the one the net records].")
@click.option("--no-reference", is_flag=True,
              help="Drop the reference the net records: no approximation or boundary term, "
                   "and the new net records none.")
@click.option("--handles", type=click.Path(path_type=Path),
              help='Handles JSON: {"handles": [{"index": [u, v], "target": [x, y, z]} | '
                   '{"index": [u, v], "offset": [dx, dy, dz]}]}: u the row (0..m−1, along the '
                   'geodesics), v the column (0..n−1); targets and offsets in the net\'s unit '
                   '(its data.units, from init --units).')
@click.option("--steps", type=click.IntRange(min=1), default=1, show_default=True,
              help="Reach the handles in K increments, as a dragged handle would.")
@click.option("--weight", "weights", multiple=True, metavar="NAME=VALUE|NAME=A->B",
              help="Override a term's weight, or a schedule such as fairness=0.01->0 "
                   "(repeatable).")
@click.option("--max-iter", type=click.IntRange(min=1), default=None,
              help="Iteration limit of the whole run, handle steps and the final projection "
                   f"onto the hard constraints included [default: {TOL.max_iter} for each "
                   "step and for the projection].")
@click.option("--tol", type=FiniteFloat(min=0, min_open=True), default=TOL.solver_R,
              show_default=True, help="Tolerance on the residual of the hard constraints "
                                      "(no unit: the net scaled to mean edge length 1).")
@click.option("--max-strain", type=FiniteFloat(min=0, min_open=True),
              default=TOL.max_strain, show_default=True,
              help="revolution: largest relative error of a quad's edges and diagonals against "
                   "the surface of revolution; isometric: largest strain |λ1|+|λ2| against the "
                   "input (§6.1); above it the net is not converged (3e-4: 0.3 mm per metre).")
@click.option("--gpc-tol", type=FiniteFloat(min=0, min_open=True), default=TOL.gpc_tol,
              show_default=True,
              help="isometric: largest angle defect of (6), radians, that counts as converged.")
@click.option("--coverage-tol", type=LengthParam(min=0, min_open=True), default=None,
              help=length_help("With a reference: a point of it counts as covered when the "
                               "net passes within this distance (metrics.coverage) [default: "
                               "0.2 % of the reference's bounding-box diagonal].",
                               plausible="up to 10 % of the reference's diagonal"))
@click.option("--solver", "backend", type=click.Choice(["auto", *BACKENDS]), default="auto",
              show_default=True, help="Sparse linear solver of the normal equations.")
@output_opt
@force_opt
@format_opt
@click.pass_context
def optimize(ctx, stem, mode, reference, no_reference, handles, steps, weights, max_iter, tol,
             max_strain, gpc_tol, coverage_tol, backend, output, force, fmt):
    """Optimize the net STEM with guided projection (paper §5) and write it to -o STEM2.

    Exit code 3 if the last step does not reach --tol, if the net is pleated, in revolution
    mode if a quad is further than --max-strain from the surface of revolution, or, in
    isometric mode, if its strain or gpc angle defect is above --max-strain or --gpc-tol (the
    artifact is still written, with its status). A patch set (init --patches) is optimized
    member by member (-o STEM2.pK, and STEM2 the set of them).
    """
    if on_members(ctx, stem, output, force, "optimize"):
        return
    try:
        schedules = mode_weights(mode, weights)
    except ValueError as err:
        raise click.BadParameter(str(err), ctx=ctx, param_hint="--weight") from None
    if no_reference and reference is not None:
        raise click.UsageError("give --reference or --no-reference, not both")
    check_writable(output, force)
    settings = OptimizeSettings(mode, schedules, steps=steps, max_iter=max_iter, tol=tol,
                                max_strain=max_strain, gpc_tol=gpc_tol, backend=backend,
                                coverage_tol=coverage_tol)
    run_optimize(stem, output, settings, reference=reference, no_reference=no_reference,
                 weights=weights, handles=handles, force=force, fmt=fmt,
                 solver_progress=lambda label, target: SolverProgress(ctx, label, target),
                 written=lambda out_json: click.echo(str(out_json)))
