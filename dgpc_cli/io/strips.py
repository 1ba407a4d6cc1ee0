"""The ``strips`` artifact (SPEC §3, §6 planarize-strips): STEM.json + STEM.obj.

The OBJ holds one object per strip (``o S-v07``) with its 2m vertices in the order
A_0 B_0 A_1 B_1 … (A on the geodesic v, B on v+1), the planar quads A_u A_(u+1) B_(u+1) B_u and
the rulings A_u B_u as lines. The JSON ``data.strips`` lists the strips in the OBJ's order with
what the OBJ cannot hold (quality, ruling directions, flat rows, polish outcome, and for a
shared-outline template the ``cut_edges``: the template's outline curves sampled in the strip's
``(t, s)``, identical for every strip, which ``unfold`` cuts along; older files without them
are cut along A and B).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import DgpcError
from .artifact import (
    artifact_files,
    artifact_paths,
    listed_file,
    load_envelope,
    read_listed,
    reread,
)
from .obj import _vertex_rows, check_obj_objects, parse_obj
from .units import DEFAULT_UNITS, stored

KIND = "strips"


def format_parts_obj(title: str, parts: list[tuple[str, np.ndarray, np.ndarray]],
                     outlines: dict | None = None) -> bytes:
    """OBJ bytes of quad strips ``(name, A (m, d), B (m, d))`` (d = 2 gives z = 0): one object
    per strip, vertices A_0 B_0 A_1 B_1 …, quads A_u A_(u+1) B_(u+1) B_u, lines A_u B_u.
    A part named in ``outlines`` (``name → (outline (k, 2), score lines)``, a strip trimmed to
    the reference's outline) is drawn as its closed outline and its score lines instead.
    Floats as ``repr`` (exact, deterministic)."""
    lines = [f"# dgpc {__version__}", f"# {title}",
             "# per object: vertices A_0 B_0 A_1 B_1 ..., quads A_u A_u+1 B_u+1 B_u, "
             "lines A_u B_u (a trimmed part: its outline and score lines)"]
    base = 1
    outlines = outlines or {}
    for name, A, B in parts:
        if name in outlines:
            outline, score = outlines[name]
            pts = [np.asarray(outline, float)] + [np.asarray(s, float) for s in score]
            lines.append(f"o {name}")
            for p in pts:
                lines += [f"v {x!r} {y!r} 0.0" for x, y in p.tolist()]
            k = len(pts[0])
            lines.append("l " + " ".join(str(base + i) for i in [*range(k), 0]))
            start = base + k
            for p in pts[1:]:
                lines.append("l " + " ".join(str(start + i) for i in range(len(p))))
                start += len(p)
            base = start
            continue
        grid = np.stack([A, B], axis=1).reshape(-1, A.shape[1])
        if grid.shape[1] == 2:
            grid = np.concatenate([grid, np.zeros((len(grid), 1))], axis=1)
        m = A.shape[0]
        lines.append(f"o {name}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in grid.astype(float).tolist()]
        a = base + 2 * np.arange(m)
        lines += [f"f {p} {q} {r} {s}" for p, q, r, s in
                  np.stack([a[:-1], a[1:], a[1:] + 1, a[:-1] + 1], axis=-1).tolist()]
        lines += [f"l {p} {q}" for p, q in np.stack([a, a + 1], axis=-1).tolist()]
        base += 2 * m
    return ("\n".join(lines) + "\n").encode("ascii")


def parse_parts_obj(data: bytes, rows: list[int], source) -> list[tuple[np.ndarray, np.ndarray]]:
    """The strips ``(A, B)`` of an OBJ written by :func:`format_parts_obj` with ``rows[i]``
    rows each (vertex counts checked)."""
    vertices = np.array(_vertex_rows(data, source), dtype=float).reshape(-1, 3)
    expected = 2 * sum(rows)
    if len(vertices) != expected:
        raise DgpcError(f"{len(vertices)} vertices, but the JSON lists strips with {expected}",
                        source=source)
    if not np.isfinite(vertices).all():
        raise DgpcError("non-finite vertex coordinate", source=source)
    out, start = [], 0
    for m in rows:
        grid = vertices[start:start + 2 * m].reshape(m, 2, 3)
        out.append((grid[:, 0], grid[:, 1]))
        start += 2 * m
    return out


def read_obj_checked(json_path: Path, obj_path: Path, sha256: str) -> bytes:
    """The bytes of an artifact's OBJ, checked against the hash its JSON records."""
    return read_listed(obj_path, sha256, json_path, "data.obj_sha256")


@dataclass
class StripsArtifact:
    """Planar-quad strips: ``geometry[i] = (A, B)`` with ``A, B (m, 3)`` in ``units`` and the
    JSON record ``records[i]`` (``id``, ``v``, ``rows``, quality, rulings), plus the envelope
    fields; ``template`` the one template all strips bend from (variant, start, fit outcome,
    its 2-D boundaries ``A, B (m, 2)`` in ``units``), None for strips planarized one by one."""

    geometry: list
    records: list
    source_shape: tuple
    units: str = DEFAULT_UNITS
    parameters: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    status: dict = field(default_factory=dict)
    template: dict | None = None


def strips_files(stem: str | Path, art: StripsArtifact) -> dict[Path, bytes]:
    """The bytes of ``STEM.json`` and ``STEM.obj`` (nothing written), schema-checked."""
    ids = [r["id"] for r in art.records]
    obj_bytes = format_parts_obj(f"strips of planar quads ({len(ids)})",
                                 [(i, stored(A, art.units), stored(B, art.units))
                                  for i, (A, B) in zip(ids, art.geometry, strict=True)])
    data = {"source_shape": list(art.source_shape), "geodesic_family": "u",
            "units": art.units, "strips": art.records}
    if art.template is not None:
        data["template"] = art.template
    return artifact_files(KIND, stem, obj_bytes, data, inputs=art.inputs,
                          parameters=art.parameters, metrics=art.metrics, status=art.status)


def _check_cut_edges(records: list[dict], json_path: Path) -> None:
    """Every strip's cut-edge samples (``cut_edges``, a shared-outline template's curves in the
    strip's ``(t, s)``) finite and strictly between its end rows; DgpcError naming the first
    one that is not."""
    for i, r in enumerate(records):
        for side in ("A", "B") if "cut_edges" in r else ():
            ts = np.asarray(r["cut_edges"][side], float).reshape(-1, 2)
            bad = np.nonzero(~np.isfinite(ts).all(axis=1) | (ts[:, 0] <= 0)
                             | (ts[:, 0] >= r["rows"] - 1))[0]
            if bad.size:
                raise DgpcError(f"data.strips[{i}].cut_edges.{side}[{int(bad[0])}]: t must lie "
                                f"strictly between 0 and {r['rows'] - 1} (the end rows)",
                                source=json_path)


@reread
def read_strips(stem: str | Path) -> StripsArtifact:
    """Read and validate a strips artifact (envelope, schema, OBJ hash and vertex counts)."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    obj_path = listed_file(data["obj"], json_path, "data.obj")
    obj_bytes = read_obj_checked(json_path, obj_path, data["obj_sha256"])
    records = data["strips"]
    check_obj_objects(parse_obj(obj_bytes, obj_path), [(r["id"], 2 * r["rows"]) for r in records],
                      obj_path, "data.strips")
    geometry = parse_parts_obj(obj_bytes, [r["rows"] for r in records], obj_path)
    _check_cut_edges(records, json_path)
    return StripsArtifact(geometry=geometry, records=records,
                          source_shape=tuple(data["source_shape"]), units=data["units"],
                          parameters=doc["parameters"], inputs=doc["inputs"],
                          metrics=doc["metrics"], status=doc["status"],
                          template=data.get("template"))
