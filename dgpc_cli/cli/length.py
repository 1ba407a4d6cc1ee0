"""``LengthParam``: the click type of every length option (a number with an optional unit).

A length option takes ``2.5m``, ``2500mm``, ``0.5 mm``, ``1in`` or a plain number. A plain
number means the unit of the artifact the command reads (its ``data.units``), or, where the
option says so in its help (sheet sizes, kerf), millimetres: the option's ``plain`` unit.
The type returns a :class:`~dgpc_cli.io.length.Length`; the command converts it once it knows
the artifact's unit. The rule every length follows (one limit after conversion, a plausible
span for plain numbers) is :meth:`~dgpc_cli.io.length.Length.check`: an option whose span and
unit are known here is checked at once, the others by their stage once it has read its input.

NaN, ±inf, malformed text, unknown units and values outside the option's range are usage
errors (click's ``BadParameter``, exit 2) naming the option.
"""

from __future__ import annotations

import math
import re

import click

from dgpc_cli.errors import OptionSlip
from dgpc_cli.io.length import Length, Span
from dgpc_cli.io.units import UNIT_MM, mm_per_unit

__all__ = ["ARTIFACT_UNIT", "Length", "LengthParam", "Span", "length_help"]

_LENGTH = re.compile(
    r"^\s*(?P<number>[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>[A-Za-z]+)?\s*$")

#: The ``plain`` setting of an option whose plain numbers are in the artifact's unit.
ARTIFACT_UNIT = None


class LengthParam(click.ParamType):
    """A length with an optional unit suffix, optionally bounded (bounds in the given unit).

    ``plain``: the unit of a plain number (None: the artifact's unit); ``min``/``max`` bound
    the number as typed, ``min_open`` excludes ``min`` itself (a length that must be > 0);
    ``span``: where a plain number is plausible (:class:`~dgpc_cli.io.length.Span`, mm),
    checked here for an option whose plain numbers are in a fixed unit. A length whose unit
    is known here is also held to the one limit of every length
    (:meth:`~dgpc_cli.io.length.Length.check`); the others are checked by their stage.
    """

    name = "length"

    def __init__(self, plain: str | None = ARTIFACT_UNIT, min: float | None = None,
                 max: float | None = None, min_open: bool = False, span: Span | None = None):
        if plain is not None:
            mm_per_unit(plain)
        self.plain, self.min, self.max, self.min_open = plain, min, max, min_open
        self.span = span

    def get_metavar(self, param, ctx=None) -> str:
        return "LENGTH"

    def convert(self, value, param, ctx):
        if isinstance(value, Length):
            return value
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            number, unit = float(value), None
        else:
            match = _LENGTH.match(str(value))
            if match is None and _non_finite(str(value)):
                self.fail(f"{value!r} is not a finite length.", param, ctx)
            if match is None:
                self.fail(f"{value!r} is not a length (a number, optionally with a unit: "
                          f"{', '.join(UNIT_MM)}; e.g. 2.5m, 2500mm).", param, ctx)
            number, unit = float(match["number"]), match["unit"]
            if unit is not None and unit not in UNIT_MM:
                self.fail(f"unknown unit {unit!r} in {value!r} (known: {', '.join(UNIT_MM)}).",
                          param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite length.", param, ctx)
        if self.min is not None and (number < self.min or (self.min_open and number == self.min)):
            self.fail(f"{value!r} must be {'>' if self.min_open else '>='} {self.min:g}.",
                      param, ctx)
        if self.max is not None and number > self.max:
            self.fail(f"{value!r} must be <= {self.max:g}.", param, ctx)
        length = Length(number, unit, self.plain, typed=" ".join(str(value).split()))
        if unit is not None or self.plain is not None:
            option = param.opts[0] if param is not None and param.opts else "length"
            try:
                length.check(option, span=self.span)
            except OptionSlip as slip:
                raise click.UsageError(str(slip), ctx) from None
        return length


def _non_finite(text: str) -> bool:
    """Whether ``text`` is a number Python reads as NaN or ±inf (``nan``, ``-inf``)."""
    try:
        return not math.isfinite(float(text))
    except ValueError:
        return False


def length_help(text: str, plain: str | None = ARTIFACT_UNIT, where: str | None = None,
                plausible: str | Span | None = None) -> str:
    """An option's help with the rule for its units appended (``where``: what a plain number
    is in, for an option whose unit is neither an artifact's nor fixed, e.g. ``init --units``;
    ``plausible``: where a plain number is plausible, a span or its words)."""
    where = where or ("in the artifact's unit (its data.units)" if plain is None
                      else f"in {plain}")
    out = f"{text} A LENGTH with a unit (2.5m, 2500mm, 0.5mm) or a plain number {where}."
    if plausible is not None:
        words = plausible.words() if isinstance(plausible, Span) else plausible
        out += (f" Plausible: {words} (a plain number outside it is a usage error; a length "
                "with its unit is taken as given).")
    return out
