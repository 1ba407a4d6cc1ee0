"""A command given a patch set runs itself on each of its members (``stages.patch_set_run``)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.options import check_writable, show_progress
from dgpc_cli.io.patch_set import is_patch_set, member_stems


def on_members(ctx, stem: Path, output: Path, force: bool, stage: str, **extra) -> bool:
    """When ``stem`` is a patch set: run the command of ``ctx`` on each member (its options as
    given, the member as input and ``OUT.pK`` as output), write ``OUT.json`` as the patch set of
    the outputs, echo it, and return True; else False. Nothing is written unless the set and
    every member that passed are written together."""
    from dgpc_cli.stages.patch_set_run import each_member

    if not is_patch_set(stem):
        return False
    names = [name for name, _ in member_stems(stem)]  # a set with a failed member: refused
    check_writable(output, force, members=tuple(names))
    say = (lambda text: click.echo(text, err=True)) if show_progress(ctx) else None

    def run(member: Path, target: Path) -> None:
        ctx.invoke(ctx.command, **{**ctx.params, "stem": member, "output": target})

    each_member(stem, output, stage, run, force=force, say=say,
                announce=lambda written: click.echo(str(written)), **extra)
    return True
