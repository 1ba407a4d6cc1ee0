"""``dgpc unfold``: develop planar-quad strips into the plane and group them into congruence
classes (paper §6.2.4, Fig. 18 bottom; SPEC §6, §7, §8)."""

from __future__ import annotations

import logging

import numpy as np
from shapely.geometry import Polygon

from dgpc_cli.errors import DgpcError
from dgpc_cli.strips.congruence import Alignment, congruence_classes
from dgpc_cli.strips.develop import develop_strip, signed_area
from dgpc_cli.strips.trim import developed_part

log = logging.getLogger(__name__)

#: Default congruence tolerance: largest point distance over the strip length (SPEC §8).
CONGRUENCE_TOL = 1e-3


def unfold_strips(geometry: list, ids: list[str], columns: list[int], *,
                  congruence_tol: float = CONGRUENCE_TOL,
                  mirror_ok: bool = False,
                  source: str | None = None,
                  trims: list | None = None) -> tuple[list[dict], list[dict], dict]:
    """Develop every strip ``(A, B)`` of ``geometry`` and classify the developments.

    Returns the part records and class records of the flat artifact (see
    :mod:`dgpc_cli.io.flat`) and its metrics. DgpcError (naming ``source``) when a developed
    outline crosses itself: a cutter cannot cut it. ``trims[i]`` (``planarize-strips
    --trim``), when given, lists the parts of strip i inside the reference's outline (records
    with ``id`` and ``outline`` in the strip's ``(t, s)``): those are developed instead of the
    whole strip, each its own congruence class (their end cuts follow the outline).
    """
    devs = [develop_strip(A, B) for A, B in geometry]
    if trims is not None and any(t is not None for t in trims):
        return _unfold_trimmed(devs, ids, columns, trims, congruence_tol, mirror_ok, source)
    folded = [ids[i] for i, d in enumerate(devs) if not Polygon(d.outline).is_valid]
    if folded:
        raise DgpcError(f"the developed outline of {', '.join(folded)} crosses itself (its "
                        "rulings cross; planarize-strips reports them in status.rulings_cross)",
                        source=source)
    classes = congruence_classes([(d.A, d.B, d.length) for d in devs], congruence_tol,
                                 mirror_ok=mirror_ok)
    parts: list[dict] = [{} for _ in devs]
    class_records = []
    for cls in classes:
        rep_len = devs[cls.representative].length
        for i, al in zip(cls.members, cls.alignments, strict=True):
            d = devs[i]
            parts[i] = {
                "id": ids[i], "strip": int(columns[i]), "class": cls.id,
                "outline": d.outline, "score": d.rulings, "label": d.label_point,
                "geodesics": [d.A, d.B], "straightness": d.straightness, "strain": d.strain,
                "length": d.length, "area": signed_area(d.outline),
                "alignment": al.record(rep_len)}
        errors = [al.error for al in cls.alignments]
        class_records.append({
            "id": cls.id, "representative": ids[cls.representative],
            "quantity": len(cls.members), "members": [ids[i] for i in cls.members],
            "max_error": max(errors), "max_relative_error": max(errors) / rep_len})
    metrics = flat_metrics(parts, class_records)
    log.info("%d parts in %d congruence classes; max strain %.3g", len(parts),
             len(class_records), metrics["max_strain"])
    return parts, class_records, metrics


def _unfold_trimmed(devs, ids, columns, trims, congruence_tol, mirror_ok, source):
    """:func:`unfold_strips` for strips clipped to the reference's outline."""
    whole = [i for i, t in enumerate(trims) if t is None]
    if whole:
        parts, classes, _ = unfold_strips(
            [(devs[i].A, devs[i].B) for i in whole], [ids[i] for i in whole],
            [columns[i] for i in whole], congruence_tol=congruence_tol, mirror_ok=mirror_ok,
            source=source)
    else:
        parts, classes = [], []
    identity = Alignment(R=np.eye(2), t=np.zeros(2), relabel="identity", mirrored=False,
                         error=0.0)
    for i, trim in enumerate(trims):
        if trim is None:
            continue
        d = devs[i]
        for piece in trim["parts"]:
            part = developed_part(d.A, d.B, np.asarray(piece["outline"], float))
            if not Polygon(part["outline"]).is_valid:
                raise DgpcError(f"the developed outline of {piece['id']} crosses itself",
                                source=source)
            cls = f"C{len(classes) + 1:02d}"
            parts.append({"id": piece["id"], "strip": int(columns[i]), "class": cls,
                          "strain": d.strain, "alignment": identity.record(part["length"]),
                          "trimmed": True, **part})
            classes.append({"id": cls, "representative": piece["id"], "quantity": 1,
                            "members": [piece["id"]], "max_error": 0.0,
                            "max_relative_error": 0.0})
    if not parts:
        raise DgpcError("no part lies inside the reference's outline", source=source)
    metrics = flat_metrics(parts, classes)
    log.info("%d parts (%d trimmed to the outline) in %d congruence classes; max strain %.3g",
             len(parts), sum(bool(p.get("trimmed")) for p in parts), len(classes),
             metrics["max_strain"])
    return parts, classes, metrics


def flat_metrics(parts: list[dict], classes: list[dict]) -> dict:
    """The metrics of a flat artifact recomputed from its records (for ``dgpc inspect``)."""
    return {
        "n_parts": len(parts), "n_classes": len(classes),
        "max_strain": max(p["strain"] for p in parts),
        "max_straightness": float(max(max(p["straightness"]) for p in parts)),
        "max_congruence_error": max(c["max_relative_error"] for c in classes),
        "classes": {c["id"]: {"quantity": c["quantity"], "representative": c["representative"],
                              "max_relative_error": c["max_relative_error"]} for c in classes},
        "per_part": {p["id"]: {"strain": p["strain"], "straightness": p["straightness"],
                               "length": p["length"], "class": p["class"],
                               "relative_error": p["alignment"]["relative_error"]}
                     for p in parts},
        "total_area": float(np.sum([p["area"] for p in parts])),
    }
