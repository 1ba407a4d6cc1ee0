"""The gate in front of every fabrication stage: no folded or collapsed net goes on (SPEC §4;
``laths``, ``planarize-strips``, ``unfold`` and ``extract-mold`` refuse a degenerate input)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.degenerate import GPC_LIMIT, degeneracies


def require_sound_net(f: np.ndarray, source, *, gpc: bool = True) -> None:
    """DgpcError naming ``source`` (one line: what is degenerate and in which rows and
    columns) when the net ``f (m, n, 3)`` is degenerate (see
    :func:`~dgpc_cli.metrics.degenerate.degeneracies`); without ``gpc`` only folded or
    collapsed quads count (``planarize-strips``: the strips between any two u-lines planarize,
    geodesic or not, but not folded ones)."""
    found = degeneracies(f, gpc_limit=GPC_LIMIT if gpc else None)
    if found:
        raise DgpcError(f"degenerate net (folded or collapsed): {found.message()}; fix or "
                        "re-make it first", source=source)


def require_sound_strips(geometry, ids: list[str], source) -> None:
    """DgpcError naming ``source`` and the first degenerate strip when a planar-quad strip
    ``(A, B)`` of ``geometry`` has a collapsed edge or a folded quad (the strip as an m × 2
    net; its rows are named)."""
    for (A, B), strip in zip(geometry, ids, strict=True):
        found = degeneracies(np.stack([A, B], axis=1), gpc_limit=None)
        if found:
            what = ("is folded: its developed outline crosses itself (planarize-strips "
                    "reports crossing rulings in status.rulings_cross)" if len(found.flipped)
                    else "is collapsed")
            raise DgpcError(f"strip {strip} {what}: {found.message()}", source=source)
