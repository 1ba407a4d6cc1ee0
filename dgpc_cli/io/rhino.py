"""Rhino ``.3dm`` export of the geometry artifacts (``--format 3dm``), with rhino3dm.

The 3dm is an extra file ``STEM.3dm`` written beside the artifact's JSON and OBJ (which stay the
pipeline's own format); the JSON records it as ``data.rhino_3dm`` (``path`` relative to the JSON,
``sha256``). The model's unit system is the artifact's unit (``data.units``) and coordinates are
the artifact's own; the sheets are in mm.

Contents per kind (layer: objects; every object named, with user text: ``id``, ``kind`` and
what the object is — class, length, width, sheet, mold piece …):

* net — ``Net``: one quad mesh of the m×n grid (vertices row-major, (m−1)(n−1) faces);
  ``Geodesics``: the n u-lines ``f[:, v]`` as open polylines named ``u-v00`` …;
* strips — ``Strips::S-v07``: a sublayer per strip with its quad mesh, vertices
  A_0 B_0 A_1 B_1 …;
* flat — ``Flat::CUT`` (closed outlines), ``Flat::SCORE`` (score lines, ``<id>/score``),
  ``Flat::LABEL`` (a text dot with the id at its label point): the parts side by side, each
  moved by the translation in its ``place`` user text, never on top of each other;
* sheets — per sheet ``Sheet01::SHEET`` (the border), ``Sheet01::CUT``, ``::SCORE``,
  ``::LABEL`` (the label as on the DXF, leaders as polylines), the sheets side by side along x
  as in the OBJ;
* laths — ``Laths::A`` and ``Laths::B``: one open polyline per lath;
* mold — ``Mold::surface`` and ``Mold::sector`` (the quad meshes of the OBJ's two objects) and
  ``Panels::net1`` … : per input net a mesh per panel named by its id (with its mold piece).

Object and layer ids are derived from their names (uuid5), so a model holds the same content
each run, and the file's bytes depend on that content alone: no write time, no temporary path
(:mod:`.rhino_archive`).
"""

from __future__ import annotations

import base64
import json
import uuid
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import DgpcError
from .artifact import artifact_paths, dumps_json, relative_input, validate_envelope
from .flat import side_by_side
from .obj import net_quads
from .rhino_archive import fixed_times
from .sheets import transform

if TYPE_CHECKING:
    import rhino3dm

#: Namespace of the deterministic layer and object ids.
ID_NAMESPACE = uuid.UUID("6f1d2a4e-3c5b-4e7a-9d21-0d9c3a7b5e10")
#: Rhino's unit system (a ``rhino3dm.UnitSystem`` member) of each length unit.
UNIT_SYSTEMS = {"mm": "Millimeters", "cm": "Centimeters", "m": "Meters", "in": "Inches",
                "ft": "Feet"}
#: Layer colours (RGBA) by the last part of a layer's path.
COLORS = {"Net": (128, 128, 128, 255), "Geodesics": (200, 30, 30, 255),
          "CUT": (220, 0, 0, 255), "SCORE": (0, 0, 220, 255), "LABEL": (0, 150, 0, 255),
          "SHEET": (140, 140, 140, 255), "A": (200, 30, 30, 255), "B": (30, 30, 200, 255),
          "surface": (150, 150, 150, 255), "sector": (60, 120, 200, 255)}
#: rhino3dm file version written.
ARCHIVE_VERSION = 8
#: Gap between sheets along x, as a fraction of the sheet width (as the sheets OBJ).
SHEET_GAP = 0.1


class Model:
    """A ``rhino3dm.File3dm`` in ``units`` with layers (paths ``Parent::Child``) and named
    objects carrying user text. rhino3dm is imported here, not with the module: most commands
    write no 3dm, and it takes a tenth of a second to load."""

    def __init__(self, units: str, kind: str) -> None:
        import rhino3dm

        if units not in UNIT_SYSTEMS:
            raise DgpcError(f"unknown length unit {units!r}", source="data.units")
        self._rh = rhino3dm
        self.file = rhino3dm.File3dm()
        self.file.Settings.ModelUnitSystem = getattr(rhino3dm.UnitSystem, UNIT_SYSTEMS[units])
        self.file.ApplicationName = "dgpc"
        self.kind = kind
        self._layers: dict[str, int] = {}
        self._ids: set[str] = set()

    def layer(self, path: str) -> int:
        """The index of the layer ``path`` (``"Sheet01::CUT"``), made with its parents."""
        if path not in self._layers:
            parent, _, name = path.rpartition("::")
            layer = self._rh.Layer()
            layer.Name = name
            layer.Id = str(uuid.uuid5(ID_NAMESPACE, "layer/" + path))
            if parent:
                self.layer(parent)
                layer.ParentLayerId = str(uuid.uuid5(ID_NAMESPACE, "layer/" + parent))
            layer.Color = COLORS.get(name, (0, 0, 0, 255))
            self._layers[path] = self.file.Layers.Add(layer)
        return self._layers[path]

    def _attributes(self, layer: str, name: str, info: dict) -> rhino3dm.ObjectAttributes:
        attrs = self._rh.ObjectAttributes()
        attrs.LayerIndex = self.layer(layer)
        attrs.Name = name
        for key, value in {"id": name, "kind": self.kind, **info}.items():
            attrs.SetUserString(key, value if isinstance(value, str) else _text(value))
        key, k = f"{layer}/{name}", 0
        while key in self._ids:  # same name twice on a layer: still unique ids
            k += 1
            key = f"{layer}/{name}#{k}"
        self._ids.add(key)
        attrs.Id = str(uuid.uuid5(ID_NAMESPACE, "object/" + key))
        return attrs

    def mesh(self, layer: str, name: str, vertices, quads, info: dict | None = None) -> None:
        mesh = self._rh.Mesh()
        points = np.asarray(vertices, float).reshape(-1, 3).tolist()
        for x, y, z in points:
            mesh.Vertices.Add(x, y, z)
        # Add stores floats; switch to double precision, then set each vertex exactly.
        mesh.Vertices.UseDoublePrecisionVertices = True
        for i, (x, y, z) in enumerate(points):
            mesh.Vertices.SetPoint3dAt(i, self._rh.Point3d(x, y, z))
        for a, b, c, d in np.asarray(quads, int).reshape(-1, 4).tolist():
            mesh.Faces.AddFace(a, b, c, d)
        self.file.Objects.AddMesh(mesh, self._attributes(layer, name, info or {}))

    def polyline(self, layer: str, name: str, points, *, closed: bool = False,
                 info: dict | None = None) -> None:
        pts = _xyz(points)
        polyline = self._rh.Polyline(len(pts) + int(closed))
        for x, y, z in pts.tolist():
            polyline.Add(x, y, z)
        if closed:
            polyline.Add(*pts[0].tolist())
        self.file.Objects.AddPolyline(polyline, self._attributes(layer, name, info or {}))

    def dot(self, layer: str, name: str, text: str, point, info: dict | None = None) -> None:
        x, y, z = _xyz(np.asarray(point, float).reshape(1, -1))[0].tolist()
        self.file.Objects.AddTextDot(text, self._rh.Point3d(x, y, z),
                                     self._attributes(layer, name, info or {}))

    def to_bytes(self) -> bytes:
        """The .3dm bytes, which depend on the model alone: written to memory (an archive
        written to a file records its path) with fixed revision times
        (:func:`~dgpc_cli.io.rhino_archive.fixed_times`)."""
        options = self._rh.File3dmWriteOptions()
        options.Version = ARCHIVE_VERSION
        try:
            blob = base64.b64decode(self.file.Encode(options), validate=True)
        except (ValueError, RuntimeError) as e:
            raise DgpcError(f"rhino3dm could not write the model ({e})",
                            source="--format 3dm") from None
        return fixed_times(blob)


def _text(value) -> str:
    """User text of a value: floats exact (``repr``), lists joined by ``,``."""
    if isinstance(value, float):
        return repr(float(value))
    if isinstance(value, list | tuple):
        return ",".join(_text(v) for v in value)
    return str(value)


def _xyz(points) -> np.ndarray:
    """``(k, 3)`` float points; 2-D points get z = 0."""
    pts = np.asarray(points, float)
    if pts.shape[-1] == 2:
        pts = np.concatenate([pts, np.zeros((*pts.shape[:-1], 1))], axis=-1)
    return pts.reshape(-1, 3)


def net_model(f: np.ndarray, units: str) -> Model:
    """A net ``f (m, n, 3)``: the quad mesh and the n u-line geodesics."""
    model = Model(units, "net")
    f = np.asarray(f, float)
    m, n = f.shape[:2]
    model.mesh("Net", "net", f, net_quads(m, n), {"rows": m, "columns": n})
    width = max(2, len(str(n - 1)))
    for v in range(n):
        model.polyline("Geodesics", f"u-v{v:0{width}d}", f[:, v], info={"column": v})
    return model


def strips_model(strips: list[tuple[dict, np.ndarray, np.ndarray]], units: str) -> Model:
    """Strips ``(record, A (m, 3), B (m, 3))``: one quad mesh each on its own sublayer,
    vertices A_0 B_0 A_1 B_1 …"""
    model = Model(units, "strips")
    for rec, A, B in strips:
        grid = np.stack([_xyz(A), _xyz(B)], axis=1).reshape(-1, 3)
        a = 2 * np.arange(len(A))
        quads = np.stack([a[:-1], a[1:], a[1:] + 1, a[:-1] + 1], axis=-1)
        model.mesh(f"Strips::{rec['id']}", rec["id"], grid, quads,
                   {"strip": rec["v"], "width": rec["width"], "planarity": rec["planarity"]})
    return model


def part_info(part: dict) -> dict:
    """User text of a flat part (its unit's lengths)."""
    return {"class": part["class"], "strip": part["strip"], "board": part["board"],
            "rows": part["rows"], "length": part["length"], "width_min": part["width"][0],
            "width_max": part["width"][1]}


def _add_part(model: Model, layer: str, part: dict, place, info: dict,
              label: tuple[str, np.ndarray] | None = None) -> None:
    pid = part["id"]
    model.polyline(f"{layer}::CUT", pid, place(part["outline"]), closed=True, info=info)
    for line in part["score"]:
        model.polyline(f"{layer}::SCORE", f"{pid}/score", place(line), info=info)
    text, at = label if label is not None else (pid, place(np.reshape(part["label"], (1, 2))))
    model.dot(f"{layer}::LABEL", f"{pid}/label", text, at, info=info)


def flat_model(parts: list[dict], units: str) -> Model:
    """Flat parts (records of the flat artifact), side by side (z = 0)."""
    model = Model(units, "flat")
    for part, t in zip(parts, side_by_side([p["outline"] for p in parts]), strict=True):
        _add_part(model, "Flat", part, lambda p, t=t: np.asarray(p, float) + t,
                  {**part_info(part), "place": [float(t[0]), float(t[1])]})
    return model


def sheets_model(data: dict, parts: list[dict]) -> Model:
    """Sheets (``data`` of the sheets artifact) with the flat ``parts`` they place, in mm."""
    model = Model("mm", "sheets")
    by_id = {p["id"]: p for p in parts}
    W, H = float(data["sheet"]["width"]), float(data["sheet"]["height"])
    k = float(data["sheet"]["mm_per_unit"])
    for sheet in data["sheets"]:
        s = int(sheet["index"])
        layer = f"Sheet{s + 1:02d}"
        dx = np.array([s * (1.0 + SHEET_GAP) * W, 0.0])
        model.polyline(f"{layer}::SHEET", sheet["id"],
                       np.array([[0.0, 0.0], [W, 0.0], [W, H], [0.0, H]]) + dx, closed=True,
                       info={"sheet": sheet["id"], "width": W, "height": H})
        for pl in data["placements"]:
            if pl["sheet"] != s:
                continue
            if pl["part"] not in by_id:
                raise DgpcError(f"placed part {pl['part']} is not among the flat parts")
            part = by_id[pl["part"]]
            info = {**part_info(part), "sheet": sheet["id"], "rotation": pl["rotation"],
                    "translation": pl["translation"]}
            label = (pl["label"]["text"], np.asarray(pl["label"]["at"], float) + dx)
            _add_part(model, layer, part,
                      lambda p, pl=pl, dx=dx: transform(k * np.asarray(p, float),
                                                        pl["rotation"], pl["translation"]) + dx,
                      info, label)
    return model


def laths_model(laths: list[tuple[str, str, np.ndarray]], units: str) -> Model:
    """Laths ``(id, family, points (k, 3))`` as polylines on layers ``Laths::<family>``."""
    model = Model(units, "laths")
    for lid, family, points in laths:
        pts = np.asarray(points, float)
        length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        model.polyline(f"Laths::{family}", lid, pts, info={"family": family, "length": length})
    return model


def parse_obj_objects(data: bytes) -> list[tuple[str, np.ndarray, list, list, list]]:
    """The objects of an OBJ as ``(name, vertices (k, 3), faces, lines, groups)`` with 0-based
    indices local to the object; ``groups[i]`` is the group (``g``) of face i ("" if none)."""
    vertices: list[tuple[float, float, float]] = []
    objects: list[tuple[str, int, list, list, list]] = []
    group = ""
    for raw in data.decode("ascii").splitlines():
        tok = raw.split()
        if not tok:
            continue
        if tok[0] == "o":
            objects.append((" ".join(tok[1:]), len(vertices), [], [], []))
            group = ""
        elif tok[0] == "g":
            group = " ".join(tok[1:])
        elif tok[0] == "v":
            vertices.append((float(tok[1]), float(tok[2]), float(tok[3])))
        elif tok[0] in ("f", "l") and objects:
            idx = [int(t.split("/")[0]) - 1 for t in tok[1:]]
            objects[-1][2 if tok[0] == "f" else 3].append(idx)
            if tok[0] == "f":
                objects[-1][4].append(group)
    out = []
    ends = [start for _, start, *_ in objects[1:]] + [len(vertices)]
    for (name, start, faces, lines, groups), end in zip(objects, ends, strict=True):
        out.append((name, np.array(vertices[start:end], float).reshape(-1, 3),
                    [[i - start for i in f] for f in faces],
                    [[i - start for i in ln] for ln in lines], groups))
    return out


def mold_model(obj: bytes, panels_obj: bytes, data: dict) -> Model:
    """The mold OBJ's objects ``surface`` and ``sector`` as quad meshes, and every panel of
    the nets (``panels_obj``, faces grouped by panel id) as a mesh named by its id."""
    model = Model(data["units"], "mold")
    for name, vertices, faces, _, _ in parse_obj_objects(obj):
        model.mesh(f"Mold::{name}", name, vertices, faces)
    panels = {p["id"]: p for p in data["panels"]}
    for name, vertices, faces, _, groups in parse_obj_objects(panels_obj):
        faces = np.asarray(faces, int)
        for pid in dict.fromkeys(groups):
            quads = faces[[g == pid for g in groups]]
            used, local = np.unique(quads, return_inverse=True)
            p = panels[pid]
            model.mesh(f"Panels::{name}", pid, vertices[used], local.reshape(-1, 4),
                       {"piece": p["piece"] or "none (flat)", "flat": p["flat"],
                        "rows": p["rows"], "cols": p["cols"],
                        "isometry_error": p["isometry_error"]})
    return model


def artifact_model(files: dict[Path, bytes], stem: str | Path, *,
                   parts: list[dict] | None = None) -> Model:
    """The model of an artifact about to be written (``files`` from ``*_files``)."""
    from .obj import parse_net_obj
    from .strips import parse_parts_obj

    json_path, obj_path = artifact_paths(stem)
    doc = json.loads(files[json_path])
    kind, data = doc["kind"], doc["data"]
    obj = files.get(obj_path, b"")
    if kind == "net":
        m, n = data["shape"]
        return net_model(parse_net_obj(obj, m, n, obj_path), data["units"])
    if kind == "strips":
        geometry = parse_parts_obj(obj, [r["rows"] for r in data["strips"]], obj_path)
        return strips_model([(r, A, B) for r, (A, B) in
                             zip(data["strips"], geometry, strict=True)], data["units"])
    if kind == "flat":
        return flat_model(data["parts"], data["units"])
    if kind == "sheets":
        if parts is None:
            raise DgpcError("3dm of sheets needs the flat parts", source=json_path)
        return sheets_model(data, parts)
    if kind == "laths":
        n_a = int(data["laths"]["A"])
        objs = parse_obj_objects(obj)
        return laths_model([(name, "A" if i < n_a else "B", v)
                            for i, (name, v, *_) in enumerate(objs)], data["units"])
    if kind == "mold":
        panels_path = json_path.resolve().parent / data["files"]["panels_obj"]["path"]
        return mold_model(obj, files[_match(files, panels_path)], data)
    raise DgpcError(f"no 3dm export for a '{kind}' artifact", source=json_path)


def _match(files: dict[Path, bytes], path: Path) -> Path:
    """The key of ``files`` that is ``path`` (keys may be relative)."""
    for key in files:
        if Path(key).resolve() == path:
            return key
    raise KeyError(path)


def rhino_path(stem: str | Path) -> Path:
    """``STEM.3dm``."""
    json_path, _ = artifact_paths(stem)
    return json_path.with_suffix(".3dm")


def with_3dm(files: dict[Path, bytes], stem: str | Path, fmt: str, *,
             parts: list[dict] | None = None) -> dict[Path, bytes]:
    """``files`` plus ``STEM.3dm`` when ``fmt == "3dm"`` (the JSON then records it as
    ``data.rhino_3dm``, re-validated); ``files`` unchanged for ``"obj"``."""
    if fmt != "3dm":
        return files
    json_path, _ = artifact_paths(stem)
    path = rhino_path(stem)
    blob = artifact_model(files, stem, parts=parts).to_bytes()
    doc = json.loads(files[json_path])
    doc["data"]["rhino_3dm"] = relative_input(path, json_path.resolve().parent, blob)
    json_bytes = dumps_json(doc)
    validate_envelope(json.loads(json_bytes), doc["kind"], json_path)
    return {**files, json_path: json_bytes, path: blob}


__all__ = ["Model", "artifact_model", "flat_model", "laths_model", "mold_model", "net_model",
           "rhino_path", "sheets_model", "strips_model", "with_3dm"]
