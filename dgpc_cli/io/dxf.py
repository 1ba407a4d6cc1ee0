"""Every DXF dgpc writes, and its previews (SPEC §3, §6, §9 ezdxf): one place for the format.

Callers describe a drawing in millimetres (:class:`Drawing`: layers, polylines, texts) and get
its bytes from :meth:`Drawing.to_bytes`, which

* drops zero-length segments (repeated points) and every segment drawn before (the same two
  end points, either way round, on any layer: the first one drawn keeps it), so that a CAM
  never cuts a line twice; a closed outline on a layer that holds closed outlines only
  (``CUT``) is never split: a duplicate there is an error;
* writes DXF R2010 with ``$INSUNITS`` = 4 (mm), ``$MEASUREMENT`` = 1 (metric), the layers with
  their colours, linetypes and plot flags, ``$EXTMIN``/``$EXTMAX`` (and the limits and the
  initial view) set to the drawing's extents as ezdxf measures them (``ezdxf.bbox``, texts by
  their font), so that a viewer's "zoom extents" shows the drawing and nothing more;
* runs ezdxf's ``audit()`` on the document before writing it: an error there is a
  :class:`~dgpc_cli.errors.DgpcError` (exit 1), and nothing is written;
* makes the bytes deterministic: ezdxf stamps creation dates and random GUIDs into a drawing
  unless its option ``write_fixed_meta_data_for_testing`` is set (it is, meanwhile), and adds a
  CLASS per entity type in the order of a ``set`` of type names (per-process string hashing:
  the CLASSES section is sorted).

Layer convention of the cut sheets (:data:`SHEET_LAYERS`, documented in the README): ``CUT``
(red, 1) closed outlines to cut; ``SCORE`` (blue, 5) open bend/score lines; ``LABEL`` (green,
3) part ids and leaders as TEXT (``nest --label-style text``) or ``ENGRAVE`` (green, 3) the same
as single-stroke polylines for an engraver (``--label-style stroke``,
:mod:`dgpc_cli.io.stroke_font`); ``SHEET_BORDER`` (grey, 8, plotted) the sheet's border, one
closed polyline, only when ``nest --border`` asks for it (a CAM cuts whatever it is given).
Previews (:func:`previews`) are rendered from the DXF bytes themselves by ezdxf's drawing
add-on, in the layers' colours on white, with a title, the sheet's outline (one path, not in
the DXF) and a scale bar.

Text boxes (:func:`text_box`) are estimated without fonts (every character as wide as the text
is high), which is wider than the glyphs of the usual CAD fonts: a label placed by its box
leaves room on every machine.
"""

from __future__ import annotations

import io
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import ezdxf
import numpy as np
from ezdxf import units
from ezdxf.enums import TextEntityAlignment

from ..errors import DgpcError
from .stroke_font import BOX_ABOVE, BOX_BELOW, CHAR_WIDTH, stroke_lines
from .units import nice_length


@dataclass(frozen=True)
class Layer:
    """A DXF layer: ACI ``color``, ``linetype``, whether it is plotted, and whether it holds
    closed outlines only."""

    color: int
    linetype: str = "Continuous"
    plot: bool = True
    closed_only: bool = False


#: The layers a cut sheet may have (the convention of the module docstring); a sheet's DXF
#: has those it draws on.
SHEET_LAYERS = {"SHEET_BORDER": Layer(8, closed_only=True), "CUT": Layer(1, closed_only=True),
                "SCORE": Layer(5), "LABEL": Layer(3), "ENGRAVE": Layer(3)}
#: Points closer than this (mm) are the same point: zero-length and duplicate segments.
QUANTUM_MM = 1e-6
#: Text alignments :class:`Text` may have.
ALIGNMENTS = {"MIDDLE_CENTER": TextEntityAlignment.MIDDLE_CENTER,
              "MIDDLE_LEFT": TextEntityAlignment.MIDDLE_LEFT}


@dataclass(frozen=True)
class Text:
    """A single-line TEXT: its ``at`` point is the middle of the text's centre line
    (``MIDDLE_CENTER``) or of its left end (``MIDDLE_LEFT``); ``rotation`` in degrees."""

    layer: str
    text: str
    at: tuple[float, float]
    height: float
    rotation: float = 0.0
    align: str = "MIDDLE_CENTER"

    def box(self) -> np.ndarray:
        """The corners ``(4, 2)`` of its estimated box (:func:`text_box`)."""
        return text_box(self.text, self.height, self.at, self.rotation, self.align)


def text_box(text: str, height: float, at, rotation: float = 0.0,
             align: str = "MIDDLE_CENTER") -> np.ndarray:
    """Corners ``(4, 2)`` (counter-clockwise) of the box a text of ``height`` mm takes at
    ``at`` turned by ``rotation`` degrees: ``len(text) × CHAR_WIDTH × height`` long, from
    ``BOX_BELOW × height`` below to ``BOX_ABOVE × height`` above its centre line."""
    w = len(text) * CHAR_WIDTH * height
    x0 = -0.5 * w if align == "MIDDLE_CENTER" else 0.0
    local = np.array([[x0, -BOX_BELOW * height], [x0 + w, -BOX_BELOW * height],
                      [x0 + w, BOX_ABOVE * height], [x0, BOX_ABOVE * height]])
    a = np.radians(rotation)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return local @ R.T + np.asarray(at, float)


@dataclass
class Drawing:
    """A drawing in mm: ``layers`` (name → :class:`Layer`), polylines and texts, in the order
    they are drawn."""

    layers: dict[str, Layer]
    polylines: list[tuple[str, np.ndarray, bool]] = field(default_factory=list)
    texts: list[Text] = field(default_factory=list)

    def _layer(self, name: str) -> Layer:
        if name not in self.layers:
            raise ValueError(f"layer {name!r} is not a layer of this drawing")
        return self.layers[name]

    def polyline(self, layer: str, points, closed: bool = False) -> None:
        """A polyline ``points (k, 2)``; closed ones only on a ``closed_only`` layer."""
        if self._layer(layer).closed_only and not closed:
            raise ValueError(f"layer {layer} holds closed outlines only")
        self.polylines.append((layer, np.asarray(points, dtype=float).reshape(-1, 2), closed))

    def line(self, layer: str, a, b) -> None:
        """A segment from ``a`` to ``b``."""
        self.polyline(layer, [a, b])

    def text(self, layer: str, text: str, at, height: float, rotation: float = 0.0,
             align: str = "MIDDLE_CENTER") -> None:
        """A text (see :class:`Text`)."""
        self._layer(layer)
        if align not in ALIGNMENTS:
            raise ValueError(f"alignment {align!r} is not one of {', '.join(ALIGNMENTS)}")
        self.texts.append(Text(layer, text, (float(at[0]), float(at[1])), float(height),
                               float(rotation), align))

    def stroke_text(self, layer: str, text: str, at, height: float, rotation: float = 0.0,
                    align: str = "MIDDLE_CENTER") -> None:
        """A text as single-stroke open polylines (:func:`~.stroke_font.stroke_lines`), placed
        like :meth:`text`."""
        for line in stroke_lines(text, height, at, rotation, align):
            self.polyline(layer, line)

    def extents(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower-left and upper-right corners of everything drawn (text boxes included)."""
        pts = [p for _, p, _ in self.polylines] + [t.box() for t in self.texts]
        allp = np.concatenate(pts) if pts else np.zeros((1, 2))
        return allp.min(axis=0), allp.max(axis=0)

    def to_bytes(self, source: str | Path | None = None) -> bytes:
        """The DXF bytes (see the module); DgpcError naming ``source`` when ezdxf's audit
        finds an error."""
        return _dxf_bytes(self, source)


def _key(p: np.ndarray) -> tuple[int, int]:
    q = np.round(p / QUANTUM_MM)
    return int(q[0]), int(q[1])


def _runs(points: np.ndarray, closed: bool, seen: set, layer: str, source
          ) -> Iterator[tuple[np.ndarray, bool]]:
    """The pieces of one polyline left after dropping repeated points and segments in
    ``seen`` (which gets the kept ones): ``(points, closed)``."""
    keys = [_key(p) for p in points]
    pts, ks = [], []
    for p, k in zip(points, keys, strict=True):
        if not ks or k != ks[-1]:
            pts.append(p)
            ks.append(k)
    if closed and len(ks) > 1 and ks[0] == ks[-1]:
        pts, ks = pts[:-1], ks[:-1]
    if len(ks) < 2 or (closed and len(ks) < 3):
        return
    n = len(ks)
    count = n if closed else n - 1
    segs = [(ks[i], ks[(i + 1) % n]) for i in range(count)]
    fresh = []
    for a, b in segs:
        key = (a, b) if a <= b else (b, a)
        fresh.append(key not in seen)
        seen.add(key)
    if closed and all(fresh):
        yield np.asarray(pts), True
        return
    if closed and layer == "CUT":
        raise DgpcError("internal: a cut outline repeats a line already drawn", source=source)
    if closed:                      # start after a dropped segment, walk around once
        start = fresh.index(False) + 1
        order = [(start + i) % n for i in range(n + 1)]
        seg_fresh = [fresh[(start + i) % n] for i in range(n)]
    else:
        order, seg_fresh = list(range(n)), fresh
    run = [order[0]]
    for i, ok in enumerate(seg_fresh):
        if ok:
            run.append(order[i + 1])
        else:
            if len(run) > 1:
                yield np.asarray([pts[j] for j in run]), False
            run = [order[i + 1]]
    if len(run) > 1:
        yield np.asarray([pts[j] for j in run]), False


def clean(polylines: list[tuple[str, np.ndarray, bool]], source=None
          ) -> list[tuple[str, np.ndarray, bool]]:
    """The polylines without zero-length or repeated segments (see the module)."""
    seen: set = set()
    out = []
    for layer, points, closed in polylines:
        out += [(layer, p, c) for p, c in _runs(points, closed, seen, layer, source)]
    return out


@contextmanager
def fixed_metadata():
    """ezdxf writes dates and random GUIDs unless this option is set; set it meanwhile."""
    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def _sorted_classes(doc) -> None:
    """Make the CLASSES section come out sorted by name whenever ezdxf completes it."""
    section = doc.classes
    complete = section.add_required_classes

    def add_required_classes(dxfversion: str) -> None:
        complete(dxfversion)
        ordered = sorted(section.classes.items())
        section.classes.clear()
        section.classes.update(ordered)

    section.add_required_classes = add_required_classes


def _document(drawing: Drawing, source):
    doc = ezdxf.new("R2010", setup=["linetypes"], units=units.MM)
    doc.header["$INSUNITS"] = units.MM
    doc.header["$MEASUREMENT"] = 1
    for name, layer in drawing.layers.items():
        entry = doc.layers.add(name, color=layer.color, linetype=layer.linetype)
        entry.dxf.plot = int(layer.plot)
    msp = doc.modelspace()
    for layer, points, closed in clean(drawing.polylines, source):
        msp.add_lwpolyline([(float(x), float(y)) for x, y in points], format="xy",
                           close=closed, dxfattribs={"layer": layer})
    for t in drawing.texts:
        msp.add_text(t.text, height=t.height, rotation=t.rotation,
                     dxfattribs={"layer": t.layer}).set_placement(
            t.at, align=ALIGNMENTS[t.align])
    lo, hi = _measured_extents(msp, drawing)
    # ezdxf copies the model space's extents into the header when it writes, unless one of
    # them is the zero vector: set both
    for name, value in (("extmin", lo), ("extmax", hi)):
        msp.dxf.set(name, (float(value[0]), float(value[1]), 0.0))
        doc.header[f"${name.upper()}"] = (float(value[0]), float(value[1]), 0.0)
    msp.dxf.limmin = (float(lo[0]), float(lo[1]))
    msp.dxf.limmax = (float(hi[0]), float(hi[1]))
    size = max(float(hi[1] - lo[1]), float(hi[0] - lo[0]) * 0.75, 1e-9)
    doc.set_modelspace_vport(1.05 * size, center=(float(lo[0] + hi[0]) / 2,
                                                  float(lo[1] + hi[1]) / 2))
    return doc


def _measured_extents(msp, drawing: Drawing) -> tuple[np.ndarray, np.ndarray]:
    """Lower-left and upper-right corners of the model space as ezdxf measures it (texts by
    their font); the drawing's own estimate when there is nothing to measure."""
    from ezdxf import bbox

    box = bbox.extents(msp, fast=False)
    if not box.has_data:
        return drawing.extents()
    return np.array([box.extmin.x, box.extmin.y]), np.array([box.extmax.x, box.extmax.y])


def _dxf_bytes(drawing: Drawing, source) -> bytes:
    with fixed_metadata():                 # creation and writing both stamp dates and GUIDs
        doc = _document(drawing, source)
        auditor = doc.audit()
        if auditor.has_errors:
            first = auditor.errors[0]
            raise DgpcError(f"the DXF does not pass ezdxf's audit ({len(auditor.errors)} "
                            f"errors, first: code {first.code}, {first.message}); nothing "
                            "written", source=source)
        _sorted_classes(doc)
        stream = io.StringIO()
        doc.write(stream)
    return doc.encode(stream.getvalue())


def previews(dxf: bytes, formats: tuple[str, ...] = ("svg", "png"), *,
             title: str | None = None, frame: tuple[float, float] | None = None,
             width: float = 10.0) -> tuple[bytes, ...]:
    """Previews of the DXF bytes ``dxf`` in ``formats`` (svg, png), rendered with ezdxf's
    drawing add-on in the layers' colours on white, ``title`` above, a scale bar in mm under
    the drawing, and with ``frame = (width, height)`` the sheet's outline from the origin (one
    dashed grey path, drawn in the preview only), ``width`` inches wide at 100 dpi; no
    metadata that changes between runs."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.config import BackgroundPolicy, ColorPolicy, Configuration
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    doc = ezdxf.read(io.StringIO(dxf.decode("utf-8", errors="replace")))
    config = Configuration(background_policy=BackgroundPolicy.WHITE,
                           color_policy=ColorPolicy.COLOR)
    meta = {"svg": {"Date": None, "Creator": None}, "png": {"Software": None}}
    out = []
    lo, hi = _preview_limits(doc, frame)
    # the figure as wide as the page, as tall as the drawing needs (within 3 and 10 inches),
    # with bands for the title (0.5 in) and the scale bar (0.6 in)
    inner = min(max(0.98 * width * float(hi[1] - lo[1]) / float(hi[0] - lo[0]), 1.9),
                0.9 * width)
    height = inner + 0.6 + (0.5 if title else 0.1)
    with plt.rc_context({"svg.hashsalt": "dgpc", "svg.fonttype": "path"}):
        fig = plt.figure(figsize=(width, height))
        try:
            ax = fig.add_axes((0.01, 0.6 / height, 0.98, inner / height))
            Frontend(RenderContext(doc), MatplotlibBackend(ax), config=config).draw_layout(
                doc.modelspace(), finalize=True)
            fig.set_size_inches(width, height)       # the add-on resizes it to the drawing
            _preview_frame(ax, lo, hi, frame, fontsize=width)
            if title:
                fig.text(0.01, 0.985, title, ha="left", va="top", fontsize=1.2 * width)
            for fmt in formats:
                buf = io.BytesIO()
                fig.savefig(buf, format=fmt, dpi=100, metadata=meta[fmt])
                out.append(buf.getvalue())
        finally:
            plt.close(fig)
    return tuple(out)


def _preview_limits(doc, frame: tuple[float, float] | None) -> tuple[np.ndarray, np.ndarray]:
    """Corners of what a preview shows: the drawing (``ezdxf.bbox``) and the sheet ``frame``
    from the origin, with a margin of 3 % around."""
    from ezdxf import bbox

    box = bbox.extents(doc.modelspace(), fast=False)
    lo = np.array([box.extmin.x, box.extmin.y]) if box.has_data else np.zeros(2)
    hi = np.array([box.extmax.x, box.extmax.y]) if box.has_data else np.ones(2)
    if frame is not None:
        lo, hi = np.minimum(lo, 0.0), np.maximum(hi, frame)
    pad = 0.03 * float(max(hi - lo))
    return lo - pad, hi + pad


def _preview_frame(ax, lo, hi, frame: tuple[float, float] | None, fontsize: float = 10.0
                   ) -> None:
    """The preview's limits ``lo``, ``hi``, the sheet ``frame`` as one dashed rectangle (the
    DXF has no border unless asked) and a round scale bar under the drawing, in mm."""
    from matplotlib.patches import Rectangle
    from matplotlib.transforms import offset_copy

    if frame is not None:
        ax.add_patch(Rectangle((0.0, 0.0), frame[0], frame[1], fill=False,
                               edgecolor=(0.5, 0.5, 0.5), lw=0.8, linestyle=(0, (6, 4)),
                               gid="sheet-frame"))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box", anchor="N")
    ax.set_axis_off()
    length = nice_length(0.2 * float(hi[0] - lo[0]))
    x0 = lo[0] + 0.01 * float(hi[0] - lo[0])
    fig = ax.get_figure()
    ax.plot([x0, x0 + length], [0.0, 0.0], color="k", lw=2.5, solid_capstyle="butt",
            clip_on=False, gid="scale-bar",
            transform=offset_copy(ax.get_xaxis_transform(), fig, y=-8, units="points"))
    ax.text(x0 + 0.5 * length, 0.0, f"{length:g} mm", ha="center", va="top", fontsize=fontsize,
            clip_on=False,
            transform=offset_copy(ax.get_xaxis_transform(), fig, y=-12, units="points"))
