"""The net as an OBJ file (SPEC §3): m×n vertices in row-major order, quads between them."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import DgpcError
from .coordinates import bad_rows, coordinate_problem


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


def count_lines(data: bytes, keyword: bytes) -> int:
    """How many lines of OBJ bytes start with ``keyword`` (after blanks), as a parser that
    splits lines at ``\n``, ``\r`` or both would see them; counted before anything is parsed
    (the size guards)."""
    pattern = re.compile(rb"(?:^|[\r\n])[ \t]*" + re.escape(keyword) + rb"[ \t]")
    return sum(1 for _ in pattern.finditer(data))


def parse_net_obj(data: bytes, m: int, n: int, source: str | Path) -> np.ndarray:
    """Net ``(m, n, 3)`` from OBJ bytes whose ``v`` lines number exactly ``m*n`` (row-major).

    Other lines (vt, vn, f, comments, ...) and extra vertex columns (w, colours) are ignored.
    Errors are DgpcErrors naming ``source``: no vertices, a count other than m×n, an
    unparsable number (with its line), a non-finite coordinate (with its vertex and (u, v)).
    """
    counted = count_lines(data, b"v")
    if counted > m * n:                 # refused before a long file is parsed
        raise DgpcError(f"{counted} vertices, but the net is {m} x {n} = {m * n}",
                        source=source)
    rows = _vertex_rows(data, source)
    if not rows:
        raise DgpcError("no vertices ('v' lines) in the OBJ", source=source)
    if len(rows) != m * n:
        raise DgpcError(f"{len(rows)} vertices, but the net is {m} x {n} = {m * n}",
                        source=source)
    f = np.array(rows, dtype=np.float64)
    bad = bad_rows(f)
    if bad.size:
        k = int(bad[0])
        raise DgpcError(f"vertex {k + 1} (u, v) = ({k // n}, {k % n}) has "
                        f"{coordinate_problem(f[k])}: {f[k].tolist()}", source=source)
    return f.reshape(m, n, 3)


_FACE = re.compile(rb"^[ \t]*f[ \t]+([^\r\n]*)", re.MULTILINE)


def check_net_faces(data: bytes, m: int, n: int, source: str | Path) -> None:
    """The faces of a net's OBJ are exactly the m×n grid's quads (:func:`net_quads`, in that
    order): a face naming a vertex the net does not have, or a grid of another shape (a
    ``data.shape`` of [7, 9] on a 9×7 net, whose vertex count agrees), is a DgpcError naming
    ``source``."""
    faces = []
    for k, match in enumerate(_FACE.finditer(data), 1):
        try:
            faces.append([int(token.split(b"/")[0]) for token in match.group(1).split()])
        except ValueError:
            raise DgpcError(f"face {k}: not vertex numbers: {match.group(0)[:60]!r}",
                            source=source) from None
        bad = [i for i in faces[-1] if not 1 <= i <= m * n]
        if bad:
            raise DgpcError(f"face {k} names vertex {bad[0]}, but the net has {m * n} "
                            f"({m} x {n})", source=source)
    expected = net_quads(m, n) + 1
    if len(faces) != len(expected) or any(len(face) != 4 for face in faces) \
            or not np.array_equal(np.array(faces, dtype=np.int64), expected):
        raise DgpcError(f"its {len(faces)} faces are not the quads of a {m} x {n} net "
                        "(does data.shape match the OBJ?)", source=source)


@dataclass
class ObjObject:
    """One ``o`` object of an OBJ: its name, vertex count, ``g`` groups (in order) and how many
    faces and polylines it has."""

    name: str | None
    vertices: int = 0
    groups: list[str] = field(default_factory=list)
    faces: int = 0
    lines: int = 0


@dataclass
class ObjContents:
    """What an artifact's OBJ holds: every vertex ``(k, 3)`` and its objects in file order
    (vertices before the first ``o`` belong to an object named None)."""

    vertices: np.ndarray
    objects: list[ObjObject]

    def names(self) -> list[str | None]:
        return [o.name for o in self.objects]

    def object_vertices(self, k: int) -> np.ndarray:
        """The vertices of object ``k`` (objects hold consecutive vertices)."""
        start = sum(o.vertices for o in self.objects[:k])
        return self.vertices[start:start + self.objects[k].vertices]


#: Statements of the OBJ format that the artifacts' OBJs may carry and that are skipped.
_SKIPPED = {"vt", "vn", "vp", "s", "usemtl", "mtllib", "cstype", "deg", "mg"}


def parse_obj(data: bytes, source: str | Path) -> ObjContents:
    """Parse the OBJ of an artifact (written by dgpc: ``v``, ``o``, ``g``, ``f``, ``l``).

    DgpcError naming ``source`` (and the line) for anything else: not text, an unknown
    statement, a vertex without 3 numbers or with a non-finite one, a face or line that refers
    to a vertex not defined before it (negative, relative indices included), a vertex that no
    face or line uses (dgpc's OBJs use each)."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise DgpcError("not an OBJ file (binary data, not text)", source=source) from None
    if "\0" in text:
        raise DgpcError("not an OBJ file (binary data, not text)", source=source)
    rows: list[tuple[float, float, float]] = []
    lines_of: list[int] = []
    objects = [ObjObject(None)]
    used: set[int] = set()
    for lineno, raw in enumerate(text.splitlines(), 1):
        parts = raw.split()
        if not parts or parts[0].startswith("#"):
            continue
        key = parts[0]
        if key == "v":
            try:
                rows.append((float(parts[1]), float(parts[2]), float(parts[3])))
            except (ValueError, IndexError):
                raise DgpcError(f"line {lineno}: a vertex needs 3 numbers, got "
                                f"{raw.strip()[:60]!r}", source=source) from None
            lines_of.append(lineno)
            objects[-1].vertices += 1
        elif key in ("f", "l"):
            try:
                idx = [int(p.split("/")[0]) for p in parts[1:]]
            except ValueError:
                raise DgpcError(f"line {lineno}: not vertex numbers in {raw.strip()[:60]!r}",
                                source=source) from None
            if len(idx) < (3 if key == "f" else 2) or not all(0 < i <= len(rows) for i in idx):
                raise DgpcError(f"line {lineno}: {'face' if key == 'f' else 'line'} "
                                f"{raw.strip()[:60]!r} does not join vertices defined before "
                                f"it ({len(rows)})", source=source)
            used.update(idx)
            if key == "f":
                objects[-1].faces += 1
            else:
                objects[-1].lines += 1
        elif key == "o":
            objects.append(ObjObject(" ".join(parts[1:])))
        elif key == "g":
            objects[-1].groups.append(" ".join(parts[1:]))
        elif key not in _SKIPPED:
            raise DgpcError(f"line {lineno}: not an OBJ statement: {raw.strip()[:40]!r}",
                            source=source)
    if objects[0].vertices == 0 and not objects[0].groups and len(objects) > 1:
        objects.pop(0)
    vertices = np.array(rows, dtype=np.float64).reshape(-1, 3)
    bad = bad_rows(vertices)
    if bad.size:
        k = int(bad[0])
        raise DgpcError(f"line {lines_of[k]}: vertex {k + 1} has "
                        f"{coordinate_problem(vertices[k])}", source=source)
    if len(used) != len(rows):
        k = min(set(range(1, len(rows) + 1)) - used)
        raise DgpcError(f"line {lines_of[k - 1]}: vertex {k} is used by no face or line",
                        source=source)
    return ObjContents(vertices=vertices, objects=objects)


def check_obj_objects(obj: ObjContents, expected: list[tuple[str, int | None]], source,
                      what: str) -> None:
    """The objects of ``obj`` are ``expected`` = ``[(name, vertex count or None), ...]`` in
    this order; DgpcError naming ``source`` and ``what`` (the JSON field they come from)."""
    names = obj.names()
    want = [n for n, _ in expected]
    if names != want:
        k = next((i for i, (a, b) in enumerate(zip(names, want, strict=False)) if a != b),
                 min(len(names), len(want)))
        got = names[k] if k < len(names) else "(none)"
        raise DgpcError(f"{len(names)} objects, {what} lists {len(want)}; object {k + 1} is "
                        f"{got!r}, expected {want[k] if k < len(want) else '(none)'!r}",
                        source=source)
    for o, (name, count) in zip(obj.objects, expected, strict=True):
        if count is not None and o.vertices != count:
            raise DgpcError(f"object {name!r} has {o.vertices} vertices, {what} implies "
                            f"{count}", source=source)
