"""A length as the user typed it, and the one rule every length option follows.

A length option takes ``2.5m``, ``2500mm``, ``0.5 mm``, ``1in`` or a plain number. A plain
number keeps its documented meaning: the unit of the artifact the command reads (its
``data.units``), or, where the option says so (``nest``'s sheet, kerf, bit, margin, spacing),
millimetres: the option's ``plain`` unit. The command knows what the length is once it knows
that unit (:meth:`Length.to_mm`, :meth:`Length.in_units`).

One rule for every length option (:meth:`Length.check`):

- after conversion every length is finite and at most :data:`MAX_LENGTH_MM` (1000 km), with
  or without a unit: beyond it is a usage error (``unfold --stock-length 1e308m``);
- each option has a plausible :class:`Span` (a router bit 0.5–50 mm, a margin of at least
  1 mm, a congruence tolerance within 1 % of the parts' width, ...), stated in its help. A
  *plain* number outside it is a usage error that names both readings, the one taken and the
  one likely meant (``--tool-diameter 0.006`` read as mm is a 0.006 mm router bit; did you
  mean 6mm?). A length typed with its unit is taken as given.

The usage error is an :class:`~dgpc_cli.errors.OptionSlip`, raised before anything is
written; the command line turns it into exit 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import OptionSlip
from ..tolerances import tol
from .units import mm_per_unit

#: The longest length any option takes, in mm, after its unit is applied (1000 km: beyond any
#: building; the coordinates read are bounded alike, ``tol.max_coordinate``).
MAX_LENGTH_MM = tol.max_length_mm

#: The other readings tried for a plain number outside its span, in this order (the slips
#: seen: a number meant in mm read in the artifact's unit, one meant in m read as mm).
READINGS = ("mm", "m", "cm")


def _exp(x: float) -> str:
    """``1e9``: a power of ten as typed."""
    return f"{x:.0e}".replace("e+0", "e").replace("e+", "e")


def mm_text(mm: float) -> str:
    """``"3.49 mm"``, ``"2500 mm"``: a length in mm for a message (4 significant digits)."""
    return f"{mm:.4g} mm"


@dataclass(frozen=True)
class Span:
    """Where a length option's value is plausible, in mm: from ``low`` to ``high`` (None: open
    on that side; ``low_open``: ``low`` itself excluded), ``noun`` what the length is (``router
    bit``), ``low_text``/``high_text`` the bounds in words (default ``"0.5 mm"``; e.g. ``"1 %
    of the parts' mean width (3.49 mm)"``). A plain 0 is the same in every unit and is never
    outside a span whose ``zero_ok`` is set (a margin of 0: parts to the sheet's edge)."""

    low: float | None = None
    high: float | None = None
    noun: str = ""
    low_text: str | None = None
    high_text: str | None = None
    low_open: bool = False
    zero_ok: bool = False

    def holds(self, mm: float) -> bool:
        if self.zero_ok and mm == 0:
            return True
        if self.low is not None and (mm < self.low or (self.low_open and mm == self.low)):
            return False
        return self.high is None or mm <= self.high

    def miss(self, mm: float) -> str:
        """How ``mm`` misses the span, in words: ``"outside the plausible 0.5–50 mm"``,
        ``"below 1 mm"``."""
        if None not in (self.low, self.high) and self.low_text is self.high_text is None:
            return f"outside the plausible {self.words()}"
        if self.low is not None and not (mm > self.low or (mm == self.low and
                                                           not self.low_open)):
            return f"{'not above' if mm == self.low else 'below'} " \
                   f"{self.low_text or mm_text(self.low)}"
        return f"above {self.high_text or mm_text(self.high)}"

    def words(self) -> str:
        """The span for a help text: ``"0.5–50 mm"``, ``">= 1 mm"``."""
        low = None if self.low is None else self.low_text or mm_text(self.low)
        high = None if self.high is None else self.high_text or mm_text(self.high)
        if low and high and self.low_text is None and self.high_text is None:
            return f"{self.low:g}–{self.high:g} mm"
        if low and high:
            return f"from {low} to {high}"
        if low:
            return f"{'>' if self.low_open else '>='} {low}"
        return f"<= {high}" if high else "any"


@dataclass(frozen=True)
class Length:
    """A length as the user gave it: ``value`` in ``unit`` (None: the option's plain unit,
    ``plain``, or where that is None the artifact's unit, known only to the command)."""

    value: float
    unit: str | None = None
    #: The unit a plain number is in (None: the artifact's unit).
    plain: str | None = None
    #: The text the user typed, for messages (None: :meth:`text`).
    typed: str | None = field(default=None, compare=False, repr=False)

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

    def text(self) -> str:
        """The length as typed back, with its unit where one was given: ``0.5mm``, ``2500``."""
        return f"{self.value:g}{self.unit or ''}"

    def shown(self) -> str:
        """The length as the user typed it (``1e308m``), for messages."""
        return self.typed or self.text()

    def said(self, artifact_units: str | None = None) -> str:
        """The length with its unit, for messages: as typed where it has one (``2500mm``),
        else the plain number in the unit it was read in (``2.5 m``)."""
        if self.unit is not None:
            return self.shown()
        return f"{self.value:g} {self.unit_for(artifact_units)}"

    def __str__(self) -> str:
        return self.text()

    def check(self, option: str, artifact_units: str | None = None, span: Span | None = None,
              whose: str = "the artifact's") -> float:
        """The length in mm, after the rule of the module: OptionSlip (a usage error naming
        ``option``) where it is beyond :data:`MAX_LENGTH_MM`, or a plain number outside
        ``span`` (``whose`` unit a plain number is in when it is the artifact's, e.g.
        ``"the strips'"``)."""
        mm = self.to_mm(artifact_units)
        if not math.isfinite(mm) or mm > MAX_LENGTH_MM:
            raise OptionSlip(f"{option} {self.shown()} is {mm:.4g} mm, beyond 1000 km "
                             f"({_exp(MAX_LENGTH_MM)} mm), the longest length dgpc takes")
        if span is None or self.unit is not None or span.holds(mm):
            return mm
        raise OptionSlip(self.slip(option, artifact_units, span, whose))

    def slip(self, option: str, artifact_units: str | None, span: Span,
             whose: str = "the artifact's") -> str:
        """The one-line usage error of a plain number outside ``span``: both readings, the one
        taken and the one likely meant, and how to mean it as typed."""
        unit = self.unit_for(artifact_units)
        mm = self.to_mm(artifact_units)
        where = "" if self.plain is not None else f" ({whose} unit)"
        noun = f" {span.noun}" if span.noun else ""
        taken = (f"{option} {self.shown()} read as {unit}{where} is a {self.value:g} {unit}"
                 f"{noun}, {span.miss(mm)}")
        meant = next((self.value * mm_per_unit(u) for u in READINGS
                      if u != unit and span.holds(self.value * mm_per_unit(u))), None)
        guess = f"; did you mean {meant:.6g}mm?" if meant is not None else ""
        return f"{taken}{guess} (to mean it as typed, give its unit: {self.shown()}{unit})"

