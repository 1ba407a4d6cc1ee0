"""``LengthParam``: the click type of every length option (a number with an optional unit).

A length option takes ``2.5m``, ``2500mm``, ``0.5 mm``, ``1in`` or a plain number. A plain
number means the unit of the artifact the command reads (its ``data.units``), or, where the
option says so in its help (sheet sizes, kerf), millimetres: the option's ``plain`` unit.
The type returns a :class:`Length`; the command converts it once it knows the artifact's unit
(:meth:`Length.to_mm`, :meth:`Length.in_units`). Units are those of :data:`io.units.UNIT_MM`.

NaN, ±inf, malformed text, unknown units and values outside the option's range are usage
errors (click's ``BadParameter``, exit 2) naming the option.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import click

from dgpc_cli.io.units import UNIT_MM, mm_per_unit

_LENGTH = re.compile(
    r"^\s*(?P<number>[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>[A-Za-z]+)?\s*$")

#: The ``plain`` setting of an option whose plain numbers are in the artifact's unit.
ARTIFACT_UNIT = None


@dataclass(frozen=True)
class Length:
    """A length as the user gave it: ``value`` in ``unit`` (None: the option's plain unit)."""

    value: float
    unit: str | None = None
    #: The unit a plain number is in (None: the artifact's unit, known only to the command).
    plain: str | None = ARTIFACT_UNIT

    def unit_for(self, artifact_units: str | None) -> str:
        """The unit this length is in, given the unit of the artifact the command reads."""
        unit = self.unit or self.plain or artifact_units
        if unit is None:
            raise ValueError("a plain number needs the artifact's unit")
        return unit

    def to_mm(self, artifact_units: str | None = None) -> float:
        """The length in millimetres."""
        return self.value * mm_per_unit(self.unit_for(artifact_units))

    def in_units(self, units: str, artifact_units: str | None = None) -> float:
        """The length in ``units`` (``artifact_units``: the unit of a plain number)."""
        return self.to_mm(artifact_units) / mm_per_unit(units)

    def unit_slip(self, option: str, artifact_units: str, limit_mm: float, what: str,
                  whose: str = "the artifact's") -> str | None:
        """The one-line usage error for a plain number that is in ``artifact_units`` (``whose``
        unit, e.g. "the strips'") but was likely meant in millimetres (issue: no silent unit
        traps): longer than ``limit_mm`` (``what`` it is compared with, e.g. "every strip (the
        longest is 6.06 m)") while read as mm it would not be. None when the length has a
        unit, a plain number is not in the artifact's unit, the artifact is in mm, or neither
        reading is plausible."""
        if self.unit is not None or self.plain is not None or artifact_units == "mm":
            return None
        if not self.to_mm(artifact_units) > limit_mm or self.value > limit_mm:
            return None
        k = mm_per_unit(artifact_units)
        return (f"{option} {self.text()} is in {whose} unit ({artifact_units}): {self.value:g} "
                f"{artifact_units} is longer than {what}; give the unit, e.g. {self.value:g}mm "
                f"or {self.value / k:g}{artifact_units}")

    def text(self) -> str:
        """The length as typed back, with its unit where one was given: ``0.5mm``, ``2500``."""
        return f"{self.value:g}{self.unit or ''}"

    def __str__(self) -> str:
        return self.text()


class LengthParam(click.ParamType):
    """A length with an optional unit suffix, optionally bounded (bounds in the given unit).

    ``plain``: the unit of a plain number (None: the artifact's unit); ``min``/``max`` bound
    the number as typed, ``min_open`` excludes ``min`` itself (a length that must be > 0).
    """

    name = "length"

    def __init__(self, plain: str | None = ARTIFACT_UNIT, min: float | None = None,
                 max: float | None = None, min_open: bool = False):
        if plain is not None:
            mm_per_unit(plain)
        self.plain, self.min, self.max, self.min_open = plain, min, max, min_open

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
        return Length(number, unit, self.plain)


def _non_finite(text: str) -> bool:
    """Whether ``text`` is a number Python reads as NaN or ±inf (``nan``, ``-inf``)."""
    try:
        return not math.isfinite(float(text))
    except ValueError:
        return False


def length_help(text: str, plain: str | None = ARTIFACT_UNIT, where: str | None = None) -> str:
    """An option's help with the rule for its units appended (``where``: what a plain number
    is in, for an option whose unit is neither an artifact's nor fixed, e.g. ``init --units``)."""
    where = where or ("in the artifact's unit (its data.units)" if plain is None
                      else f"in {plain}")
    return f"{text} A LENGTH with a unit (2.5m, 2500mm, 0.5mm) or a plain number {where}."
