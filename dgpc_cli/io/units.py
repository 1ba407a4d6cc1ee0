"""Length units of artifacts, and their exact conversion to millimetres (SPEC §3).

Every artifact records the unit of its coordinates and lengths in ``data.units``: one of
:data:`UNIT_MM` (``dgpc init --units``, default mm), carried on by every later stage.

The stages compute in millimetres. A stage converts its input's coordinates once,
``x_mm = x · mm_per_unit`` (:func:`to_mm`), and stores its results back in the artifact's
unit with :func:`from_mm`, which picks for each value the double ``x`` whose product
``x · mm_per_unit`` is the computed millimetre value bit for bit. So the next stage gets the
millimetres back exactly, whatever the unit, and a design drawn in metres computes with the
same bits as the same design drawn in millimetres (coordinates × 1000): the two give
byte-identical cut sheets although the optimizations amplify any last-bit difference.

Not every double is such a product for every unit (about one in ten is not, for 25.4 or
304.8): :func:`from_mm` first moves a value by the fewest ulps (at most a few dozen, a
relative change below 1e-14) to the nearest double that is one for every unit, so that the
stored millimetres do not depend on the unit.
"""

from __future__ import annotations

import numpy as np

from ..errors import DgpcError

#: Length units an artifact may be in, and their size in mm.
UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "ft": 304.8}
#: The units in words, for messages.
UNIT_NAMES = {"mm": "millimetres", "cm": "centimetres", "m": "metres", "in": "inches",
              "ft": "feet"}
#: The unit of ``dgpc init`` without ``--units``.
DEFAULT_UNITS = "mm"
#: How far (ulps) :func:`from_mm` may move a value to make it exact in every unit.
REACH_ULPS = 64

_FACTORS = tuple(k for k in UNIT_MM.values() if k != 1.0)


def mm_per_unit(units: str, source: str | None = None) -> float:
    """The size of ``units`` in mm; DgpcError naming ``source`` for an unknown unit."""
    try:
        return UNIT_MM[units]
    except (KeyError, TypeError):
        raise DgpcError(f"unknown length unit {units!r} (known: {', '.join(UNIT_MM)})",
                        source=source) from None


def to_mm(x, units: str) -> np.ndarray:
    """Coordinates or lengths ``x`` given in ``units`` as float64 millimetres."""
    return np.asarray(x, dtype=np.float64) * mm_per_unit(units)


def _preimage(y: np.ndarray, k: float) -> np.ndarray:
    """Per value the double ``v`` with ``v · k == y`` exactly (NaN where there is none)."""
    v0 = y / k
    out = np.full(y.shape, np.nan)
    for v in (v0, np.nextafter(v0, -np.inf), np.nextafter(v0, np.inf)):
        hit = np.isnan(out) & (v * k == y)
        out[hit] = v[hit]
    return out


def exact_mm(y) -> np.ndarray:
    """``y`` (mm) moved by the fewest ulps to doubles that are ``v · k`` of some double ``v`` for
    every unit's ``k``; values out of reach (none among finite lengths) stay as they are."""
    y = np.asarray(y, dtype=np.float64)
    out = y.copy()
    todo = np.isfinite(y)
    up, down = y.copy(), y.copy()
    for step in range(REACH_ULPS + 1):
        for cand in (up,) if step == 0 else (down, up):
            ok = todo.copy()
            for k in _FACTORS:
                ok[ok] &= ~np.isnan(_preimage(cand[ok], k))
            out[ok] = cand[ok]
            todo &= ~ok
        if not todo.any():
            break
        up, down = np.nextafter(up, np.inf), np.nextafter(down, -np.inf)
    return out


def from_mm(y_mm, units: str) -> np.ndarray:
    """Millimetres ``y_mm`` in ``units``, chosen so that :func:`to_mm` gives back
    ``exact_mm(y_mm)`` bit for bit (see the module)."""
    y = exact_mm(y_mm)
    k = mm_per_unit(units)
    if k == 1.0:
        return y
    v = _preimage(y, k)
    return np.where(np.isnan(v), y / k, v)


def stored(x, units: str) -> np.ndarray:
    """Coordinates ``x`` in ``units`` as they are stored: :func:`from_mm` of their mm (a no-op
    on values already stored so; for results computed in the unit itself)."""
    return from_mm(to_mm(x, units), units)


def same_units(records: list[tuple[str, str]], source: str | None = None) -> str:
    """The common unit of several inputs ``[(name, units), …]``; DgpcError naming the first
    input whose unit differs from the first one's (exit 1: inputs in different units)."""
    (first, units), *rest = records
    for name, other in rest:
        if other != units:
            raise DgpcError(f"{name} is in {other} but {first} is in {units}: inputs in "
                            "different units (re-run one of them with init --units)",
                            source=source or name)
    return units


def nice_length(span: float) -> float:
    """The largest 1, 2 or 5 × 10^k not above ``span`` (the length of a scale bar; 1 for a
    span that is not a positive finite number)."""
    if not span > 0 or not np.isfinite(span):
        return 1.0
    k = np.floor(np.log10(span))
    return float(max(step * 10.0**k for step in (1.0, 2.0, 5.0) if step * 10.0**k <= span))
