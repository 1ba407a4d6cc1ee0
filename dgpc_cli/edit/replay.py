"""``dgpc edit --replay``: a recorded sequence of drag events through the solver thread of the
page, without a page, at the events' own times; the latency of each event is logged."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.edit.live import Answer, LiveSolver, Request
from dgpc_cli.edit.session import EditSession, Frame
from dgpc_cli.fitting.optimize import OptimizeOutcome
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.drags import DragEvent

#: Seconds a replay waits for the solver after its last event, at most.
REPLAY_TIMEOUT = 3600.0


def event_request(event: DragEvent, tag) -> Request:
    """The solver request of a recorded event."""
    u, v = event.index
    if event.action == "drag":
        return Request("drag", (u, v, event.target), end=event.end, tag=tag)
    return Request(event.action, (u, v), end=event.end, tag=tag)


def replay(session: EditSession, events: list[DragEvent], output: Path,
           handles_path: Path | None = None,
           show: Callable[[Frame], None] | None = None) -> tuple[OptimizeOutcome, dict]:
    """Settle the session's handles, then feed ``events`` (their times counted from there) to a
    :class:`LiveSolver` on ``session`` at their recorded times, let the
    net settle, save the artifact and the handles file (see :meth:`EditSession.save`). Returns
    the outcome and the log: per event its latency (seconds from its arrival to the net
    shown) or ``superseded``, the guided-projection iterations and factorizations run, the
    state shown; per settling run the seconds from the drag's end to the settled net. With
    ``show`` (a page's ``show``), every frame is also handed to it, and ``shown`` logs the
    seconds from the event's arrival to the frame's data sent to the page; ``cpu`` the solver
    thread's CPU seconds from taking the event up to that point (its cost without the wait
    for a loaded machine's cores)."""
    session.settle()                 # the page, too, opens on the settled net
    answers: list[tuple[Answer, float | None, float]] = []

    def on_frame(answer: Answer) -> None:
        shown = None
        if show is not None and answer.frame is not None:
            show(answer.frame)
            shown = time.perf_counter() - answer.request.arrived
        answers.append((answer, shown, time.thread_time() - answer.request.cpu))

    solver = LiveSolver(session, on_frame)
    t0 = time.perf_counter()
    try:
        for k, event in enumerate(events):
            delay = t0 + event.time - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            solver.submit(event_request(event, k))
        solver.wait_idle(REPLAY_TIMEOUT)
    finally:
        solver.close()
    outcome = session.save(output, handles_path)
    records, settles = [], []
    for a, shown, cpu in answers:
        if a.refresh:
            continue
        if a.request.action == "settle":
            if a.frame is not None:
                settles.append({"seconds": a.latency, "state": a.frame.state,
                                "iterations": a.frame.iterations})
            continue
        rec = {"event": a.request.tag, "action": a.request.action}
        if a.frame is None:
            rec["superseded"] = True
        else:
            rec.update(latency=a.latency, iterations=a.frame.iterations,
                       factorizations=a.frame.factorizations, state=a.frame.state)
            if shown is not None:
                rec["shown"] = shown
            rec["cpu"] = cpu
        if a.error:
            rec["error"] = a.error
        records.append(rec)
    return outcome, {"events": records, "settles": settles}


def write_log(path: Path, log: dict) -> None:
    """The replay's latency log as JSON (timings: not part of any compared artifact)."""
    write_files({path: (json.dumps(log, indent=1, sort_keys=True) + "\n").encode()}, force=True)
