"""The ``flat`` artifact (SPEC §3, §6 unfold): developed strips as 2-D parts, STEM.json + STEM.obj.

``data.parts`` (in part-id order) carries per part everything the next stage (nest) needs, in
the artifact's unit ``data.units`` (the net's):

* ``id`` (the strip's stable id, e.g. ``S-v07``, or a board's ``S-v07.2`` with
  ``unfold --stock-length``), ``strip`` (its column v), ``board`` (1, 2, … along the strip;
  1 for a whole strip), ``rows`` (the first and last net row it covers), ``positions`` (the
  arc length along the strip's mid-curve of its two ends), ``class``; ``row_span`` where a
  joint cuts it inside a planar quad (no ruling within the stock): the fractional rows of its
  ends, ``u + f`` for the straight joint across quad u at the fraction f of both its sides;
* ``outline``: the closed outline polygon, counter-clockwise, first point not repeated;
* ``score``: open polylines (the interior rulings, bend/score lines);
* ``label``: a point inside the part for its id;
* ``geodesics``: the two developed boundary geodesics A and B (the vertices of the quads
  ``A_u A_(u+1) B_(u+1) B_u``), ``straightness``, ``strain``, ``length`` (mean of the two
  geodesics), ``width`` (least and largest distance between them), ``area``;
* ``cuts`` (boards of one template, ``unfold --stock-length``): the board's two end cuts, each
  a straight line of the template, not necessarily a ruling: ``along`` its arc lengths on the
  template's edges A and B from the first row, ``A`` and ``B`` its ends in the strip's
  ``(t, s)``, ``path`` its ends and ruling crossings in ``(t, s)`` (the cut on the 3-D strip:
  :mod:`dgpc_cli.strips.template_boards`); ``rows`` are then the net rows the
  board reaches into;
* ``alignment``: the rigid motion ``x ↦ matrix·x + translation`` onto its class representative
  (with the boundary pairing used and whether it is a reflection) and its error.

``data.classes`` lists the congruence classes (the cutting templates): ``id``,
``representative`` (a part id: the template), ``quantity``, ``members`` (part ids: its copies)
and the largest member error (``max_error`` in the artifact's unit, ``max_deviation_mm`` in
mm; each part's own in its ``alignment.deviation_mm``); ``score_lines``: ``shared`` when every
copy's score lines, aligned, lie within the congruence tolerance of the representative's, else
``per copy``, and ``score_deviation_mm`` the largest such distance (mm). ``data.joints``
lists where boards meet: ``strip``, net ``row`` (fractional, ``u + f``, for a joint inside a
quad), ``position`` (arc length along the strip) and the two ``parts``; for boards of one
template also the ``cut`` (as a part's ``cuts``), ``row`` the nearest ruling (where the strips
share the template's vertices, its fractional row).
The OBJ holds the same parts (z = 0) as one object each, for viewers. Beside it, all listed in
``data.files``:

* ``STEM.parts.csv`` (``parts_csv``): the cut list, one line per template (class) with its
  quantity and its copies' ids, in mm (:data:`CLASS_COLUMNS`);
* ``STEM.assembly.csv`` (``assembly_csv``): one line per part, where it goes (strip, board,
  rows, arc-length positions: the joints) and its class, in mm (:data:`ASSEMBLY_COLUMNS`);
* ``STEM.C01.dxf``, ... (``template_C01_dxf``, ...): each template alone, in mm, on the cut
  sheets' layers, for shops that nest the parts themselves; for a class whose copies have
  their own score lines (``score_lines`` ``per copy``) one file per copy instead,
  ``STEM.C01.S-v03.dxf`` (``template_C01_S-v03_dxf``): the same outline, the copy's score
  lines.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .artifact import (
    artifact_files,
    artifact_paths,
    listed_file,
    listed_path,
    load_envelope,
    read_listed,
    relative_input,
    reread,
)
from .coordinates import bad_rows, coordinate_problem
from .obj import check_obj_objects, parse_obj
from .strips import format_parts_obj, read_obj_checked
from .units import DEFAULT_UNITS, mm_per_unit

KIND = "flat"
#: Gap between flat parts laid side by side, as a fraction of the tallest part's height.
PART_GAP = 0.25
#: Columns of a part in the cut lists (FLAT.parts.csv, and SHEETS.parts.csv around its
#: placement): lengths in mm, the area in mm².
PART_COLUMNS = ("id", "class", "strip", "board", "row_start", "row_stop", "start_mm",
                "stop_mm", "length_mm", "width_min_mm", "width_max_mm", "area_mm2")


#: Columns of the cut list FLAT.parts.csv: one line per template (congruence class), its
#: copies' ids separated by spaces, the representative's sizes and the class's largest
#: deviation (mm), whether its copies share their score lines (``shared``, ``per copy``) and
#: its DXF files (one, or one per copy in the order of ``parts``), separated by spaces.
CLASS_COLUMNS = ("class", "quantity", "parts", "representative", "length_mm", "width_min_mm",
                 "width_max_mm", "area_mm2", "max_deviation_mm", "score_lines", "dxf")
#: Columns of FLAT.assembly.csv: a part's columns and its deviation from its template (mm).
ASSEMBLY_COLUMNS = (*PART_COLUMNS, "deviation_mm")


def side_by_side(outlines: list[np.ndarray]) -> list[np.ndarray]:
    """Translations ``(2,)`` that lay 2-D outlines side by side: left-aligned, one above the
    other, :data:`PART_GAP` of the tallest one apart (so none overlaps another)."""
    heights = [float(np.ptp(np.asarray(o)[:, 1])) for o in outlines]
    gap = PART_GAP * max(heights, default=0.0)
    out, y = [], 0.0
    for o, h in zip(outlines, heights, strict=True):
        o = np.asarray(o, float)
        out.append(np.array([-o[:, 0].min(), y - o[:, 1].min()]))
        y += h + gap
    return out


def part_row(part: dict, mm: float) -> dict:
    """The :data:`PART_COLUMNS` of a part record whose lengths are ``mm`` mm per unit."""
    return {"id": part["id"], "class": part["class"], "strip": part["strip"],
            "board": part["board"], **row_columns(part),
            "start_mm": f"{mm * part['positions'][0]:.3f}",
            "stop_mm": f"{mm * part['positions'][1]:.3f}",
            "length_mm": f"{mm * part['length']:.3f}",
            "width_min_mm": f"{mm * part['width'][0]:.3f}",
            "width_max_mm": f"{mm * part['width'][1]:.3f}",
            "area_mm2": f"{mm * mm * part['area']:.2f}"}


def first_row(part: dict) -> float:
    """The net row of a part record's first end: fractional (``row_span``) where a joint cuts
    it inside a quad."""
    return float(part.get("row_span", part.get("rows", [0]))[0])


def row_columns(part: dict) -> dict:
    """``row_start``, ``row_stop`` of a part record: its net rows, or the fractional rows of
    its ends (``row_span``) where a joint cuts it inside a quad."""
    span = part.get("row_span")
    if span is None:
        return {"row_start": part["rows"][0], "row_stop": part["rows"][1]}
    return {"row_start": f"{span[0]:.4f}".rstrip("0").rstrip("."),
            "row_stop": f"{span[1]:.4f}".rstrip("0").rstrip(".")}


def csv_bytes(columns: tuple, rows: list[dict]) -> bytes:
    """CSV bytes with a header line of ``columns`` and one line per row dict."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue().encode("utf-8")


def parts_csv(parts: list[dict], classes: list[dict], units: str,
              dxf_names: dict[str, list[str]]) -> bytes:
    """FLAT.parts.csv: the cut list, one line per class (in class order), mm; ``dxf_names``
    the file names of each class's DXFs (its template's, or one per copy)."""
    mm = mm_per_unit(units)
    by_id = {p["id"]: p for p in parts}
    rows = []
    for c in classes:
        rep = part_row(by_id[c["representative"]], mm)
        rows.append({"class": c["id"], "quantity": c["quantity"], "parts": " ".join(c["members"]),
                     "representative": c["representative"],
                     **{k: rep[k] for k in CLASS_COLUMNS[4:8]},
                     "max_deviation_mm": f"{class_deviation_mm(c, mm):.3f}",
                     "score_lines": c.get("score_lines", "shared"),
                     "dxf": " ".join(dxf_names.get(c["id"], []))})
    return csv_bytes(CLASS_COLUMNS, rows)


def class_deviation_mm(cls: dict, mm: float) -> float:
    """A class's largest member deviation in mm (``mm`` mm per unit: for records without
    ``max_deviation_mm``)."""
    return float(cls.get("max_deviation_mm", mm * cls["max_error"]))


def assembly_csv(parts: list[dict], units: str) -> bytes:
    """FLAT.assembly.csv: one line per part (in part order), mm."""
    mm = mm_per_unit(units)
    return csv_bytes(ASSEMBLY_COLUMNS, [
        {**part_row(p, mm),
         "deviation_mm": f"{p['alignment'].get('deviation_mm', mm * p['alignment']['error']):.3f}"}
        for p in parts])


@dataclass
class FlatArtifact:
    """Developed parts ``parts`` and congruence ``classes`` (JSON records as described in the
    module) with the envelope fields."""

    parts: list
    classes: list
    units: str = DEFAULT_UNITS
    #: Class id -> the bytes of its template DXF (written beside the artifact).
    templates: dict = field(default_factory=dict)
    joints: list = field(default_factory=list)
    parameters: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    status: dict = field(default_factory=dict)

    def part(self, part_id: str) -> dict:
        for p in self.parts:
            if p["id"] == part_id:
                return p
        raise KeyError(part_id)


def _obj_bytes(parts: list) -> bytes:
    return format_parts_obj(f"flat parts ({len(parts)}), developed strips in the plane z = 0",
                            [(p["id"], np.asarray(p["geodesics"][0], float),
                              np.asarray(p["geodesics"][1], float)) for p in parts],
                            outlines={p["id"]: (p["outline"], p["score"]) for p in parts
                                      if _drawn_as_outline(p)})


def _drawn_as_outline(part: dict) -> bool:
    """Whether the part's OBJ object is its outline and score lines (a part trimmed to the
    reference's outline, or cut along a template's curved edges) rather than its quads."""
    return bool(part.get("trimmed")) or "edges" in part


def csv_path(stem: str | Path, name: str = "parts") -> Path:
    """``STEM.parts.csv`` (or ``STEM.NAME.csv``)."""
    json_path, _ = artifact_paths(stem)
    return json_path.with_suffix(f".{name}.csv")


def template_path(stem: str | Path, name: str) -> Path:
    """``STEM.C01.dxf``: the template DXF ``name`` (a class id, or ``C01.S-v03`` a copy's)."""
    json_path, _ = artifact_paths(stem)
    return json_path.with_suffix(f".{name}.dxf")


def flat_files(stem: str | Path, art: FlatArtifact) -> dict[Path, bytes]:
    """The bytes of ``STEM.json``, ``STEM.obj``, the cut list ``STEM.parts.csv``,
    ``STEM.assembly.csv`` and the template DXFs (nothing written), schema-checked."""
    json_path, _ = artifact_paths(stem)
    folder = json_path.resolve().parent
    names: dict[str, list[str]] = {}
    for name in art.templates:                      # in class order, copies in member order
        names.setdefault(name.split(".")[0], []).append(template_path(stem, name).name)
    table = parts_csv(art.parts, art.classes, art.units, names)
    assembly = assembly_csv(art.parts, art.units)
    listed = {"parts_csv": (csv_path(stem), table),
              "assembly_csv": (csv_path(stem, "assembly"), assembly),
              **{f"template_{name.replace('.', '_')}_dxf": (template_path(stem, name), data)
                 for name, data in sorted(art.templates.items())}}
    data = {"units": art.units, "parts": art.parts, "classes": art.classes,
            "joints": art.joints,
            "files": {key: relative_input(path, folder, b) for key, (path, b) in listed.items()}}
    files = artifact_files(KIND, stem, _obj_bytes(art.parts), data, inputs=art.inputs,
                           parameters=art.parameters, metrics=art.metrics, status=art.status)
    return {**files, **{path: b for path, b in listed.values()}}


def _check_part_points(parts: list[dict], json_path: Path) -> None:
    """Every point of every part (outline, score lines, label, geodesics) within the range of
    :mod:`.coordinates`; DgpcError naming the first one beyond it."""
    for i, part in enumerate(parts):
        fields = [("outline", part["outline"]), ("label", [part["label"]])]
        fields += [(f"score[{j}]", s) for j, s in enumerate(part["score"])]
        fields += [(f"geodesics[{j}]", g) for j, g in enumerate(part["geodesics"])]
        fields += [(f"edges[{j}]", g) for j, g in enumerate(part.get("edges", []))]
        for name, points in fields:
            points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
            bad = bad_rows(points)
            if bad.size:
                where = "" if name == "label" else f"[{int(bad[0])}]"
                raise DgpcError(f"data.parts[{i}].{name}{where}: "
                                f"{coordinate_problem(points[bad[0]])}", source=json_path)


def _check_row_spans(parts: list[dict], json_path) -> None:
    """A part's fractional rows (``row_span``, a joint inside a quad) ascending and within the
    net rows it reaches into (``rows``); DgpcError naming the first part where they are not."""
    for i, p in enumerate(parts):
        span = p.get("row_span")
        if span is not None and not (p["rows"][0] <= span[0] < span[1] <= p["rows"][1]
                                     and np.floor(span[0]) == p["rows"][0]
                                     and np.ceil(span[1]) == p["rows"][1]):
            raise DgpcError(f"data.parts[{i}].row_span: {span} does not lie in its rows "
                            f"{p['rows']} (from row_span[0] rounded down to row_span[1] "
                            "rounded up)", source=json_path)


def _obj_vertices(part: dict) -> int:
    """Vertices of a part's OBJ object: 2 per row, or for a part trimmed to the reference's
    outline those of its outline and score lines."""
    if _drawn_as_outline(part):
        return len(part["outline"]) + sum(len(line) for line in part["score"])
    return 2 * len(part["geodesics"][0])


def check_simple_outlines(parts: list[dict], source) -> None:
    """Every part's outline is a simple polygon (no edge crosses another: a bow tie is no
    piece that can be cut); a DgpcError naming the first part and where it crosses."""
    import shapely
    from shapely.validation import explain_validity

    polygons = [shapely.Polygon(np.asarray(p["outline"], dtype=np.float64)) for p in parts]
    bad = np.flatnonzero(~shapely.is_valid(polygons)) if polygons else []
    if len(bad):
        k = int(bad[0])
        why = " ".join(explain_validity(polygons[k]).split())
        raise DgpcError(f"data.parts[{k}] ({parts[k]['id']}): its outline crosses itself or "
                        f"is degenerate ({why})", source=source)


@reread
def read_flat(stem: str | Path) -> FlatArtifact:
    """Read and validate a flat artifact: envelope, schema, the OBJ's hash, and the classes'
    consistency with the parts (every part in exactly one class, quantities match)."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    obj_path = listed_file(data["obj"], json_path, "data.obj")
    obj = parse_obj(read_obj_checked(json_path, obj_path, data["obj_sha256"]), obj_path)
    check_obj_objects(obj, [(p["id"], _obj_vertices(p)) for p in data["parts"]], obj_path,
                      "data.parts")
    for key, record in data["files"].items():
        field = f"data.files.{key}"
        read_listed(listed_path(record["path"], json_path, field), record["sha256"], json_path,
                    field)
    parts, classes = data["parts"], data["classes"]
    _check_part_points(parts, json_path)
    _check_row_spans(parts, json_path)
    check_simple_outlines(parts, json_path)
    ids = [p["id"] for p in parts]
    if len(set(ids)) != len(ids):
        raise DgpcError("data.parts: duplicate part ids", source=json_path)
    members = [m for c in classes for m in c["members"]]
    if sorted(members) != sorted(ids):
        raise DgpcError("data.classes: the members are not the parts, each once", source=json_path)
    for i, c in enumerate(classes):
        if c["quantity"] != len(c["members"]) or c["representative"] not in c["members"]:
            raise DgpcError(f"data.classes[{i}]: quantity or representative does not match "
                            "its members", source=json_path)
    return FlatArtifact(parts=parts, classes=classes, units=data["units"],
                        joints=data["joints"], parameters=doc["parameters"],
                        inputs=doc["inputs"], metrics=doc["metrics"], status=doc["status"])
