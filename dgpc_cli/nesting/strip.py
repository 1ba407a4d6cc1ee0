"""spyrrow (the Python wheel of sparrow) as a strip packer: the yardstick of ``make bench`` and
the optional ``--engine spyrrow`` of ``dgpc nest`` (SPEC §10).

spyrrow packs one strip of fixed height and minimal length, stopping on a wall-clock budget
(``total_computation_time``; its ``early_termination`` ends sooner once it stalls). With one
worker and a fixed seed its search is the same sequence of steps on every run, but where the
budget cuts that sequence depends on the machine's speed and load: results are reproducible
only when the budget is not what stops it. This is why the default engine of ``dgpc nest`` is
the deterministic fill of :mod:`~dgpc_cli.nesting.blf`.
"""

from __future__ import annotations

import logging

import numpy as np

from .blf import Placement, Sheet
from .geometry import CLEARANCE_MM, Part, rotation_matrix
from .pairs import _norm

log = logging.getLogger(__name__)

#: Extra clearance for spyrrow's single-precision coordinates (mm).
SPYRROW_CLEARANCE_MM = 1e-2


def _solve(parts: list[Part], indices: list[int], height: float, rotations: list[float],
           spacing: float, time_limit: float, seed: int):
    import spyrrow

    items = [spyrrow.Item(str(i), [tuple(q) for q in parts[i].outline.tolist()], 1,
                          [float(r) for r in rotations]) for i in indices]
    config = spyrrow.StripPackingConfig(
        early_termination=True, total_computation_time=max(1, int(round(time_limit))),
        seed=int(seed), num_workers=1,
        min_items_separation=(spacing + SPYRROW_CLEARANCE_MM) if spacing > 0 else None)
    return spyrrow.StripPackingInstance("dgpc", float(height), items).solve(config)


def strip_density(parts: list[Part], height: float, rotations: list[float], spacing: float,
                  time_limit: float, seed: int) -> tuple[float, float]:
    """spyrrow's own single-strip result for all ``parts``: ``(density, length)`` of a strip
    of height ``height`` (mm)."""
    sol = _solve(parts, list(range(len(parts))), height, rotations, spacing, time_limit, seed)
    return float(sol.density), float(sol.width)


def spyrrow_sheets(parts: list[Part], sheet: Sheet, rotations: list[float], time_limit: float,
                   seed: int, progress=None) -> list[Placement]:
    """Fill sheets one after another: strip-pack the remaining parts with the sheet's inner
    height as the strip height, keep the parts that lie within the sheet's inner width, repeat
    with the rest."""
    m = sheet.margin + CLEARANCE_MM + SPYRROW_CLEARANCE_MM
    inner_w, inner_h = sheet.width - 2 * m, sheet.height - 2 * m
    remaining = list(range(len(parts)))
    out: list[Placement] = []
    s = 0
    while remaining:
        sol = _solve(parts, remaining, inner_h, rotations, sheet.spacing, time_limit, seed)
        placed = []
        for item in sol.placed_items:
            i = int(item.id)
            rot = _norm(item.rotation)
            rot = next((r for r in rotations if _norm(r) == rot), rot)
            placed.append((i, rot, np.asarray(item.translation, float),
                           parts[i].outline @ rotation_matrix(rot).T))
        # spyrrow keeps the items' separation from the strip's ends too: the layout starts
        # that far in, so measure what a sheet takes from its left-most point
        x0 = min((float((pts[:, 0] + t[0]).min()) for _, _, t, pts in placed), default=0.0)
        kept = [Placement(i, s, float(rot), (float(t[0]) - x0 + m, float(t[1]) + m))
                for i, rot, t, pts in placed if (pts[:, 0] + t[0]).max() - x0 <= inner_w]
        if not kept:
            kept_i = min(sol.placed_items, key=lambda it: it.translation[0])
            raise RuntimeError(f"spyrrow placed nothing inside the sheet (first: {kept_i.id})")
        out += kept
        done = {p.index for p in kept}
        remaining = [i for i in remaining if i not in done]
        if progress is not None:
            progress(len(kept))
        log.info("spyrrow: sheet %d takes %d parts, %d left", s + 1, len(kept), len(remaining))
        s += 1
    return sorted(out, key=lambda p: (p.sheet, p.index))
