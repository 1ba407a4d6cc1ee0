"""The ``mold`` artifact (SPEC §3, §6): STEM.json + STEM.obj + profile CSV/DXF + panel map CSV.

Files, all listed in ``data`` with their sha256:

* ``STEM.obj`` — object ``surface``: the discrete surface of revolution, m rows × one full turn
  (N segments; the last one partial when N is not an integer); object ``sector``: the mold
  sector, just wide enough for the widest panel, its faces grouped by mold piece (``g M01``,
  …, ``g no-mold`` for rows that need none);
* ``STEM.profile.csv`` — the meridian, header ``r,h``, in the nets' unit ``data.units`` (it
  reads back with ``dgpc init --profile FILE --units UNIT``);
* ``STEM.profile.dxf`` — the meridian in mm with the axis drawn (made by
  :mod:`dgpc_cli.mold.dxf`, handed in as bytes);
* ``STEM.panels.csv`` — the panel-to-mold map, one line per panel: its id, net, mold piece,
  integer vertex rows and columns, angles on the mold, isometry error and flat flag;
* ``STEM.panels.obj`` — the input nets (one object each, ``net1`` …) with their faces grouped
  by panel id (``g P-u03-v07``), so that a facade model shows which panel is which.

The JSON holds the profile (r, h, d, l, x), N and λ, the pieces and the panel-to-mold map.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import __version__
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
from .coordinates import bad_rows, coordinate_problem
from .obj import check_obj_objects, net_quads, parse_obj

KIND = "mold"
#: Extra files of a mold artifact: data.files key → suffix after the stem.
EXTRA_FILES = {"profile_csv": ".profile.csv", "profile_dxf": ".profile.dxf",
               "panels_csv": ".panels.csv", "panels_obj": ".panels.obj"}


def mold_paths(stem: str | Path) -> dict[str, Path]:
    """Every file of a mold artifact: ``json``, ``obj`` and the keys of :data:`EXTRA_FILES`."""
    json_path, obj_path = artifact_paths(stem)
    base = str(json_path)[: -len(".json")]
    return {"json": json_path, "obj": obj_path,
            **{key: Path(base + suffix) for key, suffix in EXTRA_FILES.items()}}


def _grid(r: np.ndarray, h: np.ndarray, phi: np.ndarray) -> np.ndarray:
    return np.stack([r[:, None] * np.cos(phi)[None, :], r[:, None] * np.sin(phi)[None, :],
                     np.broadcast_to(h[:, None], (r.size, phi.size))], axis=-1)


def surface_angles(segments: float) -> np.ndarray:
    """Column angles of the full turn: k·2π/N for k = 0 … ⌈N⌉, the last clipped to 2π."""
    count = max(1, math.ceil(segments - 1e-9))
    return np.minimum(np.arange(count + 1) * (2.0 * math.pi / segments), 2.0 * math.pi)


def sector_angles(sector: float, segments: float) -> np.ndarray:
    """Column angles of the sector [0, sector], steps of about 2π/N."""
    q = max(1, math.ceil(sector / (2.0 * math.pi / segments) - 1e-9))
    return np.linspace(0.0, sector, q + 1)


def format_mold_obj(r, h, segments: float, sector: float,
                    pieces: list[tuple[str, int, int]]) -> bytes:
    """OBJ bytes: objects ``surface`` and ``sector`` (faces of the sector grouped by piece).

    Vertices row-major per object, floats as ``repr``; no timestamps.
    """
    r, h = np.asarray(r, float), np.asarray(h, float)
    m = r.size
    surf = _grid(r, h, surface_angles(segments))
    sect = _grid(r, h, sector_angles(sector, segments))
    lines = [f"# dgpc {__version__}",
             f"# mold: surface of revolution about the z axis, {m} rows, N = {segments!r}",
             "o surface"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in surf.reshape(-1, 3).tolist()]
    lines += [f"f {a} {b} {c} {d}" for a, b, c, d in (net_quads(m, surf.shape[1]) + 1).tolist()]
    lines.append("o sector")
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in sect.reshape(-1, 3).tolist()]
    quads = (net_quads(m, sect.shape[1]) + 1 + surf.shape[0] * surf.shape[1]).reshape(
        m - 1, sect.shape[1] - 1, 4)
    covered = np.zeros(m - 1, dtype=bool)
    for pid, start, stop in pieces:
        lines.append(f"g {pid}")
        lines += [f"f {a} {b} {c} {d}" for a, b, c, d in quads[start:stop].reshape(-1, 4).tolist()]
        covered[start:stop] = True
    if not covered.all():
        lines.append("g no-mold")
        lines += [f"f {a} {b} {c} {d}" for a, b, c, d in quads[~covered].reshape(-1, 4).tolist()]
    return ("\n".join(lines) + "\n").encode("ascii")


def format_profile_csv(r, h) -> bytes:
    """``r,h`` CSV of the meridian (floats as ``repr``)."""
    lines = ["r,h"] + [f"{a!r},{b!r}" for a, b in zip(np.asarray(r, float).tolist(),
                                                      np.asarray(h, float).tolist(), strict=True)]
    return ("\n".join(lines) + "\n").encode("ascii")


PANEL_COLUMNS = ("id", "net", "piece", "row_start", "row_stop", "col_start", "col_stop",
                 "angle_start_deg", "angle_stop_deg", "isometry_error", "curvature_max", "flat")


def format_panels_csv(panels: list[dict]) -> bytes:
    """The panel-to-mold map as CSV, one line per panel (``piece`` empty for flat panels):
    net as ``net1`` …, integer rows and columns, angles to 1e-6 degrees, errors to 4 digits."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(PANEL_COLUMNS)
    for p in panels:
        curv = p["curvature_max"]
        writer.writerow([p["id"], f"net{int(p['net']) + 1}", p["piece"] or "",
                         *(int(i) for i in p["rows"]), *(int(i) for i in p["cols"]),
                         *(f"{float(a):.6f}" for a in p["angle_deg"]),
                         f"{float(p['isometry_error']):.4g}",
                         "" if curv is None else f"{float(curv):.4g}", int(p["flat"])])
    return out.getvalue().encode("ascii")


def format_panels_obj(nets: list[np.ndarray], panels: list[dict]) -> bytes:
    """OBJ bytes of the nets ``f (m, n, 3)`` (objects ``net1`` …, vertices row-major) with
    their quads grouped by panel (``g <panel id>``, the panels' order)."""
    lines = [f"# dgpc {__version__}", "# the input nets, faces grouped by panel id"]
    base = 1
    for k, f in enumerate(nets):
        f = np.asarray(f, float)
        m, n = f.shape[:2]
        quads = (net_quads(m, n) + base).reshape(m - 1, n - 1, 4)
        lines.append(f"o net{k + 1}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in f.reshape(-1, 3).tolist()]
        for p in (p for p in panels if p["net"] == k):
            (r0, r1), (c0, c1) = p["rows"], p["cols"]
            lines.append(f"g {p['id']}")
            lines += [f"f {a} {b} {c} {d}" for a, b, c, d in
                      quads[r0:r1, c0:c1].reshape(-1, 4).tolist()]
        base += m * n
    return ("\n".join(lines) + "\n").encode("ascii")


@dataclass
class MoldArtifact:
    """A mold artifact read back: the envelope fields (``data`` as in the JSON)."""

    parameters: dict
    inputs: dict
    data: dict
    metrics: dict
    status: dict

    @property
    def units(self) -> str:
        """The length unit of the profile and every length (the nets')."""
        return self.data["units"]

    @property
    def r(self) -> np.ndarray:
        return np.asarray(self.data["profile"]["r"], dtype=float)

    @property
    def h(self) -> np.ndarray:
        return np.asarray(self.data["profile"]["h"], dtype=float)


def mold_files(stem: str | Path, *, profile: dict, units: str, profile_dxf: bytes,
               segments: dict, sector_deg: float, pieces: list[dict], nets: list[dict],
               net_geometry: list[np.ndarray], panels: list[dict], panel_size: int,
               inputs: dict, parameters: dict, metrics: dict, status: dict
               ) -> dict[Path, bytes]:
    """The bytes of every file of the artifact (nothing written), the JSON checked against
    ``mold.schema.json``; to be written at once with :func:`~dgpc_cli.io.atomic.write_files`.

    ``profile`` has the arrays r, h (m,), x, l (m−1,), d (m,); ``segments`` the fields
    ``segments``, ``lambda``, ``lambda_lowered``, ``segments_requested``; ``pieces`` records
    ``{"id", "rows": [a, b], "meridian_length"}``.
    """
    paths = mold_paths(stem)
    folder = paths["json"].resolve().parent
    r, h = np.asarray(profile["r"], float), np.asarray(profile["h"], float)
    triples = [(p["id"], p["rows"][0], p["rows"][1]) for p in pieces]
    files = {
        "obj": format_mold_obj(r, h, segments["segments"], math.radians(sector_deg), triples),
        "profile_csv": format_profile_csv(r, h),
        "profile_dxf": profile_dxf,
        "panels_csv": format_panels_csv(panels),
        "panels_obj": format_panels_obj(net_geometry, panels),
    }
    data = {
        "rows": int(r.size),
        "units": units,
        "axis": {"point": [0.0, 0.0, 0.0], "direction": [0.0, 0.0, 1.0]},
        "profile": {k: np.asarray(v, float).tolist() for k, v in profile.items()},
        **segments,
        "angle_step_deg": 360.0 / segments["segments"],
        "sector": {"angle_deg": sector_deg,
                   "columns": int(sector_angles(math.radians(sector_deg),
                                                segments["segments"]).size)},
        "surface": {"columns": int(surface_angles(segments["segments"]).size)},
        "panel_size": int(panel_size),
        "pieces": pieces,
        "nets": nets,
        "panels": panels,
        "files": {key: relative_input(paths[key], folder, files[key]) for key in EXTRA_FILES},
    }
    out = artifact_files(KIND, stem, files["obj"], data, inputs=inputs, parameters=parameters,
                         metrics=metrics, status=status)
    return {**out, **{paths[key]: files[key] for key in EXTRA_FILES}}


def _check_file(record: dict, json_path: Path, field: str) -> None:
    read_listed(listed_path(record["path"], json_path, field), record["sha256"], json_path,
                field)


def check_mold_data(data: dict, source: Path) -> None:
    """Consistency the schema cannot express: array lengths against ``rows``, piece and panel
    row ranges inside the grid, panel pieces that exist."""
    m = data["rows"]
    for key, size in (("r", m), ("h", m), ("d", m), ("l", m - 1), ("x", m - 1)):
        got = len(data["profile"][key])
        if got != size:
            raise DgpcError(f"data.profile.{key}: {got} values, expected {size} "
                            f"(data.rows = {m})", source=source)
        values = np.asarray(data["profile"][key], dtype=np.float64).reshape(-1, 1)
        bad = bad_rows(values)
        if bad.size:
            raise DgpcError(f"data.profile.{key}[{int(bad[0])}]: "
                            f"{coordinate_problem(values[bad[0]])}", source=source)
    ids = set()
    for k, piece in enumerate(data["pieces"]):
        a, b = piece["rows"]
        if not 0 <= a < b <= m - 1:
            raise DgpcError(f"data.pieces[{k}].rows: [{a}, {b}] is not a row range of the "
                            f"{m} rows", source=source)
        ids.add(piece["id"])
    for k, panel in enumerate(data["panels"]):
        a, b = panel["rows"]
        if not 0 <= a < b <= m - 1:
            raise DgpcError(f"data.panels[{k}].rows: [{a}, {b}] is not a row range of the "
                            f"{m} rows", source=source)
        if panel["piece"] is not None and panel["piece"] not in ids:
            raise DgpcError(f"data.panels[{k}].piece: {panel['piece']!r} is not a mold piece",
                            source=source)
        if panel["net"] >= len(data["nets"]):
            raise DgpcError(f"data.panels[{k}].net: {panel['net']} but there are "
                            f"{len(data['nets'])} nets", source=source)


def _check_objs(data: dict, json_path: Path) -> None:
    """The mold OBJ (objects surface and sector, the sector's faces grouped by piece) and the
    panels OBJ (one object per net, its faces grouped by panel) against the JSON."""
    path = listed_path(data["obj"], json_path, "data.obj")
    obj = parse_obj(read_listed(path, data["obj_sha256"], json_path, "data.obj"), path)
    m = data["rows"]
    check_obj_objects(obj, [("surface", m * data["surface"]["columns"]),
                            ("sector", m * data["sector"]["columns"])], path,
                      "data.rows × data.surface/sector.columns")
    pieces = [p["id"] for p in data["pieces"]]
    if obj.objects[1].groups not in (pieces, [*pieces, "no-mold"]):
        raise DgpcError(f"the sector's groups {obj.objects[1].groups} are not the mold pieces "
                        f"{pieces} of data.pieces", source=path)
    record = data["files"]["panels_obj"]
    path = listed_path(record["path"], json_path, "data.files.panels_obj")
    obj = parse_obj(read_listed(path, record["sha256"], json_path, "data.files.panels_obj"),
                    path)
    check_obj_objects(obj, [(f"net{k + 1}", math.prod(net["shape"]))
                            for k, net in enumerate(data["nets"])], path, "data.nets")
    for k, o in enumerate(obj.objects):
        panels = [p["id"] for p in data["panels"] if p["net"] == k]
        if o.groups != panels:
            raise DgpcError(f"object {o.name!r}: its groups are not the panels of data.panels "
                            f"on net{k + 1}", source=path)


@reread
def read_mold(stem: str | Path) -> MoldArtifact:
    """Read and validate a mold artifact: envelope and schema, consistency, the OBJ and the
    extra files present and unchanged (sha256)."""
    paths = mold_paths(stem)
    json_path = paths["json"]
    try:
        doc = load_envelope(json_path, KIND)
        data = doc["data"]
        check_mold_data(data, json_path)
    except DgpcError as err:
        raise DgpcError(f"not a valid mold artifact: {err.reason}", source=err.source) from None
    _check_objs(data, json_path)
    for key, record in data["files"].items():
        if key != "panels_obj":
            _check_file(record, json_path, f"data.files.{key}")
    return MoldArtifact(parameters=doc["parameters"], inputs=doc["inputs"], data=data,
                        metrics=doc["metrics"], status=doc["status"])
