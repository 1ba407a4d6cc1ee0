"""Progress of an optimization on stderr that tells the truth (SPEC §2): the handle step, the
iteration, the hard residual against its target and an ETA from the convergence rate.

Shown only on an interactive terminal and without ``-q``; a pipe or a log file gets nothing
(``-v`` logs every step instead), and stdout is never touched.
"""

from __future__ import annotations

import math
import sys
import time

import click

from dgpc_cli.cli.options import show_progress

#: Iterations over which the convergence rate is measured.
RATE_WINDOW = 5


class SolverProgress:
    """A one-line status ``LABEL step s/S · iteration k · R 3.2e-05 → 1e-09 · ETA 4 s``,
    rewritten in place. Call the instance with ``(k, record)`` (the solver's callback; the
    record carries ``R``, ``step``, ``steps`` and ``phase``)."""

    def __init__(self, ctx, label: str, target: float, stream=None):
        self.stream = stream or sys.stderr
        self.label, self.target = label, target
        self.visible = show_progress(ctx) and self.stream.isatty()
        self.started = time.monotonic()
        self.history: list[float] = []          # R per iteration of the current phase
        self.phase_key = None
        self.per_step: list[int] = []           # iterations of the finished handle steps
        self.count = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.visible:
            click.echo("", err=True)

    def eta(self, record: dict) -> float | None:
        """Seconds left: the current phase from its convergence rate, then the handle steps
        still to come at the mean iterations of those done (None when not yet known)."""
        if len(self.history) <= RATE_WINDOW or self.count == 0:
            return None
        now, past = self.history[-1], self.history[-1 - RATE_WINDOW]
        if not (now > 0 and past > 0):
            return None
        rate = (math.log(now) - math.log(past)) / RATE_WINDOW
        left = 0.0 if now <= self.target else (math.log(self.target / now) / rate
                                               if rate < 0 else math.inf)
        steps_left = record.get("steps", 1) - record.get("step", 1)
        if steps_left > 0 and self.per_step:
            left += steps_left * sum(self.per_step) / len(self.per_step)
        return left * (time.monotonic() - self.started) / self.count

    def __call__(self, k: int, record: dict) -> None:
        key = (record.get("phase", ""), record.get("step", 1))
        if key != self.phase_key:
            if self.phase_key is not None and self.phase_key[0] == "step":
                self.per_step.append(len(self.history))
            self.phase_key, self.history = key, []
        self.history.append(float(record.get("R", math.nan)))
        self.count += 1
        if not self.visible:
            return
        parts = [self.label]
        if record.get("phase") == "step" and record.get("steps", 1) > 1:
            parts.append(f"step {record['step']}/{record['steps']}")
        elif record.get("phase") not in (None, "step"):
            parts.append(str(record["phase"]))
        parts.append(f"iteration {k + 1}")
        parts.append(f"R {record.get('R', math.nan):.1e} → {self.target:g}")
        eta = self.eta(record)
        if eta is not None:
            parts.append("ETA " + ("?" if math.isinf(eta) else f"{eta:.0f} s"))
        self.stream.write("\r" + " · ".join(parts).ljust(78))
        self.stream.flush()


class StatusLine:
    """A one-line status ``LABEL: TEXT`` rewritten in place on stderr for a stage that tries
    things one after another (``init``'s search of candidates): call the instance with the
    text. Shown as :class:`SolverProgress` is (an interactive terminal, no ``-q``); with ``-v``
    the stage's log says the same, line by line."""

    def __init__(self, ctx, label: str, stream=None):
        self.stream = stream or sys.stderr
        self.label = label
        self.visible = show_progress(ctx) and self.stream.isatty()
        self.started = time.monotonic()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.visible:
            self.stream.write("\r" + " " * 78 + "\r")
            self.stream.flush()

    def __call__(self, text: str) -> None:
        if not self.visible:
            return
        elapsed = time.monotonic() - self.started
        line = f"{self.label}: {text} · {elapsed:.0f} s"
        self.stream.write("\r" + line[:78].ljust(78))
        self.stream.flush()
