"""``dgpc nest``: place the flat parts on cut sheets (SPEC §6 nest, §7 utilization, §10).

Units: the flat parts are in their artifact's unit (``data.units``, the net's), converted to mm
once; ``scale`` multiplies the model first (a scale model: 1 for the real thing), so 1 model
unit = ``scale × (mm per unit)`` mm in every DXF. Sheet size, margin and spacing are in mm, and
so is everything the stage computes.

Engines: ``fill`` (default) — the deterministic no-fit-polygon fill of
:mod:`dgpc_cli.nesting.blf` with congruent parts paired (:mod:`dgpc_cli.nesting.pairs`): the
same input gives the same bytes, whatever the machine; ``spyrrow`` — sheet after sheet with
spyrrow's strip packer (:mod:`dgpc_cli.nesting.strip`), seeded, one worker, reproducible only
when its time budget is not what stops it. Either result is checked independently with shapely
(inside the margin, spacing kept) before anything is written.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from dgpc_cli.errors import DgpcError, OptionSlip
from dgpc_cli.io.dxf import previews
from dgpc_cli.io.flat import PART_COLUMNS, csv_bytes, part_row
from dgpc_cli.io.length import Length, Span
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.nesting.blf import Placement, Sheet, fill_sheets, inner_fit
from dgpc_cli.nesting.drawing import mold_map_drawing, placed_part, sheet_drawing
from dgpc_cli.nesting.geometry import Part, bounds, group_tolerance, prepare_parts, transform
from dgpc_cli.nesting.strip import spyrrow_sheets
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)

ENGINES = ("fill", "spyrrow")
#: Tolerance of the independent layout check (mm).
CHECK_TOL_MM = 1e-7


#: The shortest part (its longer side, in mm) nest cuts: below a cutter's kerf a part is a slip
#: of a scale or unit, not a part.
MIN_PART_LENGTH = 0.1


def parse_rotations(text: str) -> list[float]:
    """``"0,180"`` → ``[0.0, 180.0]``: distinct angles in degrees (ValueError otherwise)."""
    items = [t.strip() for t in str(text).split(",")]
    try:
        values = [float(t) for t in items if t]
    except ValueError:
        raise ValueError(f"{text!r} is not a comma-separated list of angles in degrees, "
                         "e.g. 0,180") from None
    if not values or not all(np.isfinite(values)):
        raise ValueError(f"{text!r}: give at least one finite angle in degrees, e.g. 0,180")
    norm = [round(v % 360.0, 9) % 360.0 for v in values]
    if len(set(norm)) != len(norm):
        raise ValueError(f"{text!r}: an angle is repeated (modulo 360)")
    return values


_SIDE = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:e[+-]?\d+)?)\s*([a-z]+)?\s*$")

#: Where a plain number is plausible as a sheet's side (mm): 10 mm to 100 m.
SHEET_SPAN = Span(10.0, 1e5, "sheet side")


def parse_sheet(text: str) -> tuple[float, float]:
    """``"2500x1250"`` → ``(2500.0, 1250.0)`` mm; each side may carry a unit (``6.1mx2.5m``),
    and one unit after the last side is both sides' (``6100x2500mm``, ``6.1x2.5m``); plain
    numbers are mm. ValueError (a usage error) unless both are > 0 and the units known, on a
    side beyond the one limit of every length (:mod:`dgpc_cli.io.length`), and on plain
    numbers outside :data:`SHEET_SPAN`, naming both readings (``6.1x2.5``: did you mean 6.1m x
    2.5m?)."""
    parts = str(text).lower().replace("×", "x").split("x")
    sides = [_SIDE.match(p) for p in parts]
    if len(parts) != 2 or not all(sides):
        raise ValueError(f"{text!r} is not WIDTHxHEIGHT (mm, or with a unit: 6.1mx2.5m, "
                         "6100x2500mm), e.g. 2500x1250")
    units = [m.group(2) for m in sides]
    if units[0] is None:
        units[0] = units[1]
    try:
        lengths = [Length(float(m.group(1)), u, "mm", typed=f"{m.group(1)}{u or ''}")
                   for m, u in zip(sides, units, strict=True)]
        w, h = (length.check("--sheet") for length in lengths)
    except DgpcError as err:
        raise ValueError(f"{text!r}: {err.reason}") from None
    except OptionSlip as slip:
        raise ValueError(str(slip)) from None
    if not (w > 0 and h > 0):
        raise ValueError(f"{text!r}: width and height must be > 0 mm")
    if units[1] is None and not (SHEET_SPAN.holds(w) and SHEET_SPAN.holds(h)):
        raise ValueError(_sheet_slip(text, w, h))
    return w, h


def _sheet_slip(text: str, w: float, h: float) -> str:
    """The usage error of a plain sheet size outside :data:`SHEET_SPAN`: the size read as mm,
    and the reading likely meant."""
    meant = next((u for u in ("m", "cm") if SHEET_SPAN.holds(w * mm_per_unit(u))
                  and SHEET_SPAN.holds(h * mm_per_unit(u))), None)
    guess = f"; did you mean {w:g}{meant} x {h:g}{meant}?" if meant else ""
    off = min(w, h) if not SHEET_SPAN.holds(min(w, h)) else max(w, h)
    return (f"{text} read as mm is a {w:g} x {h:g} mm sheet, a side {SHEET_SPAN.miss(off)}"
            f"{guess} (to mean it as typed, give its unit: {text}mm)")


@dataclass
class NestResult:
    """Parts (mm), their placements and the sheet; per-sheet and overall utilization."""

    parts: list[Part]
    placements: list[Placement]
    sheet: Sheet
    rotations: list[float]
    utilization: list[float]
    overall: float
    engine_info: dict

    @property
    def sheet_count(self) -> int:
        return len(self.utilization)


def check_fit(parts: list[Part], sheet: Sheet, rotations: list[float]) -> None:
    """DgpcError naming the first part that fits inside the margin with no allowed rotation;
    where every part would fit on the sheet turned (width and height swapped), it says so."""
    for p in parts:
        if all(inner_fit(p, r, sheet) is None for r in rotations):
            x0, y0, x1, y1 = bounds(p.outline)
            turned = replace(sheet, width=sheet.height, height=sheet.width)
            swap = (f"; the sheet turned fits them: give --sheet {turned.width:g}x"
                    f"{turned.height:g} (width first)"
                    if all(any(inner_fit(q, r, turned) is not None for r in rotations)
                           for q in parts) else "")
            raise DgpcError(
                f"part {p.id} ({x1 - x0:.1f} x {y1 - y0:.1f} mm) does not fit on the "
                f"{sheet.width:g} x {sheet.height:g} mm sheet inside its {sheet.margin:g} mm "
                f"margin with rotations {', '.join(f'{r:g}' for r in rotations)}"
                + (swap or "; use a larger --sheet, or cut long strips into boards with "
                   "`dgpc unfold --stock-length LENGTH`"), source="--sheet")


def check_layout(outlines: list[np.ndarray], sheets: list[int], sheet: Sheet) -> None:
    """Independent check (shapely): every outline inside its sheet's margin, no two on one
    sheet closer than the spacing. Raises DgpcError naming the first violation."""
    polys = [Polygon(o) for o in outlines]
    m = sheet.margin - CHECK_TOL_MM
    for poly, o in zip(polys, outlines, strict=True):
        lo, hi = o.min(axis=0), o.max(axis=0)
        if lo[0] < m or lo[1] < m or hi[0] > sheet.width - m or hi[1] > sheet.height - m:
            raise DgpcError("internal: a part lies outside the sheet margin", source="nest")
        if not poly.is_valid:
            raise DgpcError("internal: a part outline is not a simple polygon", source="nest")
    tree = shapely.STRtree(polys)
    gap = max(sheet.spacing - CHECK_TOL_MM, 0.0)
    pairs = tree.query(polys, predicate="dwithin", distance=gap) if gap > 0 else \
        tree.query(polys, predicate="intersects")
    sheet_of = np.asarray(sheets)
    for i, j in pairs.T:
        if i < j and sheet_of[i] == sheet_of[j]:
            d = polys[i].distance(polys[j])
            if gap > 0 or polys[i].intersection(polys[j]).area > CHECK_TOL_MM:
                raise DgpcError(f"internal: two parts are {d:.6g} mm apart, spacing is "
                                f"{sheet.spacing:g} mm", source="nest")


def nest_parts(flat_parts: list[dict], sheet: Sheet, rotations: list[float], *,
               units: str = "mm", scale: float = 1.0, engine: str = "fill",
               time_limit: float = 10.0, seed: int = 0, progress=None) -> NestResult:
    """Place every flat part (records of the flat artifact) on sheets; see the module."""
    if sheet.width <= 0 or sheet.height <= 0:
        raise DgpcError("sheet width and height must be > 0 mm", source="--sheet")
    if sheet.spacing < 0:
        raise DgpcError(f"{sheet.spacing:g}: must be >= 0 mm", source="--spacing")
    if sheet.margin < 0:
        raise DgpcError(f"{sheet.margin:g}: must be >= 0 mm", source="--margin")
    if engine not in ENGINES:
        raise DgpcError(f"{engine!r}: not one of {', '.join(ENGINES)}", source="--engine")
    limit = TOL.max_coordinate
    for option, value in (("--sheet", max(sheet.width, sheet.height)),
                          ("--margin", sheet.margin), ("--spacing", sheet.spacing)):
        if value > limit:
            raise DgpcError(f"{value:g} mm is beyond {limit:g} mm, the largest length dgpc "
                            "accepts", source=option)
    k = scale * mm_per_unit(units)
    reach = k * max((float(np.max(np.abs(np.asarray(rec["outline"], float))))
                     for rec in flat_parts), default=0.0)
    if not reach <= limit:
        raise DgpcError(f"{scale:g}: the parts scaled by it reach {reach:g} mm, beyond "
                        f"{limit:g} mm, the largest length dgpc accepts", source="--scale")
    smallest = k * min((float(np.max(np.ptp(np.asarray(rec["outline"], float), axis=0)))
                        for rec in flat_parts), default=np.inf)
    if not smallest >= MIN_PART_LENGTH:
        raise DgpcError(f"{scale:g}: the smallest part scaled by it is {smallest:.3g} mm long, "
                        f"below {MIN_PART_LENGTH:g} mm (a cutter's kerf); check --scale and "
                        "the flat artifact's unit", source="--scale")
    parts = prepare_parts(flat_parts, k, group_tolerance(sheet.spacing))
    check_fit(parts, sheet, rotations)
    if engine == "fill":
        placements, info = fill_sheets(parts, sheet, rotations, progress)
    else:
        placements = spyrrow_sheets(parts, sheet, rotations, time_limit, seed, progress)
        info = {}
    outlines = [transform(parts[p.index].outline, p.rotation, p.translation)
                for p in placements]
    check_layout(outlines, [p.sheet for p in placements], sheet)
    if sorted(p.index for p in placements) != list(range(len(parts))):
        raise DgpcError("internal: not every part placed exactly once", source="nest")
    n = max(p.sheet for p in placements) + 1
    area = np.zeros(n)
    np.add.at(area, [p.sheet for p in placements], [parts[p.index].area for p in placements])
    util = (area / (sheet.width * sheet.height)).tolist()
    overall = float(area.sum() / (n * sheet.width * sheet.height))
    log.info("%d parts on %d sheets, utilization %.1f %% overall", len(parts), n,
             100 * overall)
    warning = scale_warning(parts, util, units, scale, sheet)
    if warning:
        log.warning("%s", warning)
    return NestResult(parts, placements, sheet, list(rotations), util, overall, info)


#: Implausible scale (issue "no silent unit traps"): a part shorter than this (mm) ...
SMALL_PART_MM = 10.0
#: ... or every sheet used less than this fraction.
LOW_UTILIZATION = 0.01


def scale_warning(parts: list[Part], utilization: list[float], units: str,
                  scale: float, sheet: Sheet | None = None) -> str | None:
    """One line naming an implausible scale (a part under :data:`SMALL_PART_MM`, even the
    fullest sheet less than :data:`LOW_UTILIZATION` used) and its likely fix, or None: for
    parts not in metres, making the net in metres; for a sheet far too large for the parts,
    the sheet's size (parts in metres already need no new net)."""
    longest = [max(np.ptp(p.outline, axis=0)) for p in parts]
    small = min(range(len(parts)), key=lambda i: longest[i])
    low = max(range(len(utilization)), key=lambda s: utilization[s])
    if longest[small] >= SMALL_PART_MM and utilization[low] >= LOW_UTILIZATION:
        return None
    remake = "make the net with `init --units m`" if units != "m" else None
    if longest[small] < SMALL_PART_MM:
        what = f"part {parts[small].id} is {longest[small]:.3g} mm long"
        fix = (f"if the net was meant in metres, {remake} (or give --scale)" if remake
               else "check --scale")
    else:
        what = f"sheet {sheet_id(low)} is {100 * utilization[low]:.2g} % used"
        size = ("" if sheet is None else
                f" (it is {sheet.width / 1000:.4g} x {sheet.height / 1000:.4g} m)")
        fix = f"check --sheet{size}" + (f", or if the net was meant in metres, {remake}"
                                        if remake else "")
    return f"implausible scale: {what} (parts in {units}, scale {scale:g}); {fix}"


def sheet_drawings(result: NestResult, *, border: bool = False, label_style: str = "text"
                   ) -> list[tuple[bytes, list]]:
    """Per sheet ``(dxf, labels)``: the bytes of its DXF (with the sheet's ``border`` or not,
    labels in ``label_style``) and the labels in placement order
    (:class:`~dgpc_cli.nesting.labels.Label`). The cut files come first: their previews
    (:func:`sheet_previews`) are drawn after every DXF, or not at all (``--no-preview``)."""
    out = []
    W, H = result.sheet.width, result.sheet.height
    for s in range(result.sheet_count):
        placed = [placed_part(result.parts[p.index], p.rotation, p.translation)
                  for p in result.placements if p.sheet == s]
        drawing, labels = sheet_drawing(W, H, placed, border=border, label_style=label_style)
        out.append((drawing.to_bytes(f"sheet {sheet_id(s)}"), labels))
    return out


def sheet_previews(result: NestResult, s: int, dxf: bytes) -> tuple[bytes, bytes]:
    """``(svg, png)`` previews of the DXF bytes of sheet ``s``: titled with the sheet, its size,
    its parts and its use, the sheet outlined."""
    W, H = result.sheet.width, result.sheet.height
    count = sum(1 for p in result.placements if p.sheet == s)
    title = (f"{sheet_id(s)} ({s + 1} of {result.sheet_count}): sheet {W:g} × {H:g} mm, "
             f"{count} parts, {100 * result.utilization[s]:.1f} % used")
    svg, png = previews(dxf, title=title, frame=(W, H))
    return svg, png


#: A sheet file of an earlier nesting (SHEETS.sheetNN.dxf/.svg/.png, SHEETS.moldmap.*).
_SHEET_FILE = re.compile(r"\.(sheet\d{2,}\.(dxf|svg|png)|moldmap\.(dxf|png))$")


def existing_sheet_files(stem) -> list[Path]:
    """The sheet and mold-map files of an earlier nesting to ``stem`` (whatever their count):
    checked before nesting, so that a run without --force fails at once."""
    stem = Path(stem)
    if not stem.parent.is_dir():
        return []
    name = stem.name
    return sorted(p for p in stem.parent.iterdir()
                  if p.name.startswith(name) and _SHEET_FILE.fullmatch(p.name[len(name):]))


def sheet_id(s: int) -> str:
    return f"SH{s + 1:02d}"


#: Columns of SHEETS.parts.csv: the part, where it is (sheet, position of its origin and its
#: rotation), then the rest of the part's columns (:data:`~dgpc_cli.io.flat.PART_COLUMNS`).
SHEET_COLUMNS = (*PART_COLUMNS[:4], "sheet", "x_mm", "y_mm", "rotation_deg", *PART_COLUMNS[4:])


def parts_csv(result: NestResult, flat_parts: list[dict], mm: float) -> bytes:
    """SHEETS.parts.csv, one line per part by id: part → strip → board → sheet → position,
    its length, widths and area in mm (``mm`` mm per flat unit, the scale included)."""
    records = {p["id"]: p for p in flat_parts}
    rows = []
    for p in sorted(result.placements, key=lambda q: result.parts[q.index].id):
        part = result.parts[p.index]
        rows.append({**part_row(records[part.id], mm), "sheet": sheet_id(p.sheet),
                     "x_mm": f"{p.translation[0]:.3f}", "y_mm": f"{p.translation[1]:.3f}",
                     "rotation_deg": f"{p.rotation:g}"})
    return csv_bytes(SHEET_COLUMNS, rows)


def sheets_obj(result: NestResult) -> bytes:
    """OBJ: the sheets side by side, outlines as closed polylines, one object per sheet."""
    from dgpc_cli import __version__
    from dgpc_cli.io.sheets import OBJ_SHEET_GAP

    W, H = result.sheet.width, result.sheet.height
    lines = [f"# dgpc {__version__}",
             f"# sheets ({result.sheet_count}), {W!r} x {H!r} mm, side by side along x"]
    nv = 0

    def ring(pts):
        nonlocal nv
        lines.extend(f"v {x!r} {y!r} 0.0" for x, y in pts.tolist())
        idx = list(range(nv + 1, nv + len(pts) + 1))
        nv += len(pts)
        lines.append("l " + " ".join(map(str, idx + idx[:1])))

    for s in range(result.sheet_count):
        dx = np.array([s * (1.0 + OBJ_SHEET_GAP) * W, 0.0])
        lines.append(f"o {sheet_id(s)}")
        ring(np.array([[0.0, 0.0], [W, 0.0], [W, H], [0.0, H]]) + dx)
        for p in result.placements:
            if p.sheet == s:
                lines.append(f"g {result.parts[p.index].id}")
                ring(transform(result.parts[p.index].outline, p.rotation, p.translation) + dx)
    return ("\n".join(lines) + "\n").encode("ascii")


def mold_map(mold, scale: float) -> tuple[bytes, bytes]:
    """The panel-to-mold map of a mold artifact (its unit to mm, times the model ``scale``):
    DXF and PNG preview bytes."""
    k = scale * mm_per_unit(mold.units)
    dxf = mold_map_drawing(k * mold.r, k * mold.h, mold.data["sector"]["angle_deg"],
                           mold.data["pieces"], mold.data["panels"]).to_bytes("mold map")
    # twice as wide as a sheet's preview: the table's ids are read there
    (png,) = previews(dxf, ("png",), title="panel-to-mold map (mm)", width=20.0)
    return dxf, png


def sheets_data(result: NestResult, labels: list[list], *, units: str, scale: float,
                engine: str, time_limit: float, seed: int, previews: bool = True) -> dict:
    """``data`` of the sheets artifact (without the file records); ``previews``: whether the
    sheets have SVG/PNG previews."""
    per_sheet = []
    for s in range(result.sheet_count):
        on = [p for p in result.placements if p.sheet == s]
        key = sheet_id(s).lower().replace("sh", "sheet")
        per_sheet.append({
            "id": sheet_id(s), "index": s,
            "parts": sorted(result.parts[p.index].id for p in on),
            "utilization": result.utilization[s],
            "parts_area": float(sum(result.parts[p.index].area for p in on)),
            "dxf": f"{key}_dxf",
            **({"svg": f"{key}_svg", "png": f"{key}_png"} if previews else {})})
    sh = result.sheet
    label_of = {}
    for s, sheet_labels in enumerate(labels):
        on = [p for p in result.placements if p.sheet == s]
        for p, lb in zip(on, sheet_labels, strict=True):
            label_of[p.index] = {"text": lb.text, "at": list(lb.at), "height": lb.height,
                                 "rotation": lb.rotation, "leader": lb.leader is not None}
    return {
        "units": "mm",
        "sheet": {"width": sh.width, "height": sh.height, "margin": sh.margin,
                  "spacing": sh.spacing, "part_units": units, "scale": scale,
                  "mm_per_unit": scale * mm_per_unit(units)},
        "rotations": result.rotations, "engine": engine, "engine_info": result.engine_info,
        "seed": seed, "time_limit": time_limit, "sheet_count": result.sheet_count,
        "sheets": per_sheet,
        "placements": [{"part": result.parts[p.index].id, "class": result.parts[p.index].cls,
                        "strip": result.parts[p.index].strip, "sheet": p.sheet,
                        "rotation": p.rotation, "translation": list(p.translation),
                        "label": label_of[p.index]}
                       for p in result.placements],
        "utilization": {"overall": result.overall, "per_sheet": result.utilization},
    }


def sheets_metrics(data: dict) -> dict:
    """The metrics of a sheets artifact (SPEC §7: sheet utilization)."""
    return {"sheet_count": data["sheet_count"], "n_parts": len(data["placements"]),
            "utilization": data["utilization"]["overall"],
            "utilization_per_sheet": data["utilization"]["per_sheet"]}
