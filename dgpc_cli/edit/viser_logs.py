"""What viser says, said as dgpc says things: one line on stderr each, never on stdout (which
carries the page's address only), never a traceback.

viser prints through ``rich`` to stdout (its address, "Server stopped", a client of another
version rejected); a message it cannot decode ends the connection's handler (logged by
``websockets`` with a traceback); a GUI update it cannot apply fails an asyncio task ("Task
exception was never retrieved", a traceback); a value that does not fit a message's field
is a ``UserWarning``. :func:`route_viser_output` turns each into one line of the
``dgpc_cli`` log."""

from __future__ import annotations

import io
import logging
import re
import warnings

from dgpc_cli.edit.page_input import describe

log = logging.getLogger(__name__)

#: rich's markup (``[bold]…[/bold]``) and the ``(viser)`` prefix of its lines.
_MARKUP = re.compile(r"\[/?[a-z ]+\]|\(viser\)\s*")


class _LogStream(io.TextIOBase):
    """A text stream whose complete lines become log records: a client of another viser
    version rejected is a warning, everything else viser prints a debug line."""

    def __init__(self):
        super().__init__()
        self._part = ""

    def writable(self) -> bool:
        return True

    def isatty(self) -> bool:
        return False

    def write(self, text: str) -> int:
        self._part += text
        *lines, self._part = self._part.split("\n")
        for line in lines:
            line = _MARKUP.sub("", line).strip()
            if not line:
                continue
            if "mismatch" in line.lower():
                log.warning("edit: the page's client was refused: %s (reload the page)", line)
            else:
                log.debug("viser: %s", line)
        return len(text)


class _OneLine(logging.Filter):
    """Turns a record of asyncio or websockets into at most one line of the dgpc log and
    drops the original (with its traceback)."""

    def filter(self, record: logging.LogRecord) -> bool:
        err = record.exc_info[1] if record.exc_info else None
        text = record.getMessage().splitlines()[0] if record.msg else ""
        if "handshake" in text or "closed" in text:
            log.debug("edit: %s", text)              # a tab that went away mid-handshake
        elif err is not None or record.levelno >= logging.ERROR:
            log.warning("edit: a message from the page dropped: %s", describe(err) if err
                        is not None else text)
        else:
            log.debug("edit: %s", text)
        return False


_FILTER = _OneLine()
_STREAM = _LogStream()


def route_viser_output() -> None:
    """Send viser's prints, its websocket and task errors and its field warnings to the dgpc
    log, one line each (idempotent; for the process running the page)."""
    import rich

    rich.reconfigure(file=_STREAM, force_terminal=False, width=10_000)
    for name in ("asyncio", "websockets", "websockets.server", "websockets.asyncio.server"):
        logger = logging.getLogger(name)
        if _FILTER not in logger.filters:
            logger.addFilter(_FILTER)
    logging.getLogger("websockets").setLevel(logging.INFO)
    # a field of another type is checked by the page's handlers (page_input), one line there
    warnings.filterwarnings("ignore", message=r"\[viser\]", category=UserWarning)
