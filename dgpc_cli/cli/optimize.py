"""``dgpc optimize``: guided projection in one of the modes of SPEC §4."""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt
from dgpc_cli.cli.progress import SolverProgress
from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.core.solver import Schedule
from dgpc_cli.core.solver.linear import BACKENDS
from dgpc_cli.errors import DgpcError, NotConverged
from dgpc_cli.geodesics.extension import fit_surface
from dgpc_cli.io.artifact import (
    artifact_paths,
    file_input,
    load_envelope,
    recorded_file,
    resolve_input,
)
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.handles import read_handles
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import NetArtifact, net_files, net_shape, read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import from_mm, mm_per_unit
from dgpc_cli.stages.inspect import summarize
from dgpc_cli.stages.modes import MODES, RELAX, SOFT, describe_weights, mode_weights
from dgpc_cli.stages.net_size import OPTIMIZE_BYTES_PER_VERTEX, check_net_size
from dgpc_cli.stages.optimize import boundary_vertices, judge, optimize_net
from dgpc_cli.stages.polish import polish_weights
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)


def _reference(net: NetArtifact, json_path: Path, reference: Path | None, mode: str,
               keep: bool = True):
    """The reference mesh: --reference, else the one the net records unless ``keep`` is off
    (--no-reference; fit needs one), checked against its recorded sha256; only its largest
    piece when the net was made with ``init --largest-component``."""
    if reference is None and keep and net.data.get("reference"):
        record = net.data["reference"]
        if isinstance(record, dict) and isinstance(record.get("path"), str) \
                and not resolve_input(record, json_path).is_file():
            raise DgpcError(f"data.reference: the reference it records, {record['path']}, is "
                            "missing (give --reference MESH, or --no-reference to drop it)",
                            source=json_path)
        reference = recorded_file(record, json_path, "data.reference")
        log.info("using the reference recorded in %s: %s", json_path, reference)
    if reference is None:
        if mode == "fit":
            raise DgpcError("--mode fit needs a reference mesh (--reference MESH)",
                            source="--no-reference" if not keep else "--reference")
        return None
    return load_mesh(reference, pieces=net.reference_pieces)


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
                               "0.2 % of the reference's bounding-box diagonal]."))
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
    artifact is still written, with its status).
    """
    try:
        schedules = mode_weights(mode, weights)
    except ValueError as err:
        raise click.BadParameter(str(err), ctx=ctx, param_hint="--weight") from None
    if no_reference and reference is not None:
        raise click.UsageError("give --reference or --no-reference, not both")
    json_path, _ = artifact_paths(stem)
    check_writable(output, force)
    m, n = net_shape(load_envelope(json_path, "net")["data"], json_path)
    check_net_size(m, n, str(json_path), "optimize a coarser net (init --rows/--cols)",
                   per_vertex=OPTIMIZE_BYTES_PER_VERTEX[mode],
                   what=f"optimizing ({mode}) a net of")
    net = read_net(stem)
    mesh = _reference(net, json_path, reference, mode, keep=not no_reference)
    if mesh is None:  # the terms that need a reference are off, and the record says so
        schedules.update({name: Schedule.constant(0.0) for name in ("approximation", "boundary")
                          if name in schedules})
    if mode == "fit":
        schedules = polish_weights(net.f, schedules, weights)
    handle_ids = handle_targets = None
    mm = mm_per_unit(net.units)      # the stages compute in mm (dgpc_cli.io.units)
    if handles is not None:
        handle_ids, handle_targets = read_handles(handles, net.shape, net.f_mm, scale=mm)
    if mode == "isometric" and handle_ids is None:
        raise click.UsageError("--mode isometric needs --handles")

    with SolverProgress(ctx, f"optimize ({mode})", tol) as progress:
        fit = fit_surface(mesh, net.extend) if mesh is not None else None
        surface = ReferenceSurface(fit.vertices * mm, fit.faces) if fit is not None else None
        # a net that runs past its reference (init --extend) has no rim on its boundary
        rim = (boundary_vertices(net.f_mm, surface)
               if surface is not None and not net.extend
               and schedules.get("boundary", Schedule.constant(0)).end > 0 else None)
        outcome = optimize_net(
            net.f_mm, schedules, reference=surface, boundary_ids=rim,
            handle_ids=handle_ids, handle_targets=handle_targets, soft=SOFT[mode], steps=steps,
            max_iter=max_iter, tol=tol, backend=backend, progress=progress,
            relax=RELAX.get(mode), gpc_tol=gpc_tol if mode == "isometric" else None,
            max_strain=max_strain if mode == "isometric" else None)

    out_json, _ = artifact_paths(output)
    folder = out_json.resolve().parent
    inputs = {"net": file_input(json_path, folder)}
    # the analytic surface (and its axis, for Clairaut) still carries the net only when the net
    # was fitted to it; the other modes move the net off it
    data = {k: v for k, v in net.data.items() if k == "surface" and mode == "fit"}
    if mesh is not None:
        inputs["reference"] = data["reference"] = file_input(mesh.path, folder)
    if handle_ids is not None:
        inputs["handles"] = file_input(handles, folder)
        data["handles"] = {"ids": handle_ids.tolist(), "targets": (handle_targets / mm).tolist()}
    if rim is not None and len(rim):
        data["boundary"] = {"ids": rim.tolist()}
    result = NetArtifact(
        f=from_mm(outcome.f, net.units), units=net.units,
        parameters={"mode": mode, "weights": describe_weights(schedules),
                    "soft": [*SOFT[mode], *outcome.released], "steps": steps,
                    "max_iter": outcome.max_iter, "tol": tol, "max_strain": max_strain,
                    "gpc_tol": gpc_tol, "solver": backend,
                    "coverage_tol": None if coverage_tol is None else coverage_tol.text(),
                    **net.reference_parameters()},
        inputs=inputs, data=data)
    outcome.status, outcome.message = judge(outcome, net.f_mm, mode=mode,
                                            max_strain=max_strain, gpc_tol=gpc_tol)
    result.status = outcome.record()
    result.metrics = summarize(result, mesh=mesh,
                               against=net if mode == "isometric" else None,
                               surface=surface.scaled(1.0 / mm) if surface is not None else None,
                               coverage_tol=(None if coverage_tol is None
                                             else coverage_tol.in_units(net.units, net.units)))
    write_files(with_3dm(net_files(output, result), output, fmt), force=force)
    click.echo(str(out_json))
    log.info("%s: %s, %d iterations, R = %.3g", out_json, outcome.status, outcome.iterations,
             result.metrics["R"])
    if not outcome.converged:
        raise NotConverged(f"{outcome.status.replace('_', ' ')}: {outcome.message}; written "
                           "anyway", source=out_json)
