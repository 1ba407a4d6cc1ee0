"""The gate in front of every fabrication stage: no folded or collapsed net goes on (SPEC §4;
``laths``, ``planarize-strips``, ``unfold`` and ``extract-mold`` refuse a degenerate input)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.degenerate import degeneracies


def require_sound_net(f: np.ndarray, source) -> None:
    """DgpcError naming ``source`` (one line: what is degenerate and in which rows and
    columns) when the net ``f (m, n, 3)`` is degenerate (see
    :func:`~dgpc_cli.metrics.degenerate.degeneracies`)."""
    found = degeneracies(f)
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
            raise DgpcError(f"strip {strip} is degenerate (folded or collapsed): "
                            f"{found.message()}", source=source)
