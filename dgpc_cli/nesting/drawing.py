"""Cut-sheet DXF, its SVG/PNG previews, and the panel-to-mold map DXF (SPEC §6 nest, §9 ezdxf).

Sheet DXF (R2010, ``$INSUNITS`` mm, origin at the sheet's lower-left corner):

* ``SHEET`` — the sheet outline, a closed LWPOLYLINE;
* ``CUT`` — one closed LWPOLYLINE per part, its outline under its placement;
* ``SCORE`` — open LWPOLYLINEs, the rulings (bend/score lines);
* ``LABEL`` — the part id, a TEXT centred on the part's label point.

Previews are rendered from the DXF bytes themselves (read back with ezdxf) by ezdxf's drawing
add-on with the matplotlib backend, in black on white.
"""

from __future__ import annotations

import io

import ezdxf
import numpy as np
from ezdxf.enums import TextEntityAlignment

from ..io.dxf import dxf_bytes, new_mm_document
from .geometry import transform

SHEET_LAYERS = {"SHEET": 8, "CUT": 1, "SCORE": 5, "LABEL": 3}
MAP_LAYERS = {"PROFILE": 7, "AXIS": 1, "SECTOR": 8, "PIECES": 3, "PANELS": 4, "LABEL": 2,
              "TABLE": 7}


def _xy(points: np.ndarray) -> list[tuple[float, float]]:
    return [(float(x), float(y)) for x, y in np.asarray(points, float)]


def _upright(deg: float) -> float:
    """A text angle in (−90°, 90°] so labels never read upside down."""
    a = (float(deg) + 90.0) % 180.0 - 90.0
    return 90.0 if a == -90.0 else a


def sheet_dxf(width: float, height: float, placed: list[dict]) -> bytes:
    """DXF bytes of one sheet; ``placed`` items have ``id``, ``outline``, ``score``, ``label``
    (all in sheet mm, already placed), ``rotation`` and ``text_height``."""

    def build():
        doc = new_mm_document(SHEET_LAYERS)
        msp = doc.modelspace()
        msp.add_lwpolyline([(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)],
                           format="xy", close=True, dxfattribs={"layer": "SHEET"})
        for p in placed:
            msp.add_lwpolyline(_xy(p["outline"]), format="xy", close=True,
                               dxfattribs={"layer": "CUT"})
            for line in p["score"]:
                msp.add_lwpolyline(_xy(line), format="xy", close=False,
                                   dxfattribs={"layer": "SCORE"})
            msp.add_text(p["id"], height=p["text_height"],
                         rotation=_upright(p["rotation"]),
                         dxfattribs={"layer": "LABEL"}).set_placement(
                tuple(map(float, p["label"])), align=TextEntityAlignment.MIDDLE_CENTER)
        return doc

    return dxf_bytes(build)


def previews(dxf: bytes) -> tuple[bytes, bytes]:
    """``(svg, png)`` bytes rendered from the DXF ``dxf`` with ezdxf's drawing add-on."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.config import BackgroundPolicy, ColorPolicy, Configuration
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    doc = ezdxf.read(io.StringIO(dxf.decode("utf-8", errors="replace")))
    config = Configuration(background_policy=BackgroundPolicy.WHITE,
                           color_policy=ColorPolicy.BLACK)
    out = []
    with plt.rc_context({"svg.hashsalt": "dgpc", "svg.fonttype": "path"}):
        fig = plt.figure(figsize=(10, 10 * 0.75))
        try:
            ax = fig.add_axes((0, 0, 1, 1))
            Frontend(RenderContext(doc), MatplotlibBackend(ax), config=config).draw_layout(
                doc.modelspace(), finalize=True)
            for fmt, meta in (("svg", {"Date": None, "Creator": None}),
                              ("png", {"Software": None})):
                buf = io.BytesIO()
                fig.savefig(buf, format=fmt, dpi=100, metadata=meta)
                out.append(buf.getvalue())
        finally:
            plt.close(fig)
    return out[0], out[1]


def mold_map_dxf(r_mm: np.ndarray, h_mm: np.ndarray, sector_deg: float,
                 pieces: list[dict], panels: list[dict]) -> bytes:
    """The panel-to-mold map sheet (mm).

    Left: the meridian profile (x = r, y = h) with the axis. Right: the developed sector — the
    meridian arc length s(u) upwards, the parallel arc r(u)·φ across, centred — with each mold
    piece outlined and named, and on it (layer PANELS) where the panels are pressed: one
    outline per band of mold rows, as wide as its panels' angle (the mold is a surface of
    revolution, so every panel of a band fits the same place), labelled with the rows and the
    number of panels. Below: a table, one line per mold piece listing its panels, then the
    flat panels (no mold) separately.
    """
    r_mm, h_mm = np.asarray(r_mm, float), np.asarray(h_mm, float)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(r_mm), np.diff(h_mm)))])
    phi = np.radians(sector_deg)
    size = float(max(np.ptp(h_mm), r_mm.max(), s[-1], 1e-9))
    text = 0.02 * size
    x0 = float(r_mm.max() + 0.3 * size + 0.5 * r_mm.max() * phi)

    def build():
        doc = new_mm_document(MAP_LAYERS)
        msp = doc.modelspace()
        msp.add_lwpolyline(_xy(np.column_stack([r_mm, h_mm])), format="xy",
                           dxfattribs={"layer": "PROFILE"})
        msp.add_line((0.0, float(h_mm.min()) - 0.05 * size),
                     (0.0, float(h_mm.max()) + 0.05 * size),
                     dxfattribs={"layer": "AXIS", "linetype": "CENTER"})
        msp.add_text("meridian profile", height=text, dxfattribs={"layer": "LABEL"}
                     ).set_placement((0.0, float(h_mm.max()) + 0.1 * size))
        half = 0.5 * r_mm * phi
        left = np.column_stack([x0 - half, s])
        right = np.column_stack([x0 + half, s])
        msp.add_lwpolyline(_xy(np.concatenate([left, right[::-1]])), format="xy", close=True,
                           dxfattribs={"layer": "SECTOR"})
        msp.add_text(f"developed sector {sector_deg:.4g} deg", height=text,
                     dxfattribs={"layer": "LABEL"}).set_placement(
            (x0 - float(half.max()), float(s[-1]) + 0.1 * size))
        for piece in pieces:
            a, b = piece["rows"]
            outline = np.concatenate([left[a:b + 1], right[a:b + 1][::-1]])
            msp.add_lwpolyline(_xy(outline), format="xy", close=True,
                               dxfattribs={"layer": "PIECES"})
            mid = (a + b) // 2
            msp.add_text(piece["id"], height=text, dxfattribs={"layer": "LABEL"}).set_placement(
                (x0, float(s[mid])), align=TextEntityAlignment.MIDDLE_CENTER)
        for (a, b), width_deg, count in panel_bands(panels):
            half_p = 0.5 * r_mm[a:b + 1] * np.radians(width_deg)
            outline = np.concatenate([np.column_stack([x0 - half_p, s[a:b + 1]]),
                                      np.column_stack([x0 + half_p, s[a:b + 1]])[::-1]])
            msp.add_lwpolyline(_xy(outline), format="xy", close=True,
                               dxfattribs={"layer": "PANELS"})
            msp.add_text(f"rows {a}-{b}: {count} panels", height=0.5 * text,
                         dxfattribs={"layer": "LABEL"}).set_placement(
                (x0 + float(half.max()) + 0.02 * size, 0.5 * float(s[a] + s[b])),
                align=TextEntityAlignment.MIDDLE_LEFT)
        y = float(min(h_mm.min(), 0.0)) - 0.2 * size
        for line in map_table(pieces, panels):
            msp.add_text(line, height=0.6 * text, dxfattribs={"layer": "TABLE"}
                         ).set_placement((0.0, y))
            y -= 1.2 * text
        return doc

    return dxf_bytes(build)


def panel_bands(panels: list[dict]) -> list[tuple[tuple[int, int], float, int]]:
    """The bands of mold rows the curved panels are pressed on: ``((first, last) row, widest
    panel angle in degrees, number of panels)``, by first row."""
    bands: dict[tuple[int, int], list[float]] = {}
    for p in panels:
        if p["piece"] is not None:
            a0, a1 = p["angle_deg"]
            bands.setdefault(tuple(p["rows"]), []).append(abs(a1 - a0))
    return [(rows, max(w), len(w)) for rows, w in sorted(bands.items())]


def map_table(pieces: list[dict], panels: list[dict], per_line: int = 8) -> list[str]:
    """The table of the map: per mold piece its rows and panels, then the flat panels."""
    lines = ["panels per mold piece"]
    for piece in pieces:
        ids = [p["id"] for p in panels if p["piece"] == piece["id"]]
        head = f"{piece['id']} rows {piece['rows'][0]}-{piece['rows'][1]} ({len(ids)} panels):"
        lines += _wrapped(head, ids, per_line)
    flat = [p["id"] for p in panels if p["flat"]]
    lines += _wrapped(f"flat panels, no mold ({len(flat)}):", flat, per_line)
    return lines


def _wrapped(head: str, ids: list[str], per_line: int) -> list[str]:
    if not ids:
        return [f"{head} none"]
    chunks = [", ".join(ids[i:i + per_line]) for i in range(0, len(ids), per_line)]
    return [f"{head} {chunks[0]}"] + [f"    {c}" for c in chunks[1:]]


def placed_part(part, rotation: float, translation) -> dict:
    """A part's outline, score lines and label point under its placement (sheet mm)."""
    return {"id": part.id, "rotation": rotation,
            "outline": transform(part.outline, rotation, translation),
            "score": [transform(s, rotation, translation) for s in part.score],
            "label": transform(part.label, rotation, translation),
            "text_height": float(max(0.4 * part.width, 1e-3))}
