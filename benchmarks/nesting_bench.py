"""Nesting benchmark (SPEC §6 nest, §10): our sheets' overall utilization beside spyrrow's own
single-strip density on the same parts, in the same run.

Sample: the flat parts of a revolution-isometric net — a full-ring catenoid meridian net
(21 × 25, 24 strips) bent by Minding's bending (λ = 0.7), planarized and unfolded, at scale 100
(strips ≈ 527 × 79 mm). Sheets 1650 × 800 mm by default, margin 10, spacing 3, rotations
0/180. spyrrow packs all parts into one strip whose height is the sheet's inner height (same
rotations and spacing), seed 0, one worker. Ratio = our overall utilization (every sheet
counted in full) / spyrrow's strip density.

    python benchmarks/nesting_bench.py [--sheet 1650x800] [--time-limit 10]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from click.testing import CliRunner

from dgpc_cli.cli.main import cli
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.nesting.geometry import CLEARANCE_MM, prepare_parts, transform
from dgpc_cli.nesting.strip import strip_density
from dgpc_cli.stages.nest import parse_sheet
from dgpc_cli.surfaces.minding import minding_bend


def _dgpc(*args) -> None:
    result = CliRunner().invoke(cli, ["-q", *map(str, args)])
    if result.exit_code != 0:
        raise SystemExit(f"dgpc {' '.join(map(str, args))}: {result.stderr.strip()}")


def sample_flat(folder: Path) -> Path:
    """The sample's flat artifact in ``folder``."""
    _dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 21, "--cols",
          25, "--span", 360, "-o", folder / "cat")
    write_net(folder / "iso", NetArtifact(f=minding_bend(read_net(folder / "cat").f, 0.7)))
    _dgpc("planarize-strips", folder / "iso", "-o", folder / "strips")
    _dgpc("unfold", folder / "strips", "-o", folder / "flat")
    return folder / "flat"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sheet", default="1650x800")
    ap.add_argument("--margin", type=float, default=10.0)
    ap.add_argument("--spacing", type=float, default=3.0)
    ap.add_argument("--scale", type=float, default=100.0)
    ap.add_argument("--time-limit", type=float, default=10.0)
    args = ap.parse_args()
    width, height = parse_sheet(args.sheet)
    with tempfile.TemporaryDirectory() as tmp:
        flat = sample_flat(Path(tmp))
        t0 = time.perf_counter()
        _dgpc("nest", flat, "--sheet", args.sheet, "--margin", args.margin, "--spacing",
              args.spacing, "--scale", args.scale, "-o", Path(tmp) / "sheets")
        t_nest = time.perf_counter() - t0
        sheets = read_sheets(Path(tmp) / "sheets")
        parts = prepare_parts(read_flat(flat).parts, args.scale)
    ours = sheets.data["utilization"]["overall"]
    # the last sheet up to the right-most part (+ margin): the rest is a reusable remnant
    n = sheets.data["sheet_count"]
    reach = max(max(x for x, _ in _placed_outline(parts, p))
                for p in sheets.data["placements"] if p["sheet"] == n - 1) + args.margin
    trimmed = sum(p.area for p in parts) / (width * height * (n - 1) + height * reach)
    inner_h = height - 2 * (args.margin + CLEARANCE_MM)
    t0 = time.perf_counter()
    density, length = strip_density(parts, inner_h, [0.0, 180.0], args.spacing,
                                    args.time_limit, seed=0)
    t_sp = time.perf_counter() - t0
    per = ", ".join(f"{u:.3f}" for u in sheets.data["utilization"]["per_sheet"])
    print(f"nesting: {len(parts)} parts, sheet {width:g}x{height:g} mm")
    print(f"  dgpc nest (fill)   {sheets.data['sheet_count']} sheets, utilization per sheet "
          f"[{per}], overall {ours:.3f}  ({t_nest:.1f} s)")
    print(f"  spyrrow one strip  height {inner_h:.1f} mm, length {length:.1f} mm, density "
          f"{density:.3f}  ({t_sp:.1f} s budget {args.time_limit:g} s)")
    print(f"  ratio ours/spyrrow {ours / density:.3f}  (done-means: >= 0.90); with the last "
          f"sheet trimmed to its used length: {trimmed:.3f}, ratio {trimmed / density:.3f}")


def _placed_outline(parts, placement):
    part = next(p for p in parts if p.id == placement["part"])
    return transform(part.outline, placement["rotation"], placement["translation"]).tolist()


if __name__ == "__main__":
    main()
