"""The solver thread of ``dgpc edit``: requests from the page (or a replayed drags file) run
one at a time on the session, off the page's thread; a newer drag of a handle supersedes one
still waiting, and any new request abandons a settling run (it starts again when the drag
ends). Every request answered gives a :class:`~dgpc_cli.edit.session.Frame` to
``on_frame``, with the seconds from the request's arrival."""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from dgpc_cli.edit.session import EditSession, Frame, Superseded

log = logging.getLogger(__name__)

#: Seconds a drag must rest (no request waiting) before its net's colours, flags and status
#: are worked out anew: while the handle moves every event shows the net alone, at once.
REFRESH_IDLE = 0.15


@dataclass
class Request:
    """``action`` one of drag, pin, release, undo, redo, settle, save, call (``args`` its
    arguments); ``end`` closes a drag (the net then settles)."""

    action: str
    args: tuple = ()
    end: bool = False
    arrived: float = field(default_factory=time.perf_counter)
    tag: object = None                    # the caller's id of the request (replay: the event)
    #: CPU seconds of the solver thread when it took the request up (its own cost, whatever
    #: else the machine runs, is ``time.thread_time()`` minus this).
    cpu: float = 0.0


@dataclass
class Answer:
    request: Request
    frame: Frame | None
    latency: float
    error: str | None = None
    #: A full frame (colours, flags, status) that follows a drag's quick one when idle.
    refresh: bool = False


class LiveSolver:
    """Runs the requests on ``session`` in a daemon thread; ``on_frame(answer)`` is called in
    that thread after each request (``frame`` None for a superseded one)."""

    def __init__(self, session: EditSession, on_frame: Callable[[Answer], None], *,
                 fabrication: Callable[[], bool] = lambda: False):
        self.session = session
        self.on_frame = on_frame
        self.fabrication = fabrication
        self._queue: deque[Request] = deque()
        self._cond = threading.Condition()
        self._busy = False
        self._settling = False
        self._stop = False
        self._thread = threading.Thread(target=self._run, name="dgpc-edit-solver", daemon=True)
        self._thread.start()

    def submit(self, request: Request) -> None:
        with self._cond:
            last = self._queue[-1] if self._queue else None
            if (request.action == "drag" and last is not None and last.action == "drag"
                    and last.args[:2] == request.args[:2] and not last.end):
                self._queue.pop()                       # superseded before it ran
                self._answer(Answer(last, None, time.perf_counter() - last.arrived))
            self._queue.append(request)
            self._cond.notify_all()

    def wait_idle(self, timeout: float | None = None) -> bool:
        """Block until every request has been answered (False on timeout)."""
        end = None if timeout is None else time.monotonic() + timeout
        with self._cond:
            while self._queue or self._busy:
                left = None if end is None else end - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(left)
        return True

    def close(self) -> None:
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        self._thread.join(timeout=5)

    def _answer(self, answer: Answer) -> None:
        try:
            self.on_frame(answer)
        except Exception:  # noqa: BLE001 - a page that went away must not stop the solver
            log.exception("edit: showing a frame failed")

    def _check(self, _k=None, _record=None) -> None:
        """The settling run's callback: a new request abandons it."""
        if self._queue:
            raise Superseded

    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._queue and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                request = self._queue.popleft()
                self._busy = True
            try:
                self._serve(request)
            finally:
                with self._cond:
                    self._busy = False
                    self._cond.notify_all()

    def _serve(self, request: Request) -> None:
        request.cpu = time.thread_time()
        s = self.session
        error = None
        try:
            if request.action == "drag":
                s.drag(*request.args)
            elif request.action in ("pin", "release"):
                getattr(s, request.action)(*request.args)
            elif request.action in ("undo", "redo"):
                getattr(s, request.action)()
            elif request.action == "settle":
                s.settle(progress=self._check)
            elif request.action == "call":       # e.g. save: fn(session)
                request.args[0](s)
            else:
                raise ValueError(f"unknown request {request.action!r}")
        except Superseded:
            log.info("edit: settling abandoned for a newer request")
            self._answer(Answer(request, None, time.perf_counter() - request.arrived))
            return
        except Exception as err:  # noqa: BLE001 - shown on the page's status line
            log.debug("edit: %s failed", request.action, exc_info=True)
            error = str(err)
        if request.action == "drag":
            # the net first (the latency a designer feels), its figures when nothing waits
            self._answer(Answer(request, s.quick_frame(), time.perf_counter() - request.arrived,
                                error))
            with self._cond:
                if not self._queue and not self._stop:
                    self._cond.wait(REFRESH_IDLE)
                waiting = bool(self._queue)
            if not waiting:
                self._answer(Answer(request, s.frame(fabrication=self.fabrication()),
                                    time.perf_counter() - request.arrived, refresh=True))
        else:
            frame = s.frame(fabrication=self.fabrication())
            self._answer(Answer(request, frame, time.perf_counter() - request.arrived, error))
        if request.end:
            self.submit(Request("settle"))
