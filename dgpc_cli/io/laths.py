"""Gridshell laths on disk (paper §6.2.1, SPEC §3): ``STEM.obj`` with one OBJ polyline object
per lath, ``STEM.csv`` the cut list, ``STEM.json`` the envelope listing both files."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import DgpcError
from .artifact import artifact_paths, dumps_json, make_envelope, sha256_bytes, validate_envelope

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


def laths_files(stem: str | Path, laths, crossings, *, inputs: dict, parameters: dict,
                metrics: dict) -> dict[Path, bytes]:
    """The bytes of ``STEM.json``, ``STEM.obj`` and ``STEM.csv`` (nothing written)."""
    json_path, obj_path = artifact_paths(stem)
    csv_path = json_path.with_suffix(".csv")
    obj_bytes = format_laths_obj(laths)
    csv_bytes = format_cut_list(laths, crossings)
    data = {"obj": obj_path.name, "obj_sha256": sha256_bytes(obj_bytes),
            "cut_list": csv_path.name, "cut_list_sha256": sha256_bytes(csv_bytes),
            "laths": {"A": sum(lt.family == "A" for lt in laths),
                      "B": sum(lt.family == "B" for lt in laths)},
            "crossings": int(len(crossings.a))}
    doc = make_envelope(KIND, inputs=inputs, parameters=parameters, data=data, metrics=metrics,
                        status={"state": "ok"})
    json_bytes = dumps_json(doc)
    validate_envelope(json.loads(json_bytes), KIND, json_path)
    return {json_path: json_bytes, obj_path: obj_bytes, csv_path: csv_bytes}


def read_cut_list(path: str | Path) -> list[dict]:
    """Rows of a cut list CSV: ``lath_id``, ``family``, ``length`` (float), ``crossings``
    (list of floats), ``crossing_laths`` (list of ids)."""
    text = Path(path).read_text(encoding="ascii").splitlines()
    if not text or tuple(text[0].split(",")) != CSV_HEADER:
        raise DgpcError("not a dgpc cut list (header)", source=path)
    rows = []
    for line in text[1:]:
        lid, fam, length, _, xs, ids = line.split(",")
        rows.append({"lath_id": lid, "family": fam, "length": float(length),
                     "crossings": [float(x) for x in xs.split(";") if x],
                     "crossing_laths": [i for i in ids.split(";") if i]})
    return rows


def read_polylines(path: str | Path) -> dict[str, np.ndarray]:
    """The polylines of a laths OBJ by object name, ``(k, 3)`` each."""
    verts, out, name = [], {}, None
    for raw in Path(path).read_text(encoding="ascii").splitlines():
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
