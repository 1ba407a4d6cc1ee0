"""The ``flat`` artifact (SPEC §3, §6 unfold): developed strips as 2-D parts, STEM.json + STEM.obj.

``data.parts`` (in part-id order) carries per part everything the next stage (nest) needs, in
the units of the net:

* ``id`` (the strip's stable id, e.g. ``S-v07``), ``strip`` (its column v), ``class``;
* ``outline``: the closed outline polygon, counter-clockwise, first point not repeated;
* ``score``: open polylines (the interior rulings, bend/score lines);
* ``label``: a point inside the part for its id;
* ``geodesics``: the two developed boundary geodesics A and B (the vertices of the quads
  ``A_u A_(u+1) B_(u+1) B_u``), ``straightness``, ``strain``, ``length``, ``area``;
* ``alignment``: the rigid motion ``x ↦ matrix·x + translation`` onto its class representative
  (with the boundary pairing used and whether it is a reflection) and its error.

``data.classes`` lists the congruence classes: ``id``, ``representative`` (a part id),
``quantity``, ``members`` (part ids) and the largest member error. The OBJ holds the same parts
(z = 0) as one object each, for viewers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .artifact import (
    artifact_files,
    artifact_paths,
    load_envelope,
)
from .strips import format_parts_obj, read_obj_checked

KIND = "flat"


@dataclass
class FlatArtifact:
    """Developed parts ``parts`` and congruence ``classes`` (JSON records as described in the
    module) with the envelope fields."""

    parts: list
    classes: list
    parameters: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    status: dict = field(default_factory=dict)

    def part(self, part_id: str) -> dict:
        for p in self.parts:
            if p["id"] == part_id:
                return p
        raise KeyError(part_id)


def _obj_bytes(parts: list) -> bytes:
    return format_parts_obj(f"flat parts ({len(parts)}), developed strips in the plane z = 0",
                            [(p["id"], np.asarray(p["geodesics"][0], float),
                              np.asarray(p["geodesics"][1], float)) for p in parts],
                            outlines={p["id"]: (p["outline"], p["score"]) for p in parts
                                      if p.get("trimmed")})


def flat_files(stem: str | Path, art: FlatArtifact) -> dict[Path, bytes]:
    """The bytes of ``STEM.json`` and ``STEM.obj`` (nothing written), schema-checked."""
    data = {"parts": art.parts, "classes": art.classes}
    return artifact_files(KIND, stem, _obj_bytes(art.parts), data, inputs=art.inputs,
                          parameters=art.parameters, metrics=art.metrics, status=art.status)


def read_flat(stem: str | Path) -> FlatArtifact:
    """Read and validate a flat artifact: envelope, schema, the OBJ's hash, and the classes'
    consistency with the parts (every part in exactly one class, quantities match)."""
    json_path, obj_path = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    read_obj_checked(json_path, obj_path, data["obj_sha256"])
    parts, classes = data["parts"], data["classes"]
    ids = [p["id"] for p in parts]
    if len(set(ids)) != len(ids):
        raise DgpcError("data.parts: duplicate part ids", source=json_path)
    members = [m for c in classes for m in c["members"]]
    if sorted(members) != sorted(ids):
        raise DgpcError("data.classes: the members are not the parts, each once", source=json_path)
    for i, c in enumerate(classes):
        if c["quantity"] != len(c["members"]) or c["representative"] not in c["members"]:
            raise DgpcError(f"data.classes[{i}]: quantity or representative does not match "
                            "its members", source=json_path)
    return FlatArtifact(parts=parts, classes=classes, parameters=doc["parameters"],
                        inputs=doc["inputs"], metrics=doc["metrics"], status=doc["status"])
