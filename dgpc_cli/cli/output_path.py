"""``OutputPath``: the click type of every ``-o``. An empty path, or a stem without a file
name, is a usage error (exit 2) naming the option. The output's lock is taken as soon as the
path is parsed and held until the command ends: a second process writing the same stem is
refused at once (exit 1, :mod:`dgpc_cli.io.lock`)."""

from __future__ import annotations

import os
from pathlib import Path

import click

from dgpc_cli.io.lock import output_lock


class OutputPath(click.Path):
    """The path of ``-o``: an empty path is a usage error, and so, for a file stem or prefix
    (``folder=False``), is a path without a file name (``.``, ``..``, ``dir/``), which would
    write hidden files such as ``..json``."""

    def __init__(self, *, folder: bool = False):
        super().__init__(file_okay=not folder, dir_okay=folder, path_type=Path)
        self.folder = folder

    def convert(self, value, param, ctx):
        text = os.fspath(value) if isinstance(value, (str, os.PathLike)) else value
        if isinstance(text, str):
            if not text.strip():
                self.fail("an empty path is not an output path.", param, ctx)
            last = text.replace(os.sep, "/").rstrip("/").rsplit("/", 1)[-1]
            if not self.folder and (text.endswith(("/", os.sep)) or last in ("", ".", "..")):
                self.fail(f"{text!r} has no file name (e.g. out/net).",
                          param, ctx)
        path = super().convert(value, param, ctx)
        if ctx is not None and not getattr(ctx, "resilient_parsing", False):
            ctx.with_resource(output_lock(path))
        return path
