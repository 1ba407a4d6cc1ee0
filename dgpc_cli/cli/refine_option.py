"""``--refine``: rulings per net row, an integer from 1 to :data:`MAX_REFINE`, or ``auto``."""

from __future__ import annotations

import click

#: The most rulings per net row: the chords' sag falls about K²-fold (``strips.refine``), so
#: 16 already makes it 256 times smaller; every ruling costs memory and time (a K of 5000 would
#: ask for tens of GiB).
MAX_REFINE = 16


class RefineParam(click.ParamType):
    """An integer K from 1 to :data:`MAX_REFINE`, or ``auto`` (converted to None: the stage
    chooses K)."""

    name = "K|auto"

    def convert(self, value, param, ctx):
        if value is None:
            return None
        if isinstance(value, int) and not isinstance(value, bool):
            return self._in_range(value, param, ctx)
        text = str(value).strip().lower()
        if text == "auto":
            return None
        try:
            k = int(text)
        except ValueError:
            self.fail(f"{value!r} is neither an integer from 1 to {MAX_REFINE} nor 'auto'",
                      param, ctx)
        return self._in_range(k, param, ctx)

    def _in_range(self, k: int, param, ctx) -> int:
        if not 1 <= k <= MAX_REFINE:
            shown = str(k) if len(str(k)) <= 12 else f"{str(k)[:6]}…({len(str(k))} digits)"
            self.fail(f"{shown} is not from 1 to {MAX_REFINE} (rulings per net row)", param,
                      ctx)
        return k
