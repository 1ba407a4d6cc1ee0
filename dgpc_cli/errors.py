"""Domain errors. The CLI turns them into one line on stderr and the exit code of SPEC §2."""

from __future__ import annotations

from pathlib import Path


class DgpcError(Exception):
    """Bad data: unreadable or invalid input, or an infeasible request (exit code 1).

    ``source`` names the file or option at fault; ``str(err)`` is the one-line message.
    """

    exit_code = 1

    def __init__(self, message: str, source: str | Path | None = None):
        self.source = str(source) if source is not None else None
        self.reason = " ".join(str(message).split())  # one line, always
        super().__init__(f"{self.source}: {self.reason}" if self.source else self.reason)


class OptionSlip(Exception):
    """An option's value found wrong only once the stage has read its input (a length beyond
    the one limit of every length, a plain number outside its option's plausible span:
    ``dgpc_cli.io.length``): the command line reports it as a usage error (exit 2), the
    one-line message its ``str``; nothing is written."""


class NotConverged(DgpcError):
    """The optimization did not reach its tolerance; the artifact is still written (exit 3)."""

    exit_code = 3
