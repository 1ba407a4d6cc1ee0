"""The parts of several flat artifacts as one set, for one nesting (``dgpc nest FLAT FLAT ...``).

A facade of several patches is cut from one stock of sheets: every patch's parts are nested
together, and congruent parts of different patches are one class (one cutting template), its
quantity the sum over the patches.

* Part ids become ``TAG:ID`` (``facade-2:S-v03``), ``TAG`` naming the flat artifact the part
  comes from (:func:`flat_tags`), so that ids stay unique and say where each part goes.
* Classes are merged in order: each class of each flat joins the first merged class whose
  representative its own representative matches (the best rigid alignment's largest point
  distance at most the congruence tolerance times the merged representative's length, as
  within one flat: :func:`dgpc_cli.strips.congruence.align`), else it founds a new class.
  Classes are renumbered ``C01``, ``C02``, ... in that order; a member that joins a class of
  another flat is aligned onto that class's representative anew (its ``alignment`` record).
* The tolerance is the strictest of the flats' ``congruence_tol_mm`` (a length, as within one
  flat; a flat without one counts with the default); mirror images count only if every flat
  allowed them (``unfold --mirror-ok``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.flat import FlatArtifact
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.stages.unfold import CONGRUENCE_TOL_MM, class_record
from dgpc_cli.strips.congruence import align

#: Separator of a flat's tag and a part's own id in a combined part id.
TAG_SEPARATOR = ":"


@dataclass
class CombinedParts:
    """Parts and classes of several flats as one flat's records, and how they were merged."""

    parts: list[dict]
    classes: list[dict]
    tags: list[str]
    congruence_tol: float
    mirror_ok: bool

    def record(self) -> dict:
        """The merge as recorded in the sheets artifact (``data.combined``)."""
        return {"tags": self.tags, "congruence_tol_mm": self.congruence_tol,
                "mirror_ok": self.mirror_ok,
                "classes": [{k: c[k] for k in ("id", "representative", "quantity", "members",
                                                "per_tag", "max_relative_error",
                                                "max_deviation_mm")}
                            for c in self.classes]}


def flat_tags(stems: list[str | Path]) -> list[str]:
    """Tags of the flat artifacts ``stems``: their names when these differ (``facade-1-flat``),
    else the names of their folders when these differ (``facade-1/flat``), else ``F1``,
    ``F2``, ..."""
    paths = [Path(s) for s in stems]
    for names in ([p.with_suffix("").name if p.suffix == ".json" else p.name for p in paths],
                  [p.resolve().parent.name for p in paths]):
        if len(set(names)) == len(names) and all(names):
            return names
    return [f"F{k + 1}" for k in range(len(paths))]


def _geodesics(part: dict) -> tuple[np.ndarray, np.ndarray]:
    """The edges the part is cut along: its ``edges`` (a template's curves), else its
    geodesics."""
    A, B = part.get("edges", part["geodesics"])
    return np.asarray(A, float), np.asarray(B, float)


def combine_flats(flats: list[tuple[str, FlatArtifact]]) -> CombinedParts:
    """The parts of the flats ``(tag, artifact)`` as one set; see the module."""
    tags = [tag for tag, _ in flats]
    if len(set(tags)) != len(tags):
        raise DgpcError(f"the flat artifacts' tags repeat ({', '.join(tags)})", source="nest")
    tol = min(float(f.parameters.get("congruence_tol_mm", CONGRUENCE_TOL_MM)) for _, f in flats)
    mm = mm_per_unit(flats[0][1].units)    # the flats share their unit (checked before)
    mirror_ok = all(bool(f.parameters.get("mirror_ok", False)) for _, f in flats)
    parts: list[dict] = []
    merged: list[dict] = []             # merged classes, with the representative's record
    for tag, flat in flats:
        by_id = {p["id"]: p for p in flat.parts}
        new_id: dict[str, str] = {}     # this flat's class id -> merged class id
        realign: dict[str, dict] = {}   # this flat's class id -> merged representative
        for cls in flat.classes:
            rep = by_id[cls["representative"]]
            A, B = _geodesics(rep)
            target = None
            for m in merged:
                Ar, Br = _geodesics(m["rep"])
                if align(A, B, Ar, Br, mirror_ok=mirror_ok).error * mm <= tol:
                    target = m
                    break
            if target is None:
                target = {"id": f"C{len(merged) + 1:02d}", "rep": rep, "tag": tag,
                          "members": [], "per_tag": {}, "errors": []}
                merged.append(target)
            else:
                realign[cls["id"]] = target["rep"]
            new_id[cls["id"]] = target["id"]
            target["per_tag"][tag] = target["per_tag"].get(tag, 0) + cls["quantity"]
        for p in flat.parts:
            record = {**p, "id": f"{tag}{TAG_SEPARATOR}{p['id']}", "class": new_id[p["class"]]}
            rep = realign.get(p["class"])
            if rep is not None:
                al = align(*_geodesics(p), *_geodesics(rep), mirror_ok=mirror_ok)
                record["alignment"] = al.record(rep["length"], mm)
            target = next(m for m in merged if m["id"] == record["class"])
            target["members"].append(record["id"])
            target["errors"].append(record["alignment"]["error"])
            parts.append(record)
    classes = [{**class_record(m["id"], f"{m['tag']}{TAG_SEPARATOR}{m['rep']['id']}",
                               m["members"], m["errors"], m["rep"]["length"]),
                "max_deviation_mm": max(m["errors"]) * mm, "per_tag": m["per_tag"]}
               for m in merged]
    return CombinedParts(parts, classes, tags, tol, mirror_ok)
