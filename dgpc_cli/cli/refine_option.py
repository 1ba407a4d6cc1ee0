"""``--refine``: rulings per net row, an integer >= 1 or ``auto``."""

from __future__ import annotations

import click


class RefineParam(click.ParamType):
    """An integer K >= 1, or ``auto`` (converted to None: the stage chooses K)."""

    name = "K|auto"

    def convert(self, value, param, ctx):
        if value is None or isinstance(value, int) and not isinstance(value, bool):
            if value is not None and value < 1:
                self.fail(f"{value} is not >= 1", param, ctx)
            return value
        text = str(value).strip().lower()
        if text == "auto":
            return None
        try:
            k = int(text)
        except ValueError:
            self.fail(f"{value!r} is neither an integer >= 1 nor 'auto'", param, ctx)
        if k < 1:
            self.fail(f"{k} is not >= 1", param, ctx)
        return k
