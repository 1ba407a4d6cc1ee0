"""Options shared by the commands, and small helpers for writing artifacts."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from dgpc_cli.cli.output_path import OutputPath
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.units import UNIT_MM

output_opt = click.option(
    "-o", "--output", "output", required=True, type=OutputPath(),
    help="Output artifact stem: writes STEM.json and STEM.obj.")
force_opt = click.option("--force", is_flag=True, help="Overwrite existing output files.")
format_opt = click.option(
    "--format", "fmt", type=click.Choice(["obj", "3dm"]), default="obj", show_default=True,
    help="Geometry format: with 3dm, also write STEM.3dm (Rhino, in the artifact's unit, "
         "layers per part) beside the OBJ and list it in the JSON (data.rhino_3dm).")
units_check_opt = click.option(
    "--units", "units_check", type=click.Choice(list(UNIT_MM)), default=None,
    help="Only a check: the unit the input is in (its data.units, set by `init --units`); a "
         "different one is a usage error. Nothing is converted by it.")


def check_units(given: str | None, actual: str, source) -> None:
    """A usage error (exit 2) naming both units when ``--units`` disagrees with the input."""
    if given is not None and given != actual:
        raise click.BadParameter(f"{given} given, but {source} is in {actual} (its data.units, "
                                 "set by `dgpc init --units`)", param_hint="'--units'")


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
        if not isinstance(param.type, click.Path) or isinstance(param.type, OutputPath):
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
    """Fail early (before any work) when an output is one of the command's inputs
    (:func:`check_not_input`), or exists and --force is not given."""
    check_not_input(stem, *extra)
    if force:
        return
    for path in (*artifact_paths(stem), *extra):
        if path.exists():
            raise DgpcError("already exists; use --force to overwrite", source=path)
    parent = Path(stem).parent
    if not parent.is_dir():
        raise DgpcError("directory does not exist", source=parent)


def show_progress(ctx) -> bool:
    return ctx.obj.get("verbosity", 0) >= 0


def progressbar(ctx, length: int, label: str):
    """A click progress bar on stderr, on an interactive terminal only (silent with -q, and in
    pipes and logs, where an error must be the only line)."""
    return click.progressbar(length=length, label=label, file=sys.stderr,
                             show_eta=True, show_pos=True,
                             hidden=not (show_progress(ctx) and sys.stderr.isatty()))
