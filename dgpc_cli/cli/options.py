"""Options shared by the commands, and small helpers for writing artifacts."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from dgpc_cli.cli.output_path import OutputPath
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.units import UNIT_MM
from dgpc_cli.stages.input_status import ACCEPT_HELP

output_opt = click.option(
    "-o", "--output", "output", required=True, type=OutputPath(),
    help="Output artifact stem: writes STEM.json and STEM.obj.")
force_opt = click.option("--force", is_flag=True, help="Overwrite existing output files.")
label_style_opt = click.option(
    "--label-style", "label_style", type=click.Choice(["text", "stroke"]), default="text",
    show_default=True,
    help="Part ids as TEXT on layer LABEL, or as single-stroke polylines on layer ENGRAVE that "
         "an engraver or pen follows.")
accept_status_opt = click.option("--accept-status", "accept_status", is_flag=True,
                                 help=ACCEPT_HELP)
format_opt = click.option(
    "--format", "fmt", type=click.Choice(["obj", "3dm"]), default="obj", show_default=True,
    help="Geometry format: with 3dm, also write STEM.3dm (Rhino, in the artifact's unit, "
         "layers per part) beside the OBJ and list it in the JSON (data.rhino_3dm).")


def old_name(old: str, new: str, type=None):
    """A hidden option ``old``, the former name of the option ``new``: it warns on stderr and
    hands its value to ``new``, whose callback must be :func:`from_old_name` (its value wins
    when both are given). Scripts keep working while the help shows one name per meaning."""
    key = f"old_name:{new}"

    def callback(ctx, param, value):
        if value is not None:
            click.echo(f"warning: {old} is deprecated, it is now {new}", err=True)
            ctx.meta[key] = value
        return value

    return click.option(old, key.replace(":", "_").replace("-", "_"), type=type, hidden=True,
                        expose_value=False, callback=callback, is_eager=True)


def from_old_name(new: str):
    """The callback of option ``new`` that takes the value of its :func:`old_name` alias when
    ``new`` itself is not given."""
    key = f"old_name:{new}"

    def callback(ctx, param, value):
        source = ctx.get_parameter_source(param.name)
        given = source is not None and source.name in ("COMMANDLINE", "ENVIRONMENT")
        return value if given or key not in ctx.meta else ctx.meta[key]

    return callback


def units_check_opt(f):
    """``--expect-units U``: a check of the input's unit (formerly ``--units``, which in
    ``init`` sets the unit: one name, one meaning)."""
    f = click.option(
        "--expect-units", "units_check", type=click.Choice(list(UNIT_MM)), default=None,
        callback=from_old_name("--expect-units"),
        help="Only a check: the unit the input is in (its data.units, set by `init --units`); "
             "a different one is a usage error. Nothing is converted by it.")(f)
    return old_name("--units", "--expect-units", type=click.Choice(list(UNIT_MM)))(f)


def check_units(given: str | None, actual: str, source) -> None:
    """A usage error (exit 2) naming both units when ``--units`` disagrees with the input."""
    if given is not None and given != actual:
        raise click.BadParameter(f"{given} given, but {source} is in {actual} (its data.units, "
                                 "set by `dgpc init --units`)", param_hint="'--expect-units'")


def _written_by_inputs(value) -> set[Path]:
    """The files an input path names: itself and, as an artifact stem, its JSON and OBJ."""
    found = {Path(value).resolve()}
    try:
        found.update(p.resolve() for p in artifact_paths(value))
    except DgpcError:
        pass
    return found


def check_not_input(stem: Path, *extra: Path) -> None:
    """Refuse (exit 1, with or without --force) an output that would overwrite one of the
    command's own inputs: any path argument or option of the running command (an artifact
    stem, a mesh, a handles file) that is ``STEM.json``, ``STEM.obj`` or one of ``extra``."""
    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return
    outputs = {p.resolve() for p in (*artifact_paths(stem), *extra)}
    for param in ctx.command.params:
        # outputs are not inputs: -o, and options named for what they write (--reference-out)
        if not isinstance(param.type, click.Path) or isinstance(param.type, OutputPath) \
                or param.name.endswith("_out"):
            continue
        value = ctx.params.get(param.name)
        values = value if isinstance(value, (list, tuple)) else [value]
        for item in values:
            if isinstance(item, (str, Path)) and str(item) and \
                    _written_by_inputs(item) & outputs:
                name = (param.opts[0] if isinstance(param, click.Option)
                        else param.human_readable_name)
                raise DgpcError(f"is also an input ({name} {item}); write the output "
                                "elsewhere (--force never overwrites an input)", source=stem)


def check_writable(stem: Path, force: bool, *extra: Path) -> None:
    """Fail early (before any work) when the output's folder is missing, an output is one of
    the command's inputs (:func:`check_not_input`), or exists and --force is not given."""
    parent = Path(stem).parent
    if not parent.is_dir():
        raise DgpcError("directory does not exist", source=parent)
    check_not_input(stem, *extra)
    if force:
        return
    for path in (*artifact_paths(stem), *extra):
        if path.exists():
            raise DgpcError("already exists; use --force to overwrite", source=path)


def show_progress(ctx) -> bool:
    return ctx.obj.get("verbosity", 0) >= 0


def progressbar(ctx, length: int, label: str):
    """A click progress bar on stderr, on an interactive terminal only (silent with -q, and in
    pipes and logs, where an error must be the only line)."""
    return click.progressbar(length=length, label=label, file=sys.stderr,
                             show_eta=True, show_pos=True,
                             hidden=not (show_progress(ctx) and sys.stderr.isatty()))
