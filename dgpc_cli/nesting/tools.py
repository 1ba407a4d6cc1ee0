"""The cutting tools of ``nest --tool`` and the sheet spacing and margin they need (mm).

A cutter removes a band of material as wide as its cut (a laser's or a water jet's kerf, a
router bit's diameter) and follows each outline on its outside, so two neighbouring parts need
at least one cut width between them; the clearance on top keeps a web that holds the sheet
together and leaves room for the tool path's lead-in. The margin keeps the parts off the
sheet's edge, clamps and hold-downs (a router), the slats' edge of a water-jet bed.

=========  ==================  ==========  =================================================
tool       cut width (mm)      clearance   margin
=========  ==================  ==========  =================================================
laser      kerf 0.2            2.8         10   (spacing 3 mm: the laser's usual setting)
router     bit diameter 6      2           20   (spacing 8 mm: the bit and a web of 2 mm)
waterjet   kerf 1              1           25   (spacing 2 mm)
=========  ==================  ==========  =================================================

``--kerf``/``--tool-diameter`` set the cut width (the spacing follows: width + clearance);
``--spacing`` and ``--margin`` given explicitly win, but a spacing below the cut width is
refused (the tool would cut into the neighbouring part).

Plausible values (:class:`~dgpc_cli.io.length.Span`; a plain number outside is a usage error
naming both readings, ``--tool-diameter 0.006`` being a 0.006 mm bit where 6 mm was meant):
a router bit 0.5–50 mm (:data:`BIT_SPAN`), a kerf 0.02–10 mm (:data:`KERF_SPAN`), a margin 0
or at least 1 mm (:data:`MARGIN_SPAN`).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..io.length import Span

__all__ = ["BIT_SPAN", "KERF_SPAN", "MARGIN_SPAN", "TOOLS", "Tool", "ToolSettings",
           "resolve_tool"]

#: A router bit's diameter (mm): from the finest engraving bits to the largest cutters.
BIT_SPAN = Span(0.5, 50.0, "router bit")
#: A laser's or a water jet's kerf (mm): a fine laser's 0.02 mm to a coarse water jet's.
KERF_SPAN = Span(0.02, 10.0, "kerf")
#: A sheet's margin (mm): 0 (parts to the edge) or at least 1 mm.
MARGIN_SPAN = Span(1.0, None, "margin", zero_ok=True)


@dataclass(frozen=True)
class Tool:
    """A cutting tool: its usual cut width, the clearance beside it and the sheet margin (mm);
    ``width_option`` the option that sets its cut width."""

    cut_width: float
    clearance: float
    margin: float
    width_option: str


TOOLS = {"laser": Tool(0.2, 2.8, 10.0, "--kerf"),
         "router": Tool(6.0, 2.0, 20.0, "--tool-diameter"),
         "waterjet": Tool(1.0, 1.0, 25.0, "--kerf")}


@dataclass(frozen=True)
class ToolSettings:
    """What ``nest`` cuts with and the spacing and margin it nests to (mm)."""

    tool: str
    cut_width: float
    spacing: float
    margin: float

    def record(self) -> dict:
        """The artifact's record: the tool, its cut width under its option's name."""
        key = "tool_diameter" if TOOLS[self.tool].width_option == "--tool-diameter" else "kerf"
        return {"tool": self.tool, key: self.cut_width}


def resolve_tool(tool: str | None, kerf: float | None, diameter: float | None,
                 spacing: float | None, margin: float | None) -> ToolSettings:
    """The settings of ``--tool`` (default: router with ``--tool-diameter``, else laser), its
    cut width (``--kerf`` or ``--tool-diameter``) and the spacing and margin, defaults filled
    in; ValueError ``(option, message)`` on a contradiction."""
    if tool is None:
        tool = "router" if diameter is not None else "laser"
    spec = TOOLS[tool]
    if diameter is not None and spec.width_option != "--tool-diameter":
        raise ValueError("--tool-diameter", f"a {tool} has no tool diameter; give its cut "
                                            "width as --kerf")
    if kerf is not None and spec.width_option != "--kerf":
        raise ValueError("--kerf", f"a {tool}'s cut width is its --tool-diameter")
    width = next((w for w in (kerf, diameter) if w is not None), spec.cut_width)
    if spacing is None:
        spacing = width + spec.clearance
    elif spacing < width:
        raise ValueError("--spacing", f"{spacing:g} mm is less than the {tool}'s cut width "
                                      f"{width:g} mm ({spec.width_option}): the tool would cut "
                                      "into the neighbouring part")
    return ToolSettings(tool, width, spacing, spec.margin if margin is None else margin)
