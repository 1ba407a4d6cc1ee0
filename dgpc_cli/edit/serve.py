"""``dgpc edit``'s run: the page served on a checked address until Ctrl-C, or a drags file
replayed without a page."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.edit.fabrication import fabrication_figures
from dgpc_cli.edit.fabrication_worker import FabricationWorker
from dgpc_cli.edit.listen import check_bound, listening_port
from dgpc_cli.edit.live import LiveSolver, Request
from dgpc_cli.edit.replay import replay, write_log
from dgpc_cli.edit.session import EditSession, handles_file
from dgpc_cli.errors import NotConverged
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.drags import read_drags
from dgpc_cli.io.handles import read_handles
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize

log = logging.getLogger(__name__)


def run_edit(stem: Path, settings: OptimizeSettings, handles: Path | None, output: Path, *,
             say: Callable[[str], None], drags: Path | None, log_path: Path, host: str,
             port: int, next_free_port: bool = False) -> None:
    """``dgpc edit``: a session on the net ``stem`` (its handles from the file ``handles``,
    if any), then the drags file ``drags`` replayed (:func:`replay_drags`) or, without one,
    the page served (:func:`serve`) on ``host:port`` (checked first, before any work:
    :func:`~dgpc_cli.edit.listen.listening_port`). ``say`` prints to stdout."""
    if drags is None:
        port = listening_port(host, port, next_free_port)
    prepared = prepare_optimize(stem, settings)
    net = prepared.net
    start = {}
    if handles is not None:
        ids, targets = read_handles(handles, net.shape, net.f_mm, scale=prepared.mm)
        start = {int(i): tuple(float(c) for c in t / prepared.mm)
                 for i, t in zip(ids, targets, strict=True)}
    session = EditSession(prepared, start)
    if drags is not None:
        replay_drags(session, drags, output, log_path, say)
    else:
        serve(session, host, port, output, settings.max_strain, say)


def replay_drags(session: EditSession, drags: Path, output: Path, log_path: Path,
                 say: Callable[[str], None]) -> None:
    """Replay the drags file ``drags`` on ``session`` (see :func:`~dgpc_cli.edit.replay.
    replay`), write the artifact, the handles file and the latency log ``log_path``; ``say``
    the artifact's path (stdout). Raises NotConverged (after writing) as ``optimize`` does."""
    out_json, _ = artifact_paths(output)
    events = read_drags(drags, session.shape)
    outcome, latency = replay(session, events, output)
    write_log(log_path, latency)
    say(str(out_json))
    shown = [e["latency"] for e in latency["events"] if "latency" in e]
    log.info("%s: %s; %d events shown, median latency %.1f ms; log %s", out_json,
             outcome.status, len(shown),
             1000 * sorted(shown)[len(shown) // 2] if shown else float("nan"), log_path)
    if not outcome.converged:
        raise NotConverged(f"{outcome.status.replace('_', ' ')}: {outcome.message}; "
                           "written anyway", source=out_json)


def serve(session: EditSession, host: str, port: int, output: Path, limit: float,
          say: Callable[[str], None]) -> None:
    """Serve the page of ``session`` on ``host:port`` until Ctrl-C (DgpcError where the server
    took another port than ``port``: :func:`~dgpc_cli.edit.listen.check_bound`); ``say`` the
    page's address, and the artifact's path on every save (stdout)."""
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
            page.saved_to(f"**Not done**: {answer.error}")

    solver = LiveSolver(session, on_frame, fabrication=fabrication.is_set)

    def fabricated(f_mm, result):
        """The pipeline's figures came: a frame with them, from the solver thread."""
        solver.submit(Request("call", (lambda s: s.fabricated(f_mm, result),)))

    worker = FabricationWorker(
        lambda f_mm: fabrication_figures(f_mm, session.prepared.net.units), fabricated)
    session.fabricate = worker.ask

    def save(s: EditSession):
        outcome = s.save(output)
        out_json, _ = artifact_paths(output)
        say(str(out_json))
        page_box[0].saved_to(f"Saved **{out_json.name}** ({outcome.status.replace('_', ' ')}) "
                             f"and {handles_file(output).name}", saved=True)

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
    reference = None if mesh is None else (mesh.vertices, mesh.faces)
    page = EditPage(session.frame(), Actions(), host=host, port=port,
                    title=f"dgpc edit {session.prepared.json_path.name}", reference=reference,
                    max_strain=limit)
    try:
        check_bound(host, port, page.server.get_port())
    except Exception:
        worker.close()
        solver.close()
        page.stop()
        raise
    page_box.append(page)
    if session.handles:
        solver.submit(Request("settle"))
    say(page.url)
    log.info("serving the page on %s (Ctrl-C to stop)", page.url)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        log.info("stopped")
    finally:
        worker.close()
        solver.close()
        page.stop()
