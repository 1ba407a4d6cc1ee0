"""Rhino ``.3dm`` export of the geometry artifacts (``--format 3dm``), with rhino3dm.

The 3dm is an extra file ``STEM.3dm`` written beside the artifact's JSON and OBJ (which stay the
pipeline's own format); the JSON records it as ``data.rhino_3dm`` (``path`` relative to the JSON,
``sha256``). The model unit system is millimeters. Lengths: the net, strips, flat parts and
laths are written in the net's model units taken as mm (scale 1, as ``nest --units mm``); the
sheets are in mm already (``x_sheet = R · mm_per_unit · x_part + translation``); the mold is
scaled from its ``data.unit`` to mm.

Contents per kind (layer: objects, each named):

* net — ``net``: one quad mesh of the m×n grid (vertices row-major, (m−1)(n−1) faces);
  ``geodesics``: the n u-lines ``f[:, v]`` as open polylines named ``u-v00`` … (every column,
  boundary columns included);
* strips — ``strips``: one quad mesh per strip named by its id (``S-v07``), vertices
  A_0 B_0 A_1 B_1 …;
* flat — ``flat-parts``: the closed outline of each part named by its id; ``score``: the score
  lines (rulings) named ``<id>/score``; ``labels``: a text dot with the id at its label point;
* sheets — per sheet a layer ``sheet01`` … with the sheet outline (named ``SH01``), the placed
  parts' outlines, score lines and label dots; sheets side by side along x as in the OBJ;
* laths — ``laths-A`` and ``laths-B``: one open polyline per lath named by its id;
* mold — ``mold-surface`` and ``mold-sector``: the quad meshes of the OBJ's two objects.

Object and layer ids are derived from their names (uuid5), so a model holds the same content
each run; the file bytes still differ between runs because openNURBS stamps the write time into
the header.
"""

from __future__ import annotations

import json
import tempfile
import uuid
from pathlib import Path

import numpy as np
import rhino3dm

from ..errors import DgpcError
from .artifact import artifact_paths, dumps_json, relative_input, validate_envelope
from .dxf import UNIT_MM
from .obj import net_quads

#: Namespace of the deterministic layer and object ids.
ID_NAMESPACE = uuid.UUID("6f1d2a4e-3c5b-4e7a-9d21-0d9c3a7b5e10")
#: Layer colours (RGBA).
COLORS = {"net": (128, 128, 128, 255), "geodesics": (200, 30, 30, 255),
          "strips": (60, 120, 200, 255), "flat-parts": (0, 0, 0, 255),
          "score": (220, 120, 0, 255), "labels": (0, 140, 0, 255),
          "laths-A": (200, 30, 30, 255), "laths-B": (30, 30, 200, 255),
          "mold-surface": (150, 150, 150, 255), "mold-sector": (60, 120, 200, 255)}
#: rhino3dm file version written.
ARCHIVE_VERSION = 8
#: Gap between sheets along x, as a fraction of the sheet width (as the sheets OBJ).
SHEET_GAP = 0.1


class Model:
    """A ``rhino3dm.File3dm`` in millimeters with layers and named objects added by name."""

    def __init__(self) -> None:
        self.file = rhino3dm.File3dm()
        self.file.Settings.ModelUnitSystem = rhino3dm.UnitSystem.Millimeters
        self.file.ApplicationName = "dgpc"
        self._layers: dict[str, int] = {}
        self._ids: set[str] = set()

    def layer(self, name: str) -> int:
        if name not in self._layers:
            layer = rhino3dm.Layer()
            layer.Name = name
            layer.Id = str(uuid.uuid5(ID_NAMESPACE, "layer/" + name))
            layer.Color = COLORS.get(name, (0, 0, 0, 255))
            self._layers[name] = self.file.Layers.Add(layer)
        return self._layers[name]

    def _attributes(self, layer: str, name: str) -> rhino3dm.ObjectAttributes:
        attrs = rhino3dm.ObjectAttributes()
        attrs.LayerIndex = self.layer(layer)
        attrs.Name = name
        key, k = f"{layer}/{name}", 0
        while key in self._ids:  # same name twice on a layer: still unique ids
            k += 1
            key = f"{layer}/{name}#{k}"
        self._ids.add(key)
        attrs.Id = str(uuid.uuid5(ID_NAMESPACE, "object/" + key))
        return attrs

    def mesh(self, layer: str, name: str, vertices, quads) -> None:
        mesh = rhino3dm.Mesh()
        points = np.asarray(vertices, float).reshape(-1, 3).tolist()
        for x, y, z in points:
            mesh.Vertices.Add(x, y, z)
        # Add stores floats; switch to double precision, then set each vertex exactly.
        mesh.Vertices.UseDoublePrecisionVertices = True
        for i, (x, y, z) in enumerate(points):
            mesh.Vertices.SetPoint3dAt(i, rhino3dm.Point3d(x, y, z))
        for a, b, c, d in np.asarray(quads, int).reshape(-1, 4).tolist():
            mesh.Faces.AddFace(a, b, c, d)
        self.file.Objects.AddMesh(mesh, self._attributes(layer, name))

    def polyline(self, layer: str, name: str, points, *, closed: bool = False) -> None:
        pts = _xyz(points)
        polyline = rhino3dm.Polyline(len(pts) + int(closed))
        for x, y, z in pts.tolist():
            polyline.Add(x, y, z)
        if closed:
            polyline.Add(*pts[0].tolist())
        self.file.Objects.AddPolyline(polyline, self._attributes(layer, name))

    def dot(self, layer: str, name: str, text: str, point) -> None:
        x, y, z = _xyz(np.asarray(point, float).reshape(1, -1))[0].tolist()
        self.file.Objects.AddTextDot(text, rhino3dm.Point3d(x, y, z), self._attributes(layer, name))

    def to_bytes(self) -> bytes:
        """The .3dm bytes (rhino3dm writes to a path only: a temp file, read back)."""
        with tempfile.TemporaryDirectory(prefix="dgpc-3dm-") as tmp:
            path = Path(tmp) / "model.3dm"
            if not self.file.Write(str(path), ARCHIVE_VERSION):
                raise DgpcError("rhino3dm could not write the model", source=path)
            return path.read_bytes()


def _xyz(points) -> np.ndarray:
    """``(k, 3)`` float points; 2-D points get z = 0."""
    pts = np.asarray(points, float)
    if pts.shape[-1] == 2:
        pts = np.concatenate([pts, np.zeros((*pts.shape[:-1], 1))], axis=-1)
    return pts.reshape(-1, 3)


def net_model(f: np.ndarray, scale: float = 1.0) -> Model:
    """A net ``f (m, n, 3)``: the quad mesh and the n u-line geodesics."""
    model = Model()
    f = scale * np.asarray(f, float)
    m, n = f.shape[:2]
    model.mesh("net", "net", f, net_quads(m, n))
    width = max(2, len(str(n - 1)))
    for v in range(n):
        model.polyline("geodesics", f"u-v{v:0{width}d}", f[:, v])
    return model


def strips_model(strips: list[tuple[str, np.ndarray, np.ndarray]], scale: float = 1.0) -> Model:
    """Strips ``(id, A (m, 3), B (m, 3))``: one quad mesh each, vertices A_0 B_0 A_1 B_1 …"""
    model = Model()
    for sid, A, B in strips:
        grid = scale * np.stack([_xyz(A), _xyz(B)], axis=1).reshape(-1, 3)
        a = 2 * np.arange(len(A))
        quads = np.stack([a[:-1], a[1:], a[1:] + 1, a[:-1] + 1], axis=-1)
        model.mesh("strips", sid, grid, quads)
    return model


def _add_part(model: Model, layer: str, score_layer: str, label_layer: str, part: dict,
              place) -> None:
    pid = part["id"]
    model.polyline(layer, pid, place(part["outline"]), closed=True)
    for line in part["score"]:
        model.polyline(score_layer, f"{pid}/score", place(line))
    model.dot(label_layer, f"{pid}/label", pid, place(np.reshape(part["label"], (1, 2))))


def flat_model(parts: list[dict], scale: float = 1.0) -> Model:
    """Flat parts (records of the flat artifact): outlines, score lines, label dots (z = 0)."""
    model = Model()
    for part in parts:
        _add_part(model, "flat-parts", "score", "labels", part,
                  lambda p: scale * np.asarray(p, float))
    return model


def sheets_model(data: dict, parts: list[dict]) -> Model:
    """Sheets (``data`` of the sheets artifact) with the flat ``parts`` they place, in mm."""
    from dgpc_cli.nesting.geometry import transform  # shapely-heavy module, import on use

    model = Model()
    by_id = {p["id"]: p for p in parts}
    W, H = float(data["sheet"]["width"]), float(data["sheet"]["height"])
    k = float(data["sheet"]["mm_per_unit"])
    for sheet in data["sheets"]:
        s = int(sheet["index"])
        layer = f"sheet{s + 1:02d}"
        dx = np.array([s * (1.0 + SHEET_GAP) * W, 0.0])
        model.polyline(layer, sheet["id"],
                       np.array([[0.0, 0.0], [W, 0.0], [W, H], [0.0, H]]) + dx, closed=True)
        for pl in data["placements"]:
            if pl["sheet"] != s:
                continue
            if pl["part"] not in by_id:
                raise DgpcError(f"placed part {pl['part']} is not among the flat parts")
            _add_part(model, layer, layer, layer, by_id[pl["part"]],
                      lambda p, pl=pl, dx=dx: transform(k * np.asarray(p, float),
                                                        pl["rotation"], pl["translation"]) + dx)
    return model


def laths_model(laths: list[tuple[str, str, np.ndarray]], scale: float = 1.0) -> Model:
    """Laths ``(id, family, points (k, 3))`` as polylines on layers ``laths-<family>``."""
    model = Model()
    for lid, family, points in laths:
        model.polyline(f"laths-{family}", lid, scale * np.asarray(points, float))
    return model


def parse_obj_objects(data: bytes) -> list[tuple[str, np.ndarray, list, list]]:
    """The objects of an OBJ as ``(name, vertices (k, 3), faces, lines)`` with 0-based
    indices local to the object (groups ``g`` are ignored)."""
    vertices: list[tuple[float, float, float]] = []
    objects: list[tuple[str, int, list, list]] = []
    for raw in data.decode("ascii").splitlines():
        tok = raw.split()
        if not tok:
            continue
        if tok[0] == "o":
            objects.append((" ".join(tok[1:]), len(vertices), [], []))
        elif tok[0] == "v":
            vertices.append((float(tok[1]), float(tok[2]), float(tok[3])))
        elif tok[0] in ("f", "l") and objects:
            idx = [int(t.split("/")[0]) - 1 for t in tok[1:]]
            objects[-1][2 if tok[0] == "f" else 3].append(idx)
    out = []
    ends = [start for _, start, _, _ in objects[1:]] + [len(vertices)]
    for (name, start, faces, lines), end in zip(objects, ends, strict=True):
        out.append((name, np.array(vertices[start:end], float).reshape(-1, 3),
                    [[i - start for i in f] for f in faces], [[i - start for i in ln]
                                                               for ln in lines]))
    return out


def mold_model(obj: bytes, scale: float) -> Model:
    """The mold OBJ's objects ``surface`` and ``sector`` as quad meshes, scaled to mm."""
    model = Model()
    for name, vertices, faces, _ in parse_obj_objects(obj):
        model.mesh(f"mold-{name}", name, scale * vertices, faces)
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
        return net_model(parse_net_obj(obj, m, n, obj_path))
    if kind == "strips":
        geometry = parse_parts_obj(obj, [r["rows"] for r in data["strips"]], obj_path)
        return strips_model([(r["id"], A, B) for r, (A, B) in
                             zip(data["strips"], geometry, strict=True)])
    if kind == "flat":
        return flat_model(data["parts"])
    if kind == "sheets":
        if parts is None:
            raise DgpcError("3dm of sheets needs the flat parts", source=json_path)
        return sheets_model(data, parts)
    if kind == "laths":
        n_a = int(data["laths"]["A"])
        objs = parse_obj_objects(obj)
        return laths_model([(name, "A" if i < n_a else "B", v)
                            for i, (name, v, _, _) in enumerate(objs)])
    if kind == "mold":
        return mold_model(obj, UNIT_MM[data["unit"]])
    raise DgpcError(f"no 3dm export for a '{kind}' artifact", source=json_path)


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
