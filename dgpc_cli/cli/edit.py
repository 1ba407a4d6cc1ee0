"""``dgpc edit``: design by dragging handles in a local web page, or replay recorded drags."""

from __future__ import annotations

import logging
import threading
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import check_writable, force_opt, output_opt
from dgpc_cli.core.solver.linear import BACKENDS
from dgpc_cli.errors import NotConverged
from dgpc_cli.fitting.modes import mode_weights
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.drags import read_drags
from dgpc_cli.io.handles import read_handles
from dgpc_cli.stages.edit_live import LiveSolver, Request
from dgpc_cli.stages.edit_replay import replay, write_log
from dgpc_cli.stages.edit_session import EditSession, handles_file
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)

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
              help="Port of the page (0: a free one).")
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
def edit(stem, mode, handles, host, port, drags, steps, max_iter, tol, max_strain, gpc_tol,
         backend, output, force):
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
    prepared = prepare_optimize(stem, settings)
    net = prepared.net
    start = {}
    if handles is not None:
        ids, targets = read_handles(handles, net.shape, net.f_mm, scale=prepared.mm)
        start = {int(i): tuple(float(c) for c in t / prepared.mm)
                 for i, t in zip(ids, targets, strict=True)}
    session = EditSession(prepared, start)
    if drags is not None:
        events = read_drags(drags, net.shape)
        outcome, latency = replay(session, events, output)
        write_log(log_path, latency)
        click.echo(str(out_json))
        shown = [e["latency"] for e in latency["events"] if "latency" in e]
        log.info("%s: %s; %d events shown, median latency %.1f ms; log %s", out_json,
                 outcome.status, len(shown),
                 1000 * sorted(shown)[len(shown) // 2] if shown else float("nan"), log_path)
        if not outcome.converged:
            raise NotConverged(f"{outcome.status.replace('_', ' ')}: {outcome.message}; "
                               "written anyway", source=out_json)
        return
    _serve(session, host or LOOPBACK, port, output, max_strain)


def _serve(session: EditSession, host: str, port: int, output: Path, limit: float) -> None:
    """Serve the page until Ctrl-C."""
    from dgpc_cli.edit.page import EditPage

    fabrication = threading.Event()
    page_box: list = []

    def on_frame(answer):
        if not page_box:
            return
        page = page_box[0]
        if answer.frame is not None:
            page.show(answer.frame)
        if answer.error:
            page.saved_to(f"⚠️ {answer.error}")

    solver = LiveSolver(session, on_frame, fabrication=fabrication.is_set)

    def save(s: EditSession):
        outcome = s.save(output)
        out_json, _ = artifact_paths(output)
        click.echo(str(out_json))
        page_box[0].saved_to(f"Saved **{out_json.name}** ({outcome.status.replace('_', ' ')}) "
                             f"and {handles_file(output).name}")

    class Actions:
        def drag(self, u, v, target, end):
            solver.submit(Request("drag", (u, v, target), end=end))

        def pin(self, u, v):
            solver.submit(Request("pin", (u, v), end=True))

        def release(self, u, v):
            solver.submit(Request("release", (u, v), end=True))

        def undo(self):
            solver.submit(Request("undo", end=True))

        def redo(self):
            solver.submit(Request("redo", end=True))

        def save(self):
            solver.submit(Request("call", (save,)))

        def fabrication(self, on):
            (fabrication.set if on else fabrication.clear)()
            solver.submit(Request("call", (lambda s: None,)))

    mesh = session.prepared.mesh
    reference = None
    if mesh is not None:
        reference = (mesh.vertices, mesh.faces)
    page = EditPage(session.frame(), Actions(), host=host, port=port,
                    title=f"dgpc edit {session.prepared.json_path.name}", reference=reference,
                    max_strain=limit)
    page_box.append(page)
    if session.handles:
        solver.submit(Request("settle"))
    click.echo(page.url)
    log.info("serving the page on %s (Ctrl-C to stop)", page.url)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        log.info("stopped")
    finally:
        solver.close()
        page.stop()
