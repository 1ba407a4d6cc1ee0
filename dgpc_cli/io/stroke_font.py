"""Single-stroke lettering for engraving (``nest --label-style stroke``): a text as open
polylines that an engraver or pen follows once, from the Hershey simplex font (``futural``) of
the Hershey-Fonts package, not outlines of a filled font.

:func:`stroke_lines` lays the glyphs out like a TEXT of the same height and alignment
(:class:`dgpc_cli.io.dxf.Text`): the cap height is the text height, ``MIDDLE_CENTER`` centres
the lettering on its point, ``MIDDLE_LEFT`` starts it there, the middle of the cap height on
the point's line; then it is shrunk, where needed, to lie inside the text's estimated box
(:func:`dgpc_cli.io.dxf.text_box`), so that a label placed by its box stays clear of the cut
and score lines whatever its letters.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["BOX_ABOVE", "BOX_BELOW", "CHAR_WIDTH", "FONT", "stroke_lines"]

#: The Hershey font of the labels: simplex sans-serif, one stroke per line of a letter.
FONT = "futural"
#: Text box of a middle-centred text of height h (:func:`dgpc_cli.io.dxf.text_box`, and the box
#: the strokes are fitted into): width per character, depth below and height above the
#: alignment point, in units of h.
CHAR_WIDTH, BOX_BELOW, BOX_ABOVE = 1.0, 0.8, 0.6


@lru_cache(maxsize=1)
def _font():
    from HersheyFonts import HersheyFonts

    font = HersheyFonts()
    font.load_default_font(FONT)
    return font


def _glyph_strokes(text: str) -> tuple[list[np.ndarray], float, float]:
    """The strokes of ``text`` in font units (y up, baseline at 0), its cap height and its
    advance width."""
    font = _font()
    opts = font.render_options
    cap, base = float(opts["cap_line"]), float(opts["base_line"])
    strokes, x = [], 0.0
    for glyph in font.glyphs_for_text(text):
        for stroke in glyph.strokes:
            pts = np.array([(x + px - glyph.left_offset, base - py) for px, py in stroke],
                           float)
            if len(pts) >= 2:
                strokes.append(pts)
        x += float(glyph.char_width)
    return strokes, base - cap, x


def stroke_lines(text: str, height: float, at, rotation: float = 0.0,
                 align: str = "MIDDLE_CENTER") -> list[np.ndarray]:
    """Open polylines ``(k, 2)`` in drawing units lettering ``text`` (see the module)."""
    strokes, cap, _ = _glyph_strokes(text)
    if not strokes:
        return []
    k = height / cap                                   # font units to drawing units
    allp = np.concatenate(strokes)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    # the ink's middle (MIDDLE_CENTER) or left end (MIDDLE_LEFT) at the origin, the middle of
    # the cap height on the x axis
    x0 = 0.5 * (lo[0] + hi[0]) if align == "MIDDLE_CENTER" else lo[0]
    local = [(s - [x0, 0.5 * cap]) * k for s in strokes]
    lo, hi = (lo - [x0, 0.5 * cap]) * k, (hi - [x0, 0.5 * cap]) * k
    # shrunk about the origin to the estimated box (its width, its depth and its height)
    width = len(text) * CHAR_WIDTH * height
    shrink = min(1.0, width / max(hi[0] - lo[0], 1e-12),
                 BOX_BELOW * height / max(-lo[1], 1e-12), BOX_ABOVE * height / max(hi[1], 1e-12))
    a = np.radians(rotation)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return [(shrink * s) @ R.T + np.asarray(at, float) for s in local]
