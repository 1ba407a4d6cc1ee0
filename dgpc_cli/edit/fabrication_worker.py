"""The pipeline's fabrication figures of a settled net, worked out off the solver thread.

``planarize-strips`` and ``unfold`` take seconds (a template fit); run in the solver thread
they would hold up every drag after a release. :class:`FabricationWorker` runs them in a
thread of its own on a copy of the settled net; a newer net waits its turn (only the latest
is worked out), and a result for a net no longer on screen is dropped by the session."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

import numpy as np

log = logging.getLogger(__name__)


class FabricationWorker:
    """``work(f_mm)`` → result, run for the latest net asked (:meth:`ask`); ``done(f_mm,
    result)`` is called in the worker's thread after each run."""

    def __init__(self, work: Callable[[np.ndarray], object],
                 done: Callable[[np.ndarray, object], None]):
        self.work, self.done = work, done
        self._cond = threading.Condition()
        self._next: np.ndarray | None = None
        self._running: np.ndarray | None = None
        self._stop = False
        self._thread = threading.Thread(target=self._run, name="dgpc-edit-fabrication",
                                        daemon=True)
        self._thread.start()

    def ask(self, f_mm: np.ndarray) -> None:
        """Work out the figures of ``f_mm`` (after the run under way; a net asked before
        and not yet started is replaced)."""
        with self._cond:
            if self._running is not None and np.array_equal(self._running, f_mm):
                return
            self._next = np.array(f_mm, dtype=float)
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        self._thread.join(timeout=1)

    def _run(self) -> None:
        while True:
            with self._cond:
                while self._next is None and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                f, self._next = self._next, None
                self._running = f
            try:
                result = self.work(f)
            except Exception:  # noqa: BLE001 - the page keeps going without the figures
                log.exception("edit: the fabrication figures failed")
                result = None
            with self._cond:
                self._running = None
            if result is not None:
                self.done(f, result)
