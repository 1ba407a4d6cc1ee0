"""The value of ``dgpc init --patches``: ``auto`` or a number of patches (the nets:
``stages.init``)."""

from __future__ import annotations

import click

#: The most patches ``--patches K`` takes.
MAX_COUNT = 12


class PatchCount(click.ParamType):
    """``auto`` (None) or a whole number of patches, 1 to :data:`MAX_COUNT`."""

    name = "auto|K"

    def convert(self, value, param, ctx):
        if value is None or isinstance(value, int):
            return value
        text = str(value).strip().lower()
        if text == "auto":
            return "auto"
        try:
            k = int(text)
        except ValueError:
            k = 0
        if not 1 <= k <= MAX_COUNT:
            self.fail(f"{value!r} is not 'auto' or a number of patches from 1 to {MAX_COUNT}",
                      param, ctx)
        return k
