"""``FiniteFloat``: the click type of every float option. NaN and ±inf are usage errors.

click's ``FLOAT`` and ``FloatRange`` accept ``nan`` and ``inf`` (Python's ``float`` parses
them, and ``nan`` passes every range check because each comparison with it is false), so a
tolerance of ``nan`` or ``inf`` would switch its check off. This type refuses them with
click's ``BadParameter`` (exit 2) naming the option, and otherwise checks the range as
``click.FloatRange`` does. The help shows the range where there is one (click's own shows
``x<=None`` for an unbounded one).
"""

from __future__ import annotations

import math

import click


class FiniteFloat(click.FloatRange):
    """A finite float, optionally in a range (the arguments of ``click.FloatRange``)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if self.min is None and self.max is None:
            self.name = "float"  # metavar FLOAT, as for a plain float option

    def _describe_range(self) -> str:
        if self.min is None and self.max is None:
            return ""
        return super()._describe_range()

    def convert(self, value, param, ctx):
        number = click.FLOAT.convert(value, param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number.", param, ctx)
        return super().convert(number, param, ctx)
