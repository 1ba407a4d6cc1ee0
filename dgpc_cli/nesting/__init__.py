"""Nesting flat parts on cut sheets (SPEC §6 nest): geometry and no-fit polygons
(:mod:`.geometry`), pairing (:mod:`.pairs`), the deterministic fill (:mod:`.blf`), spyrrow as a
strip packer (:mod:`.strip`), DXF sheets, previews and the mold map (:mod:`.drawing`)."""
