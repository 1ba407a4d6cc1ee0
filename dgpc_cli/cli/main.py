"""The ``dgpc`` click group: verbosity, error reporting and exit codes (SPEC §2)."""

from __future__ import annotations

import logging
import sys

import click

from dgpc_cli import __version__
from dgpc_cli.errors import DgpcError

log = logging.getLogger("dgpc_cli")


class _ClickHandler(logging.Handler):
    """Log records to stderr, one line each (stdout carries data only)."""

    def emit(self, record):
        try:
            click.echo(f"{record.levelname.lower()}: {record.getMessage()}", err=True)
        except Exception:  # noqa: BLE001 - never let logging break a command
            self.handleError(record)


def configure_logging(verbosity: int) -> None:
    """``-v`` per step below WARNING, ``-q`` per step above (rasterio's habit)."""
    level = max(logging.DEBUG, min(logging.CRITICAL, logging.WARNING - 10 * verbosity))
    root = logging.getLogger("dgpc_cli")
    root.handlers[:] = [_ClickHandler()]
    root.setLevel(level)
    root.propagate = False


class DgpcGroup(click.Group):
    """Turns domain errors into one line on stderr and the exit code of SPEC §2."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except DgpcError as err:
            click.echo(f"Error: {err}", err=True)
            ctx.exit(err.exit_code)
        except (click.exceptions.Exit, click.ClickException, click.Abort):
            raise
        except Exception as err:  # noqa: BLE001 - the last line of defence
            if ctx.obj and ctx.obj.get("verbosity", 0) > 0:
                raise
            reason = " ".join(str(err).split()) or type(err).__name__
            click.echo(f"Error: internal error ({type(err).__name__}): {reason} "
                       "(run with -v for the traceback)", err=True)
            ctx.exit(1)


@click.group(cls=DgpcGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("-v", "--verbose", count=True, help="More log output on stderr (repeatable).")
@click.option("-q", "--quiet", count=True, help="Less log output on stderr (repeatable).")
@click.version_option(__version__, prog_name="dgpc")
@click.pass_context
def cli(ctx, verbose, quiet):
    """Discrete geodesic parallel coordinates: from a design surface to buildable parts.

    Stages chain through artifacts (STEM.json + STEM.obj): init -> optimize -> ... Every
    stage writes with -o STEM and refuses to overwrite without --force.

    Exit codes: 0 ok; 1 bad data or infeasible request; 2 usage error; 3 the optimization
    did not reach its tolerance (the artifact is still written).
    """
    ctx.ensure_object(dict)
    ctx.obj["verbosity"] = verbose - quiet
    configure_logging(verbose - quiet)


def _register():
    from dgpc_cli.cli.batch import batch  # imports no Dask until it runs
    from dgpc_cli.cli.extract_mold import extract_mold_cmd
    from dgpc_cli.cli.init import init
    from dgpc_cli.cli.inspect import inspect
    from dgpc_cli.cli.laths import laths
    from dgpc_cli.cli.nest import nest
    from dgpc_cli.cli.optimize import optimize
    from dgpc_cli.cli.planarize_strips import planarize_strips_cmd
    from dgpc_cli.cli.report import report
    from dgpc_cli.cli.unfold import unfold

    for command in (init, optimize, extract_mold_cmd, planarize_strips_cmd, unfold, report,
                    inspect, laths, nest, batch):
        cli.add_command(command)


_register()


def main():  # pragma: no cover - console entry point
    cli(prog_name="dgpc")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
