"""The ``dgpc`` click group: verbosity, error reporting and exit codes (SPEC §2)."""

from __future__ import annotations

import importlib
import logging
import sys

import click

from dgpc_cli import __version__
from dgpc_cli.errors import DgpcError, OptionSlip

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


#: The subcommands: name -> (module under dgpc_cli.cli, attribute, short help). A command's
#: module (and the numerical libraries it needs) is imported only when the command runs or its
#: own help is asked for, so `dgpc --help`, `--version` and shell completion stay instant.
#: The short help repeats the command's own (a test keeps them equal).
COMMANDS = {
    "init": ("init", "init", "Make an initial net."),
    "optimize": ("optimize", "optimize",
                 "Optimize a net (fit, developable, revolution, isometric)."),
    "extract-mold": ("extract_mold", "extract_mold_cmd",
                     "Extract the mold (surface of revolution) of nets."),
    "planarize-strips": ("planarize_strips", "planarize_strips_cmd",
                         "Make every geodesic strip a strip of planar quads."),
    "unfold": ("unfold", "unfold",
               "Develop strips into the plane; group them into cutting templates."),
    "report": ("report", "report", "Write figures of artifacts (PNG) and an index.html."),
    "inspect": ("inspect", "inspect", "Print an artifact's metrics as JSON."),
    "laths": ("laths", "laths", "Gridshell laths of two nets and their cut list."),
    "nest": ("nest", "nest", "Nest the flat parts on cut sheets (DXF, SVG, PNG)."),
    "batch": ("batch", "batch", "Run a project of many patches (a facade, a sweep) on Dask."),
    "edit": ("edit", "edit", "Design by dragging handles in a web page (or replay drags)."),
}


class DgpcGroup(click.Group):
    """Turns domain errors into one line on stderr and the exit code of SPEC §2; loads its
    subcommands lazily (``COMMANDS``)."""

    def list_commands(self, ctx):
        return list(COMMANDS)

    def get_command(self, ctx, name):
        if name not in COMMANDS:
            return None
        module, attribute, _ = COMMANDS[name]
        return getattr(importlib.import_module(f"dgpc_cli.cli.{module}"), attribute)

    def format_commands(self, ctx, formatter):
        """The command list of ``--help`` from ``COMMANDS`` (nothing imported)."""
        rows = [(name, help_) for name, (_, _, help_) in COMMANDS.items()]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def shell_complete(self, ctx, incomplete):
        """Complete subcommand names from ``COMMANDS`` (nothing imported)."""
        from click.shell_completion import CompletionItem

        items = [CompletionItem(name, help=help_) for name, (_, _, help_) in COMMANDS.items()
                 if name.startswith(incomplete)]
        return items + [item for item in click.Command.shell_complete(self, ctx, incomplete)]

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except DgpcError as err:
            click.echo(f"Error: {err}", err=True)
            ctx.exit(err.exit_code)
        except OptionSlip as slip:
            # an option's value found wrong once its input is read: a usage error, as click's
            name = ctx.invoked_subcommand
            see = f" (see '{ctx.command_path} {name} --help')" if name else ""
            click.echo(f"Error: {' '.join(str(slip).split())}{see}", err=True)
            ctx.exit(2)
        except click.UsageError as err:
            # One line, as every error (SPEC §2): click's own display adds the usage lines.
            command = f" (see '{err.ctx.command_path} --help')" if err.ctx is not None else ""
            click.echo(f"Error: {' '.join(err.format_message().split())}{command}", err=True)
            ctx.exit(err.exit_code)
        except (click.exceptions.Exit, click.ClickException, click.Abort):
            raise
        except OSError as err:  # stdout on a full disk or a closed pipe, say
            where = f"{err.filename}: " if err.filename else "cannot write the output: "
            click.echo(f"Error: {where}{err.strerror or err}", err=True)
            ctx.exit(1)
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


def main():  # pragma: no cover - console entry point
    cli(prog_name="dgpc")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
