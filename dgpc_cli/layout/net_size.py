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
#: Estimated memory per net vertex while ``optimize`` runs, bytes, by mode: measured peaks
#: (161² and 321² sphere-zone nets, 3 iterations) grow by 2.7 KiB per vertex in revolution
#: mode and by 47–56 KiB in the fit, developable and isometric modes (the factorization of
#: their normal equations fills in), on top of about 0.09 GiB.
OPTIMIZE_BYTES_PER_VERTEX = {"revolution": 8 * 2**10, "fit": 64 * 2**10,
                             "developable": 64 * 2**10, "isometric": 64 * 2**10}
#: The largest estimate ``init`` and ``optimize`` accept, bytes (about 2.1 million vertices,
#: 1448 × 1448, for ``init``; for ``optimize`` 524,288 vertices, 724 × 724, in revolution
#: mode and 65,536, 256 × 256, in the others).
MAX_NET_BYTES = 4 * 2**30


class NetTooLarge(DgpcError):
    """A net beyond :data:`MAX_NET_BYTES`: the request itself is too large, whichever base
    curve or direction it is tried on."""


def net_bytes(m: float, n: float, per_vertex: int = BYTES_PER_VERTEX) -> float:
    """Estimated memory of making an ``m × n`` net, bytes (a float: counts estimated from a
    tiny spacing may be far beyond any integer size)."""
    return float(m) * float(n) * per_vertex


def _size(nbytes: float) -> str:
    if not math.isfinite(nbytes):
        return "more memory than a float can count"
    for unit, scale in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20)):
        if nbytes >= scale:
            return f"about {nbytes / scale:.3g} {unit} of memory"
    return f"about {nbytes / 2**10:.3g} KiB of memory"


def _count(x: float) -> str:
    return f"{x:.0f}" if x < 1e9 else f"{x:.3g}"


def check_net_size(m: float, n: float, source: str, hint: str, *,
                   per_vertex: int = BYTES_PER_VERTEX, what: str = "a net of") -> None:
    """DgpcError naming ``source`` (the option or file that set the size) when an ``m × n``
    net would need more than :data:`MAX_NET_BYTES` at ``per_vertex`` bytes a vertex
    (``optimize``: :data:`OPTIMIZE_BYTES_PER_VERTEX` of its mode); ``hint`` says what to
    change."""
    _check(net_bytes(m, n, per_vertex), f"{what} {_count(m)} × {_count(n)} vertices", source,
           hint, per_vertex)


def check_vertex_count(count: float, source: str, hint: str) -> None:
    """:func:`check_net_size` for a net known only by its number of vertices (an OBJ's lines,
    counted before it is parsed)."""
    _check(float(count) * BYTES_PER_VERTEX, f"a net of {_count(count)} vertices", source, hint,
           BYTES_PER_VERTEX)


def _check(need: float, subject: str, source: str, hint: str, per_vertex: int) -> None:
    if need <= MAX_NET_BYTES and math.isfinite(need):
        return
    raise NetTooLarge(f"{subject} would need {_size(need)} ({per_vertex} bytes per vertex), "
                      f"beyond the limit of {MAX_NET_BYTES / 2**30:g} GiB "
                      f"({MAX_NET_BYTES // per_vertex} vertices); {hint}", source=source)
