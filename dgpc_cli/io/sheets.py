"""The ``sheets`` artifact (SPEC §3, §6 nest): STEM.json + STEM.obj + per-sheet files.

Files, all listed in ``data.files`` (key → relative path and sha256); the file of key ``k`` is
``STEM.<k with '_' as '.'>``:

* ``sheetNN_dxf``, ``sheetNN_svg``, ``sheetNN_png`` — per sheet the cut DXF and its previews
  (:mod:`dgpc_cli.nesting.drawing`);
* ``parts_csv`` — one line per part: part id → 3-D strip (its net columns) → sheet → position;
* ``moldmap_dxf`` — with ``--mold``: the panel-to-mold map sheet.

``data`` holds the sheet (width, height, margin, spacing in mm; the net's ``units``, ``scale``
and the resulting ``mm_per_unit``), the allowed rotations, the engine, seed and time limit,
every placement (``part``, ``class``, ``strip``, ``sheet`` index, ``rotation`` in degrees,
``translation`` in mm: ``x_sheet = R(rotation) · mm_per_unit · x_part + translation``), per
sheet its parts and utilization, the overall utilization and the sheet count. The OBJ holds the
sheets side by side (sheet i shifted by i·1.1·width along x), z = 0: per sheet an object with
the sheet outline and each part's outline as closed polylines (``l``), one group per part.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .artifact import (
    artifact_files,
    artifact_paths,
    listed_path,
    load_envelope,
    read_listed,
    relative_input,
    reread,
)
from .obj import check_obj_objects, parse_obj

KIND = "sheets"
#: Gap between sheets in the OBJ, as a fraction of the sheet width.
OBJ_SHEET_GAP = 0.1


def rotation_matrix(deg: float) -> np.ndarray:
    """2×2 rotation by ``deg`` degrees, exact for multiples of 90°."""
    quarter = float(deg) / 90.0
    if quarter == round(quarter):
        c, s = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][int(round(quarter)) % 4]
    else:
        a = np.radians(deg)
        c, s = float(np.cos(a)), float(np.sin(a))
    return np.array([[c, -s], [s, c]])


def transform(points: np.ndarray, rotation: float, translation) -> np.ndarray:
    """``R(rotation) · points + translation`` for ``points (..., 2)``."""
    return np.asarray(points, float) @ rotation_matrix(rotation).T + np.asarray(translation,
                                                                                 float)


def extra_path(stem: str | Path, key: str) -> Path:
    """``STEM.<key with '_' → '.'>``, e.g. ``sheet01_dxf`` → ``STEM.sheet01.dxf``."""
    json_path, _ = artifact_paths(stem)
    return Path(str(json_path)[: -len(".json")] + "." + key.replace("_", "."))


def sheets_files(stem: str | Path, *, data: dict, extra: dict[str, bytes], obj: bytes,
                 inputs: dict, parameters: dict, metrics: dict, status: dict
                 ) -> dict[Path, bytes]:
    """The bytes of every file of the artifact (nothing written), the JSON schema-checked."""
    json_path, _ = artifact_paths(stem)
    folder = json_path.resolve().parent
    paths = {key: extra_path(stem, key) for key in extra}
    data = {**data,
            "files": {k: relative_input(paths[k], folder, extra[k]) for k in sorted(extra)}}
    files = artifact_files(KIND, stem, obj, data, inputs=inputs, parameters=parameters,
                           metrics=metrics, status=status)
    return {**files, **{paths[k]: extra[k] for k in sorted(extra)}}


@dataclass
class SheetsArtifact:
    """A sheets artifact read back (``data`` as in the JSON) and where its files are."""

    path: Path
    parameters: dict
    inputs: dict
    data: dict
    metrics: dict
    status: dict

    def file(self, key: str) -> Path:
        return listed_path(self.data["files"][key]["path"], self.path, f"data.files.{key}")


def _check_file(record: dict, json_path: Path, field: str) -> None:
    read_listed(listed_path(record["path"], json_path, field), record["sha256"], json_path,
                field)


def _check_obj(data: dict, json_path: Path) -> None:
    """The OBJ: one object per sheet (its id), in it a closed polyline for the sheet and one
    group with one polyline per part placed on it (the order of data.placements)."""
    path = listed_path(data["obj"], json_path, "data.obj")
    obj = parse_obj(read_listed(path, data["obj_sha256"], json_path, "data.obj"), path)
    check_obj_objects(obj, [(s["id"], None) for s in data["sheets"]], path, "data.sheets")
    for k, o in enumerate(obj.objects):
        parts = [p["part"] for p in data["placements"] if p["sheet"] == k]
        if o.groups != parts or o.lines != 1 + len(parts):
            raise DgpcError(f"object {o.name!r}: {len(o.groups)} parts in {o.lines} polylines, "
                            f"data.placements puts {len(parts)} parts on it", source=path)


@reread
def read_sheets(stem: str | Path) -> SheetsArtifact:
    """Read and validate a sheets artifact: envelope and schema, the sheet indices and counts,
    the OBJ and every listed file present and unchanged (sha256)."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    n = data["sheet_count"]
    if len(data["sheets"]) != n or len(data["utilization"]["per_sheet"]) != n:
        raise DgpcError(f"data.sheets: {len(data['sheets'])} sheets and "
                        f"{len(data['utilization']['per_sheet'])} utilizations, but "
                        f"sheet_count = {n}", source=json_path)
    for k, p in enumerate(data["placements"]):
        if p["sheet"] >= n:
            raise DgpcError(f"data.placements[{k}].sheet: {p['sheet']} but there are {n} "
                            "sheets", source=json_path)
    ids = [p["part"] for p in data["placements"]]
    if len(set(ids)) != len(ids):
        raise DgpcError("data.placements: a part is placed more than once", source=json_path)
    _check_obj(data, json_path)
    for key, record in data["files"].items():
        _check_file(record, json_path, f"data.files.{key}")
    return SheetsArtifact(path=json_path, parameters=doc["parameters"], inputs=doc["inputs"],
                          data=data, metrics=doc["metrics"], status=doc["status"])
