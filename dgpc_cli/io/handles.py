"""Handles file: net vertices pulled to target points (``{"handles": [...]}``, SPEC §4)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .coordinates import bad_rows, coordinate_problem
from .jsonable import load_schema, read_json, validate


def read_handles(path: str | Path, shape: tuple[int, int], f: np.ndarray, scale: float = 1.0
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Vertex ids ``(l,)`` int64 (``u*n+v``) and targets ``(l, 3)`` of a handles file.

    Each entry is ``{"index": [u, v], "target": [x, y, z]}`` or ``{"index": [u, v],
    "offset": [dx, dy, dz]}`` (target = ``f[u, v] + offset``; ``f`` is the net ``(m, n, 3)``).
    The file's numbers are multiplied by ``scale`` first (the net's unit to the mm of ``f``).
    DgpcError (one line naming the file and entry, e.g. ``handles[2].index``): missing or
    invalid JSON, schema violation, both or neither of target/offset, an index outside the
    m×n grid, a non-finite number, the same vertex twice, no handles.
    """
    path = Path(path)
    m, n = (int(s) for s in shape)
    f = np.asarray(f, dtype=np.float64).reshape(m, n, 3)
    doc = read_json(path)
    validate(doc, load_schema("handles"), path)
    entries = doc["handles"]
    ids = np.empty(len(entries), dtype=np.int64)
    targets = np.empty((len(entries), 3), dtype=np.float64)
    first: dict[int, int] = {}
    for k, entry in enumerate(entries):
        u, v = (int(i) for i in entry["index"])
        if u >= m or v >= n:
            raise DgpcError(f"handles[{k}].index: ({u}, {v}) is outside the {m} x {n} grid",
                            source=path)
        key = "target" if "target" in entry else "offset"
        vec = np.asarray(entry[key], dtype=np.float64)
        if bad_rows(vec[None]).size:
            raise DgpcError(f"handles[{k}].{key}: {coordinate_problem(vec)}", source=path)
        vec = vec * scale
        vid = u * n + v
        if vid in first:
            raise DgpcError(f"handles[{k}].index: vertex ({u}, {v}) is already a handle in "
                            f"handles[{first[vid]}]", source=path)
        first[vid] = k
        ids[k] = vid
        targets[k] = vec if key == "target" else f[u, v] + vec
    if not np.isfinite(targets).all():
        k = int(np.flatnonzero(~np.isfinite(targets).all(axis=1))[0])
        raise DgpcError(f"handles[{k}].offset: the net vertex it moves is not finite",
                        source=path)
    return ids, targets


def handles_bytes(ids: np.ndarray, n: int, targets: np.ndarray) -> bytes:
    """A handles file (what :func:`read_handles` reads) holding the vertices ``ids`` (``u*n+v``)
    at ``targets (l, 3)`` in the net's unit; the numbers round-trip exactly."""
    entries = [{"index": [int(i) // n, int(i) % n], "target": [float(t) for t in target]}
               for i, target in zip(ids, np.asarray(targets, dtype=float), strict=True)]
    return (json.dumps({"handles": entries}, indent=1) + "\n").encode()
