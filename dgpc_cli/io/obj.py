"""The net as an OBJ file (SPEC §3): m×n vertices in row-major order, quads between them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import DgpcError


def net_quads(m: int, n: int) -> np.ndarray:
    """0-based quads ``(m-1)(n-1), 4``: vertices (u,v), (u+1,v), (u+1,v+1), (u,v+1)."""
    vid = np.arange(m * n).reshape(m, n)
    quads = np.stack([vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]], axis=-1)
    return quads.reshape(-1, 4)


def format_net_obj(f: np.ndarray) -> bytes:
    """OBJ bytes of a net ``f (m, n, 3)``: vertex ``u*n+v+1`` is f(u, v), floats as ``repr``
    (shortest round-trip, so exact and deterministic), no timestamps."""
    f = np.asarray(f, dtype=np.float64)
    if f.ndim != 3 or f.shape[2] != 3:
        raise ValueError(f"a net is an (m, n, 3) array, got shape {f.shape}")
    m, n = f.shape[:2]
    lines = [f"# dgpc {__version__}", f"# net {m} x {n}, vertex u*n+v+1 is f(u, v)", "o net"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in f.reshape(-1, 3).tolist()]
    lines += [f"f {a} {b} {c} {d}" for a, b, c, d in (net_quads(m, n) + 1).tolist()]
    return ("\n".join(lines) + "\n").encode("ascii")


def _vertex_rows(data: bytes, source) -> list[tuple[float, float, float]]:
    rows = []
    for lineno, raw in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
        parts = raw.split()
        if not parts or parts[0] != "v":
            continue
        if len(parts) < 4:
            raise DgpcError(f"line {lineno}: vertex needs 3 coordinates, got {len(parts) - 1}",
                            source=source)
        try:
            rows.append((float(parts[1]), float(parts[2]), float(parts[3])))
        except ValueError:
            raise DgpcError(f"line {lineno}: not a number in vertex line {raw.strip()[:60]!r}",
                            source=source) from None
    return rows


def parse_net_obj(data: bytes, m: int, n: int, source: str | Path) -> np.ndarray:
    """Net ``(m, n, 3)`` from OBJ bytes whose ``v`` lines number exactly ``m*n`` (row-major).

    Other lines (vt, vn, f, comments, ...) and extra vertex columns (w, colours) are ignored.
    Errors are DgpcErrors naming ``source``: no vertices, a count other than m×n, an
    unparsable number (with its line), a non-finite coordinate (with its vertex and (u, v)).
    """
    rows = _vertex_rows(data, source)
    if not rows:
        raise DgpcError("no vertices ('v' lines) in the OBJ", source=source)
    if len(rows) != m * n:
        raise DgpcError(f"{len(rows)} vertices, but the net is {m} x {n} = {m * n}",
                        source=source)
    f = np.array(rows, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(f).all(axis=1))
    if bad.size:
        k = int(bad[0])
        raise DgpcError(f"vertex {k + 1} (u, v) = ({k // n}, {k % n}) has a non-finite "
                        f"coordinate {f[k].tolist()}", source=source)
    return f.reshape(m, n, 3)
