"""The size guard of ``init``: the memory a net of m × n vertices will take, estimated before
anything of that size is allocated, and the limit beyond which a net is refused (README).

Measured peak memory of ``dgpc init`` (net, metrics, OBJ and JSON text) grows by 1.7–1.9 KiB per
vertex (revolution nets of 200² to 800², geodesic nets on a mesh of 100 to 400 columns), on
top of about 0.1 GiB for the program and the reference mesh.
"""

from __future__ import annotations

import math

from dgpc_cli.errors import DgpcError

#: Estimated memory per net vertex while a net is made and written, bytes.
BYTES_PER_VERTEX = 2048
#: The largest estimate ``init`` accepts, bytes (about 2.1 million vertices, 1448 × 1448).
MAX_NET_BYTES = 4 * 2**30


class NetTooLarge(DgpcError):
    """A net beyond :data:`MAX_NET_BYTES`: the request itself is too large, whichever base
    curve or direction it is tried on."""


def net_bytes(m: float, n: float) -> float:
    """Estimated memory of making an ``m × n`` net, bytes (a float: counts estimated from a
    tiny spacing may be far beyond any integer size)."""
    return float(m) * float(n) * BYTES_PER_VERTEX


def _size(nbytes: float) -> str:
    if not math.isfinite(nbytes):
        return "more memory than a float can count"
    for unit, scale in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20)):
        if nbytes >= scale:
            return f"about {nbytes / scale:.3g} {unit} of memory"
    return f"about {nbytes / 2**10:.3g} KiB of memory"


def _count(x: float) -> str:
    return f"{x:.0f}" if x < 1e9 else f"{x:.3g}"


def check_net_size(m: float, n: float, source: str, hint: str) -> None:
    """DgpcError naming ``source`` (the option that set the size) when an ``m × n`` net would
    need more than :data:`MAX_NET_BYTES`; ``hint`` says what to change."""
    need = net_bytes(m, n)
    if need <= MAX_NET_BYTES and math.isfinite(need):
        return
    raise NetTooLarge(f"a net of {_count(m)} × {_count(n)} vertices would need {_size(need)} "
                    f"({BYTES_PER_VERTEX} bytes per vertex), beyond the limit of "
                    f"{MAX_NET_BYTES / 2**30:g} GiB ({MAX_NET_BYTES // BYTES_PER_VERTEX} "
                    f"vertices); {hint}", source=source)
