"""What a Dask worker runs for ``dgpc batch``: one dgpc command, in-process.

A task is the very click command of ``dgpc COMMAND ARGS`` (the one the shell runs), invoked
with ``standalone_mode=False`` from the folder the batch was started in, so it parses,
computes and writes exactly what the command line would. Its stdout (the paths it prints)
is dropped, its warnings are kept, and its error is the one line the command line would show
(exit 1 bad data, 2 usage, 3 tolerance missed with the artifact written).

The module lives in the command-line layer because it calls the commands. A worker runs one
task at a time (a lock): a task changes the process's working folder and captures its
output streams; run workers with one thread each (``dask worker --nthreads 1``), as the
numerical stages use the cores themselves.
"""

from __future__ import annotations

import io
import logging
import os
import threading
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import click

from dgpc_cli.batch.cache import hash_outputs
from dgpc_cli.errors import DgpcError, OptionSlip
from dgpc_cli.io.artifact import listed_files

_LOCK = threading.Lock()


class _Collect(logging.Handler):
    """Keeps the warnings of a task (one line each)."""

    def __init__(self):
        super().__init__(logging.WARNING)
        self.lines: list[str] = []

    def emit(self, record):
        self.lines.append(" ".join(f"{record.levelname.lower()}: {record.getMessage()}"
                                   .split()))


def invoke(command: str, args: list[str]) -> tuple[int, str]:
    """Run ``dgpc COMMAND ARGS`` (quiet) in this process: its exit code and error line."""
    from dgpc_cli.cli.main import cli

    cmd = cli.get_command(click.Context(cli), command)
    if cmd is None:
        return 2, f"no command {command!r}"
    try:
        cmd.main(args=list(args), prog_name=f"dgpc {command}", standalone_mode=False,
                 obj={"verbosity": -1})
    except DgpcError as err:
        return err.exit_code, str(err)
    except OptionSlip as slip:           # a usage error found once the input is read
        return 2, " ".join(str(slip).split())
    except click.exceptions.Exit as err:
        return err.exit_code, ""
    except click.ClickException as err:
        return err.exit_code, " ".join(err.format_message().split())
    except click.Abort:
        return 1, "aborted"
    except Exception as err:  # noqa: BLE001 - reported like the command line's last resort
        reason = " ".join(str(err).split()) or type(err).__name__
        return 1, f"internal error ({type(err).__name__}): {reason}"
    return 0, ""


def written_files(command: str, artifact: Path) -> list[Path]:
    """The files a task wrote, by the names its main output lists: an artifact's JSON and
    the files it lists (``data.obj``, ``data.files`` ...), a report's index and the figures
    it links. Nothing else in the folder (a neighbour's files, a user's notes) is counted."""
    if command == "report":
        from dgpc_cli.stages.report import previous_report_files

        prefix = artifact.parent / artifact.name[: -len("-index.html")]
        return [artifact, *previous_report_files(prefix)]
    return [artifact, *listed_files(artifact)]


def run_task(spec: dict) -> dict:
    """Run the task ``spec`` (``command``, ``args``, ``cwd``: the folder the batch runs from,
    ``out``: the output folder, ``artifact``: its main output there) and return
    ``exit_code``, ``message``, ``warnings``, ``outputs`` (path → sha256 of each file it
    wrote) and ``wall_time_s``. The files of an earlier run are left to the command, which
    replaces them whole or not at all (``--force``)."""
    with _LOCK:
        start = time.perf_counter()
        here = os.getcwd()
        logger = logging.getLogger("dgpc_cli")
        saved = (logger.handlers[:], logger.level, logger.propagate)
        collect = _Collect()
        try:
            os.chdir(spec["cwd"])
            out = Path(spec["out"])
            artifact = out / spec["artifact"]
            artifact.parent.mkdir(parents=True, exist_ok=True)
            logger.handlers[:] = [collect]
            logger.setLevel(logging.WARNING)
            logger.propagate = False
            with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
                code, message = invoke(spec["command"], spec["args"])
            outputs = {} if code not in (0, 3) else hash_outputs(
                [Path(os.path.relpath(p, out)).as_posix()
                 for p in written_files(spec["command"], artifact)], out)
        finally:
            logger.handlers[:] = saved[0]
            logger.setLevel(saved[1])
            logger.propagate = saved[2]
            os.chdir(here)
        return {"exit_code": code, "message": message, "warnings": collect.lines,
                "outputs": outputs, "wall_time_s": time.perf_counter() - start}
