"""The gate in front of every fabrication stage: no folded or collapsed net goes on (SPEC §4;
``laths``, ``planarize-strips``, ``unfold`` and ``extract-mold`` refuse a degenerate input)."""

from __future__ import annotations

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.degenerate import GPC_LIMIT, degeneracies
from dgpc_cli.strips.crossing import folded_inside


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


def require_sound_strips(geometry, ids: list[str], source, spans: list | None = None,
                         parts: list | None = None) -> None:
    """DgpcError naming ``source`` and the first degenerate strip when a planar-quad strip
    ``(A, B)`` of ``geometry`` has a collapsed edge or a folded quad (the strip as an m × 2
    net; its rows are named). ``spans[i]``, when given and not None, lists the row ranges
    ``(r0, r1)`` of strip i that are cut (its parts trimmed to the reference's outline): a
    degenerate quad outside them (in the overhang, trimmed away) does not count; ``parts[i]``,
    when given and not None, the outlines of those parts in the strip's ``(t, s)``: a fold
    (crossing rulings, no collapsed edge) counts only where it lies inside one of them
    (``strips.crossing``), as ``planarize-strips`` reports it."""
    for i, ((A, B), strip) in enumerate(zip(geometry, ids, strict=True)):
        found = degeneracies(np.stack([A, B], axis=1), gpc_limit=None)
        span = None if spans is None else spans[i]
        if found and span is not None:
            cut = np.zeros(found.bad_quads.shape[0], bool)
            for r0, r1 in span:
                cut[r0:r1] = True
            found = found if found.bad_quads[cut].any() else None
        if found and parts is not None and parts[i] is not None and not len(found.short_u) \
                and not len(found.short_v) and not folded_inside(A, B, None, None, parts[i]):
            found = None
        if found:
            what = ("is folded: its developed outline crosses itself (planarize-strips "
                    "reports crossing rulings in status.rulings_cross)" if len(found.flipped)
                    else "is collapsed")
            raise DgpcError(f"strip {strip} {what}: {found.message()}", source=source)
