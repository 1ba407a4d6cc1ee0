"""Fabrication figures of a net being edited (``dgpc edit``): what ``planarize-strips``,
``unfold`` and ``extract-mold`` would make of it, run in memory on the stage functions."""

from __future__ import annotations

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.units import from_mm
from dgpc_cli.mold.extract import extract_mold
from dgpc_cli.stages.unfold import unfold_strips
from dgpc_cli.strips.planarize import planarize_strips


def fabrication_figures(f_mm: np.ndarray, units: str) -> dict:
    """``{"strips": {...} | {"error": str}, "mold": {...} | {"error": str}}``: the congruence
    classes of the developed strips (count, quantity per class, their largest deviation as a
    fraction of the length) and the strips' largest deviation from the net (fraction of the
    width); the mold (one surface of revolution: its pieces and their lengths in the net's
    unit) and the largest strain of a panel against it."""
    f_mm = np.asarray(f_mm, dtype=float)
    n = f_mm.shape[1]
    out: dict = {}
    try:
        strips = planarize_strips(f_mm, list(range(n - 1)))
        _, classes, _ = unfold_strips([(s.A, s.B) for s in strips], [s.id for s in strips],
                                      [s.v for s in strips])
        out["strips"] = {
            "strips": len(strips), "classes": len(classes),
            "quantities": [c["quantity"] for c in classes],
            "class_deviation": max(c["max_relative_error"] for c in classes),
            "strip_deviation": max(s.deviation for s in strips)}
    except DgpcError as err:
        out["strips"] = {"error": str(err)}
    try:
        mold = extract_mold([("net", from_mm(f_mm, units))])
        figures = mold.metrics()
        out["mold"] = {"pieces": [{"id": p.id, "rows": [p.start, p.stop], "length": p.length}
                                  for p in mold.pieces],
                       "segments": figures["segments"],
                       "radius": [figures["radius_min"], figures["radius_max"]],
                       "strain_max": figures["isometry_error_max"]}
    except DgpcError as err:
        out["mold"] = {"error": str(err)}
    return out
