"""Meridian profiles of surfaces of revolution (SPEC §5, paper §2.1, §6.1 Fig. 11).

A profile is a polyline in the (r, h) half plane: r > 0 is the distance to the axis of
revolution (the z axis), h the height along it. Revolving it about the z axis gives the surface;
its points become the meridians' vertices, in the profile's order (u runs from the first point
to the last).

Profiles never touch the axis (r = 0): there all meridians meet at a pole and a net of geodesic
parallel coordinates degenerates, so the built-ins stop short of it and a CSV that reaches it
is rejected.
"""

from __future__ import annotations

import csv
import stat
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.tolerances import tol as TOL

#: Samples of a built-in profile (dense: the surface is the revolved polyline).
BUILTIN_SAMPLES = 2001


@dataclass(frozen=True, eq=False)
class Profile:
    """A meridian polyline: ``r (k,)`` distances to the axis, ``h (k,)`` heights, k ≥ 2.

    The arrays are stored as read-only float64 copies. Every r is > 0 and consecutive points
    differ (no zero-length segment); ``ValueError`` otherwise (``read_profile_csv`` reports the
    same faults of a file as :class:`DgpcError` first).
    """

    name: str
    r: np.ndarray
    h: np.ndarray

    def __post_init__(self):
        r = np.array(self.r, dtype=float)
        h = np.array(self.h, dtype=float)
        if r.ndim != 1 or r.shape != h.shape or r.size < 2:
            raise ValueError(f"profile {self.name!r}: r and h must be 1-D of equal length ≥ 2, "
                             f"got shapes {r.shape} and {h.shape}")
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(h))):
            raise ValueError(f"profile {self.name!r}: non-finite coordinates")
        if np.any(r <= 0):
            raise ValueError(f"profile {self.name!r}: every radius must be > 0 (no pole)")
        if np.any(np.hypot(np.diff(r), np.diff(h)) == 0):
            raise ValueError(f"profile {self.name!r}: consecutive duplicate points")
        for name, value in (("r", r), ("h", h)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    def __len__(self) -> int:
        return self.r.size

    @property
    def length(self) -> float:
        """Total arc length of the polyline."""
        return float(arc_length(self)[-1])

    def arc_length(self) -> np.ndarray:
        """Cumulative arc length ``s (k,)``; see :func:`arc_length`."""
        return arc_length(self)

    def resample(self, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(r (m,), h (m,), s (m,))`` at equal arc length; see :func:`resample`."""
        return resample(self, m)


def arc_length(profile: Profile) -> np.ndarray:
    """Cumulative arc length ``s (k,)`` of the polyline, ``s[0] = 0``, ``s[-1]`` = its length."""
    seg = np.hypot(np.diff(profile.r), np.diff(profile.h))
    return np.concatenate([[0.0], np.cumsum(seg)])


def resample(profile: Profile, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """m points at equal arc length along the polyline (linear interpolation on its segments).

    Returns ``r (m,)``, ``h (m,)`` and their arc lengths ``s (m,) = linspace(0, L, m)``; the
    first and last points are the profile's ends exactly.
    """
    m = int(m)
    if m < 2:
        raise ValueError(f"resample needs m ≥ 2 points, got {m}")
    s_prof = arc_length(profile)
    s = np.linspace(0.0, s_prof[-1], m)
    r = np.interp(s, s_prof, profile.r)
    h = np.interp(s, s_prof, profile.h)
    r[[0, -1]] = profile.r[[0, -1]]
    h[[0, -1]] = profile.h[[0, -1]]
    return r, h, s


# built-in profiles ------------------------------------------------------------------------------

# A bowling pin (USBC proportions, cm): height 38.1 (15 in), base Ø 5.2, belly Ø 12.1 at 11.4,
# neck Ø 4.6 at 25, head Ø 6.4 at 33; the rounded crown is cut at r = 1.5, short of the axis.
# PCHIP keeps the shape: extrema only at the control points (belly, neck, head), no overshoot.
_PIN_H = np.array([0.0, 1.5, 4.0, 7.5, 11.4, 15.0, 18.5, 21.5, 23.5, 25.0, 26.5, 28.5, 31.0,
                   33.0, 35.3, 37.2, 38.1])
_PIN_R = np.array([2.6, 3.45, 4.65, 5.65, 6.05, 5.65, 4.6, 3.3, 2.5, 2.3, 2.42, 2.7, 3.05,
                   3.2, 2.95, 2.3, 1.5])


def _bowling_pin() -> Profile:
    # Dense samples plus the control points themselves, so belly, neck and head are exact.
    h = np.union1d(np.linspace(_PIN_H[0], _PIN_H[-1], BUILTIN_SAMPLES), _PIN_H)
    from scipy.interpolate import PchipInterpolator  # only here: a slow import

    return Profile("bowling-pin", PchipInterpolator(_PIN_H, _PIN_R)(h), h)


def _circle_arc(name: str, radius: float, lat0_deg: float, lat1_deg: float) -> Profile:
    """Meridian of a sphere centred at the origin, latitudes lat0..lat1 (uniform in arc length)."""
    phi = np.radians(np.linspace(lat0_deg, lat1_deg, BUILTIN_SAMPLES))
    return Profile(name, radius * np.cos(phi), radius * np.sin(phi))


def _sphere() -> Profile:
    return _circle_arc("sphere", 5.0, 0.0, 90.0 - 8.0)


def _sphere_zone() -> Profile:
    return _circle_arc("sphere-zone", 5.0, -45.0, 45.0)


def _cylinder() -> Profile:
    h = np.linspace(0.0, 6.0, BUILTIN_SAMPLES)
    return Profile("cylinder", np.full_like(h, 2.0), h)


def _cone() -> Profile:
    h = np.linspace(0.0, 4.0, BUILTIN_SAMPLES)
    return Profile("cone", 3.0 - 0.5 * h, h)


#: Waist radius of the built-in catenoid.
CATENOID_C = 1.5


def _catenoid() -> Profile:
    h = np.linspace(-2.0, 2.0, BUILTIN_SAMPLES)
    return Profile("catenoid", CATENOID_C * np.cosh(h / CATENOID_C), h)


class BuiltinProfile(NamedTuple):
    """A built-in profile: a one-line ``description`` (for ``--help``) and its ``build()``."""

    description: str
    build: Callable[[], Profile]


#: Built-in profiles by name, in the order ``--help`` lists them.
BUILTIN_PROFILES: dict[str, BuiltinProfile] = {
    "bowling-pin": BuiltinProfile(
        "bowling pin, height 38.1, belly r 6.05 at h 11.4, neck r 2.3 at h 25, cut at r 1.5 "
        "(paper Fig. 11)", _bowling_pin),
    "sphere": BuiltinProfile(
        "half sphere of radius 5, equator to 8° from the pole", _sphere),
    "sphere-zone": BuiltinProfile(
        "sphere of radius 5 between latitudes -45° and 45°", _sphere_zone),
    "cylinder": BuiltinProfile("cylinder r = 2, h in [0, 6]", _cylinder),
    "cone": BuiltinProfile("cone frustum, r from 3 at h = 0 to 1 at h = 4", _cone),
    "catenoid": BuiltinProfile(
        "catenoid r = 1.5 cosh(h / 1.5), h in [-2, 2] (a minimal surface)", _catenoid),
}


@cache
def builtin_profile(name: str) -> Profile:
    """The built-in profile ``name`` (a key of :data:`BUILTIN_PROFILES`); KeyError otherwise."""
    if name not in BUILTIN_PROFILES:
        raise KeyError(f"unknown built-in profile {name!r}; built-ins: "
                       f"{', '.join(BUILTIN_PROFILES)}")
    return BUILTIN_PROFILES[name].build()


# CSV profiles -----------------------------------------------------------------------------------

#: The largest profile CSV read (64 MiB: millions of rows, far more than a profile needs).
MAX_PROFILE_BYTES = 64 * 1024**2


def read_profile_csv(path: str | Path) -> Profile:
    """A profile from a CSV file with a header naming the columns ``r`` and ``h`` (any order).

    Whitespace around fields and blank lines are tolerated; at least 2 data rows. Every fault
    is a :class:`DgpcError` with ``source=path`` and a one-line message (line numbers are the
    file's, the header being line 1). The profile is named by the path as given.
    """
    path = Path(path)
    try:
        info = path.stat()
    except OSError:
        info = None                     # read_text below says why
    if info is not None and not stat.S_ISDIR(info.st_mode) and \
            (not stat.S_ISREG(info.st_mode) or info.st_size > MAX_PROFILE_BYTES):
        raise DgpcError("is not a regular file (a device, a pipe or a socket), expected a "
                        "profile CSV file" if not stat.S_ISREG(info.st_mode) else
                        f"is {info.st_size} bytes, more than a profile CSV file may be "
                        f"({MAX_PROFILE_BYTES})", path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise DgpcError("profile file not found", path) from None
    except IsADirectoryError:
        raise DgpcError("is a directory, not a profile CSV file", path) from None
    except UnicodeDecodeError:
        raise DgpcError("not a text file (not UTF-8): expected a CSV with header 'r,h'",
                        path) from None
    except OSError as err:
        raise DgpcError(f"cannot read profile file: {err.strerror or err}", path) from None

    rows = [(num, [field.strip() for field in row])
            for num, row in _numbered_rows(text)
            if any(field.strip() for field in row)]
    if not rows:
        raise DgpcError("empty profile file: expected a CSV with header 'r,h' and at least "
                        "2 data rows", path)

    header_line, header = rows[0]
    names = [name.lower() for name in header]
    if sorted(names) != ["h", "r"]:
        raise DgpcError(f"wrong header on line {header_line}: expected the columns 'r,h' "
                        f"(in any order), found {','.join(header)!r}", path)
    i_r, i_h = names.index("r"), names.index("h")

    data = rows[1:]
    if len(data) < 2:
        raise DgpcError(f"a profile needs at least 2 data rows, found {len(data)}", path)
    lines = np.array([num for num, _ in data])
    values = np.empty((len(data), 2))
    for k, (num, row) in enumerate(data):
        if len(row) != 2:
            raise DgpcError(f"line {num}: expected 2 fields (r, h), found {len(row)}", path)
        for j, col in enumerate((i_r, i_h)):
            try:
                values[k, j] = float(row[col])
            except ValueError:
                raise DgpcError(f"line {num}: cannot parse {header[col]} = {row[col]!r} as a "
                                "number", path) from None
    r, h = values[:, 0], values[:, 1]

    bad = ~np.all(np.isfinite(values), axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise DgpcError(f"line {lines[k]}: non-finite value (r = {r[k]}, h = {h[k]})", path)
    far = np.any(np.abs(values) > TOL.max_coordinate, axis=1)
    if far.any():
        k = int(np.argmax(far))
        raise DgpcError(f"line {lines[k]}: r = {r[k]:g}, h = {h[k]:g} beyond "
                        f"±{TOL.max_coordinate:g} (the largest coordinate dgpc accepts, in the "
                        "profile's unit)", path)
    if np.any(r < 0):
        k = int(np.argmax(r < 0))
        raise DgpcError(f"line {lines[k]}: negative radius r = {r[k]:g}; r is the distance to "
                        "the axis of revolution and must be > 0", path)
    if np.any(r == 0):
        k = int(np.argmax(r == 0))
        raise DgpcError(f"line {lines[k]}: radius r = 0 lies on the axis, where the meridians "
                        "meet at a pole and the net degenerates; stop the profile short of the "
                        "axis (r > 0)", path)

    dr, dh = np.diff(r), np.diff(h)
    seg = np.hypot(dr, dh)
    if np.any(seg == 0):
        k = int(np.argmax(seg == 0)) + 1
        raise DgpcError(f"line {lines[k]} repeats the point of line {lines[k - 1]} "
                        f"(r = {r[k]:g}, h = {h[k]:g}): consecutive duplicate points", path)
    # A turn of 180°: the polyline doubles back over itself (a fold of zero width).
    cross = dr[:-1] * dh[1:] - dh[:-1] * dr[1:]
    dot = dr[:-1] * dr[1:] + dh[:-1] * dh[1:]
    reverses = (dot < 0) & (np.abs(cross) <= 1e-9 * seg[:-1] * seg[1:])
    if reverses.any():
        k = int(np.argmax(reverses)) + 1
        raise DgpcError(f"line {lines[k]}: the profile reverses on itself (the segments before "
                        "and after this point are opposite, a fold of zero length/width)", path)

    return Profile(str(path), r, h)


def _numbered_rows(text: str):
    """``(line number, fields)`` of each CSV record; the line number is where it starts."""
    reader = csv.reader(text.splitlines())
    start = 1
    for row in reader:
        yield start, row
        start = reader.line_num + 1


def profile_from_spec(spec: str | Path) -> Profile:
    """A built-in name (see :data:`BUILTIN_PROFILES`) or the path of a profile CSV file.

    A name that is neither a built-in nor an existing file is a :class:`DgpcError` listing the
    built-in names.
    """
    text = str(spec)
    if text in BUILTIN_PROFILES:
        return builtin_profile(text)
    if Path(text).exists():
        return read_profile_csv(text)
    raise DgpcError(f"unknown profile: neither a built-in ({', '.join(BUILTIN_PROFILES)}) "
                    "nor an existing CSV file", text)


def describe_builtins() -> str:
    """One line per built-in, its name then its description, for ``--help``."""
    width = max(map(len, BUILTIN_PROFILES))
    return "\n".join(f"{name:<{width}}  {entry.description}"
                     for name, entry in BUILTIN_PROFILES.items())


__all__ = [
    "BUILTIN_PROFILES", "BUILTIN_SAMPLES", "BuiltinProfile", "CATENOID_C", "Profile",
    "arc_length", "builtin_profile", "describe_builtins", "profile_from_spec",
    "read_profile_csv", "resample",
]
