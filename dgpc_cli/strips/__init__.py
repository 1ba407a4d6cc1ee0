"""Geodesic strips as fabrication parts (paper §6.2.2, §6.2.4, Fig. 2, 12, 15, 18): rulings and
planar-quad strips, their polish, their development into the plane and congruence classes;
:mod:`.planarize` is ``dgpc planarize-strips``' computation (a net's strips, per strip or one
template, trimmed to the outline)."""

from __future__ import annotations


def strip_id(v: int, n: int) -> str:
    """Stable id of the strip between the u-lines v and v+1 of a net with n columns: ``S-v07``
    (at least two digits, more when the net has 100 or more strips)."""
    digits = max(2, len(str(max(n - 2, 0))))
    return f"S-v{int(v):0{digits}d}"
