"""``dgpc edit``: design by dragging handles in a local web page, or replay recorded drags."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import check_writable, force_opt, output_opt
from dgpc_cli.core.solver.linear import BACKENDS
from dgpc_cli.edit.serve import run_edit
from dgpc_cli.edit.session import handles_file
from dgpc_cli.fitting.modes import mode_weights
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.stages.optimize_artifact import OptimizeSettings
from dgpc_cli.tolerances import tol as TOL

#: The only address the page listens on unless --host says otherwise.
LOOPBACK = "127.0.0.1"


@click.command(short_help="Design by dragging handles in a web page (or replay drags).")
@click.argument("stem", type=click.Path(path_type=Path))
@click.option("--mode", type=click.Choice(["isometric", "revolution"]), default="isometric",
              show_default=True,
              help="isometric: stay isometric to the input's surface of revolution; "
                   "revolution: isometric to some surface of revolution (as optimize).")
@click.option("--handles", type=click.Path(path_type=Path),
              help="Handles JSON to start from (as optimize --handles: grid indices [u, v], "
                   "targets and offsets in the net's unit).")
@click.option("--host", default=None,
              help=f"Address the page listens on [default: {LOOPBACK}, this machine only; "
                   "another address exposes the page to the network].")
@click.option("--port", type=click.IntRange(0, 65535), default=0, show_default=True,
              help="Port of the page (0: a free one). One in use is an error, unless "
                   "--next-free-port.")
@click.option("--next-free-port", is_flag=True,
              help="When --port is in use, take the next free port above it (said on "
                   "stderr).")
@click.option("--replay", "drags", type=click.Path(path_type=Path),
              help='Replay a drags file ({"events": [{"handle": [u, v], "target": [x, y, z], '
                   '"time": s, "end": true}]}) without a page; writes the artifact, the '
                   "handles file and STEM-replay.json (the latency of each event).")
@click.option("--steps", type=click.IntRange(min=1), default=1, show_default=True,
              help="Handle increments of the settling run (as optimize --steps).")
@click.option("--max-iter", type=click.IntRange(min=1), default=None,
              help="Iteration limit of a settling run (as optimize).")
@click.option("--tol", type=FiniteFloat(min=0, min_open=True), default=TOL.solver_R,
              show_default=True, help="Tolerance on the hard residual (as optimize).")
@click.option("--max-strain", type=FiniteFloat(min=0, min_open=True),
              default=TOL.max_strain, show_default=True,
              help="Largest strain (isometric) or panel error (revolution) that converges.")
@click.option("--gpc-tol", type=FiniteFloat(min=0, min_open=True), default=TOL.gpc_tol,
              show_default=True, help="isometric: largest gpc angle defect, radians.")
@click.option("--solver", "backend", type=click.Choice(["auto", *BACKENDS]), default="auto",
              show_default=True, help="Sparse linear solver of the normal equations.")
@output_opt
@force_opt
def edit(stem, mode, handles, host, port, next_free_port, drags, steps, max_iter, tol,
         max_strain, gpc_tol, backend, output, force):
    """Edit the net STEM by its handles: a page on http://127.0.0.1:PORT/ (printed on stdout)
    shows the net coloured by strain (isometric) or panel error (revolution), pleats and
    creases flagged, the handles as gizmos and the status optimize would report. Click a vertex
    to add a handle, drag a gizmo, undo, redo; Save writes -o STEM2 (the artifact optimize
    writes for the saved handles file STEM2-handles.json). Stop with Ctrl-C.

    With --replay the drags file runs without a page: exit code as optimize's (3: the settled
    net misses a tolerance; written anyway).
    """
    out_json, _ = artifact_paths(output)
    log_path = out_json.with_name(out_json.stem + "-replay.json")
    check_writable(output, force, handles_file(output), *([log_path] if drags else []))
    settings = OptimizeSettings(mode, mode_weights(mode), steps=steps, max_iter=max_iter,
                                tol=tol, max_strain=max_strain, gpc_tol=gpc_tol,
                                backend=backend)
    run_edit(stem, settings, handles, output, say=click.echo, drags=drags, log_path=log_path,
             host=host or LOOPBACK, port=port, next_free_port=next_free_port)
