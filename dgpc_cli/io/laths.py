"""Gridshell laths on disk (paper §6.2.1, SPEC §3): ``STEM.obj`` with one OBJ polyline object
per lath, ``STEM.csv`` the cut list, ``STEM.json`` the envelope listing both files."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import DgpcError
from .artifact import (
    artifact_paths,
    dumps_json,
    listed_file,
    listed_path,
    load_envelope,
    make_envelope,
    read_listed,
    reread,
    sha256_bytes,
    validate_envelope,
)
from .obj import parse_obj

KIND = "laths"
CSV_HEADER = ("lath_id", "family", "length", "n_crossings", "crossings", "crossing_laths")


def format_laths_obj(laths) -> bytes:
    """OBJ bytes: per lath an object ``o <id>`` with its vertices and one ``l`` polyline;
    floats as ``repr`` (exact round trip, so lengths recomputed from the file are the cut
    list's)."""
    lines = [f"# dgpc {__version__}", f"# {len(laths)} laths (u-line geodesics), polylines"]
    base = 1
    for lath in laths:
        lines.append(f"o {lath.id}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in lath.points.tolist()]
        k = len(lath.points)
        lines.append("l " + " ".join(str(base + i) for i in range(k)))
        base += k
    return ("\n".join(lines) + "\n").encode("ascii")


def format_cut_list(laths, crossings) -> bytes:
    """CSV bytes of the cut list: one row per lath with its length and the arc-length positions
    of its crossings with the other family (``;``-separated, increasing) and the ids of the
    crossing laths in the same order. Floats as ``repr``."""
    by_lath: dict[str, list[tuple[float, str]]] = {lt.id: [] for lt in laths}
    ids_a = [lt.id for lt in laths if lt.family == "A"]
    ids_b = [lt.id for lt in laths if lt.family == "B"]
    for a, b, sa, sb in zip(crossings.a.tolist(), crossings.b.tolist(), crossings.s_a.tolist(),
                            crossings.s_b.tolist(), strict=True):
        by_lath[ids_a[a]].append((sa, ids_b[b]))
        by_lath[ids_b[b]].append((sb, ids_a[a]))
    rows = [",".join(CSV_HEADER)]
    for lt in laths:
        hits = sorted(by_lath[lt.id])
        rows.append(",".join([lt.id, lt.family, repr(lt.length), str(len(hits)),
                              ";".join(repr(s) for s, _ in hits),
                              ";".join(o for _, o in hits)]))
    return ("\n".join(rows) + "\n").encode("ascii")


def laths_files(stem: str | Path, laths, crossings, *, units: str, inputs: dict,
                parameters: dict, metrics: dict, status: dict | None = None
                ) -> dict[Path, bytes]:
    """The bytes of ``STEM.json``, ``STEM.obj`` and ``STEM.csv`` (nothing written); lengths in
    the nets' ``units``."""
    json_path, obj_path = artifact_paths(stem)
    csv_path = json_path.with_suffix(".csv")
    obj_bytes = format_laths_obj(laths)
    csv_bytes = format_cut_list(laths, crossings)
    data = {"units": units, "obj": obj_path.name, "obj_sha256": sha256_bytes(obj_bytes),
            "cut_list": csv_path.name, "cut_list_sha256": sha256_bytes(csv_bytes),
            "laths": {"A": sum(lt.family == "A" for lt in laths),
                      "B": sum(lt.family == "B" for lt in laths)},
            "crossings": int(len(crossings.a))}
    doc = make_envelope(KIND, inputs=inputs, parameters=parameters, data=data, metrics=metrics,
                        status={"state": "ok", **(status or {})})
    json_bytes = dumps_json(doc)
    validate_envelope(json.loads(json_bytes), KIND, json_path)
    return {json_path: json_bytes, obj_path: obj_bytes, csv_path: csv_bytes}


def read_cut_list(path: str | Path) -> list[dict]:
    """Rows of a cut list CSV: ``lath_id``, ``family``, ``length`` (float), ``crossings``
    (list of floats), ``crossing_laths`` (list of ids)."""
    return parse_cut_list(Path(path).read_text(encoding="ascii"), path)


def parse_cut_list(text: str, source) -> list[dict]:
    """:func:`read_cut_list` on the CSV's text; DgpcError naming ``source`` when malformed."""
    lines = text.splitlines()
    if not lines or tuple(lines[0].split(",")) != CSV_HEADER:
        raise DgpcError("not a dgpc cut list (header)", source=source)
    rows = []
    for k, line in enumerate(lines[1:], start=2):
        try:
            lid, fam, length, _, xs, ids = line.split(",")
            rows.append({"lath_id": lid, "family": fam, "length": float(length),
                         "crossings": [float(x) for x in xs.split(";") if x],
                         "crossing_laths": [i for i in ids.split(";") if i]})
        except ValueError:
            raise DgpcError(f"line {k} is not a cut-list row", source=source) from None
        if not np.isfinite([rows[-1]["length"], *rows[-1]["crossings"]]).all():
            raise DgpcError(f"line {k}: a non-finite length or crossing", source=source)
    return rows


def read_polylines(path: str | Path) -> dict[str, np.ndarray]:
    """The polylines of a laths OBJ by object name, ``(k, 3)`` each."""
    return parse_polylines(Path(path).read_text(encoding="ascii"))


def parse_polylines(text: str) -> dict[str, np.ndarray]:
    """:func:`read_polylines` on the OBJ's text."""
    verts, out, name = [], {}, None
    for raw in text.splitlines():
        parts = raw.split()
        if not parts:
            continue
        if parts[0] == "o":
            name = parts[1]
        elif parts[0] == "v":
            verts.append([float(p) for p in parts[1:4]])
        elif parts[0] == "l":
            out[name] = np.asarray(verts, float)[[int(i) - 1 for i in parts[1:]]]
    return out


@dataclass
class LathsArtifact:
    """The laths of a gridshell: ``polylines`` by lath id (``(k, 3)`` each, family A then B),
    the cut-list ``rows`` (see :func:`read_cut_list`) and the envelope fields."""

    polylines: dict
    rows: list
    data: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    status: dict = field(default_factory=dict)

    def family(self, name: str) -> list[np.ndarray]:
        """The polylines of family ``name`` ("A" or "B") in cut-list order."""
        return [self.polylines[r["lath_id"]] for r in self.rows if r["family"] == name]


@reread
def read_laths(stem: str | Path) -> LathsArtifact:
    """Read and validate a laths artifact: envelope, schema, the OBJ's and the cut list's
    hashes, and that both list the same laths in the counts the JSON records."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    obj_path = listed_file(data["obj"], json_path, "data.obj")
    obj = read_listed(obj_path, data["obj_sha256"], json_path, "data.obj_sha256")
    csv_path = listed_path(data["cut_list"], json_path, "data.cut_list")
    csv = read_listed(csv_path, data["cut_list_sha256"], json_path, "data.cut_list_sha256")
    objects = parse_obj(obj, obj_path).objects  # text, finite, lines join existing vertices
    polylines = parse_polylines(obj.decode("utf-8"))
    for o in objects:
        if o.lines != 1 or o.vertices != len(polylines.get(o.name, ())):
            raise DgpcError(f"object {o.name!r}: {o.vertices} vertices and {o.lines} polylines, "
                            "expected one polyline through all of them", source=obj_path)
    try:
        rows = parse_cut_list(csv.decode("ascii"), csv_path)
    except UnicodeDecodeError:
        raise DgpcError("not a dgpc cut list (not text)", source=csv_path) from None
    counts = {f: sum(r["family"] == f for r in rows) for f in ("A", "B")}
    if [r["lath_id"] for r in rows] != list(polylines) or counts != data["laths"]:
        raise DgpcError(f"the cut list, the OBJ and data.laths {data['laths']} do not list the "
                        "same laths", source=json_path)
    return LathsArtifact(polylines=polylines, rows=rows, data=data, inputs=doc["inputs"],
                         metrics=doc["metrics"], status=doc["status"])
