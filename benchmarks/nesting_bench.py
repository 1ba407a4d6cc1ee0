"""Nesting benchmark (SPEC §6 nest, §10): our sheets' overall utilization beside spyrrow's own
single-strip density on the same parts, in the same run; then the facade sets, time and sheets
of the default fill beside spyrrow sheet by sheet (``--engine spyrrow``) and beside a lower
bound on the sheet count (:mod:`dgpc_cli.nesting.bounds`), in the same run.

Facade sets (built with dgpc in a temporary folder unless given): the Gehry facade's four
patches (samples/projects/gehry-facade.toml: 48 strips) on 6000 × 1250 mm sheets; the demo
wall's 12 strips (pipelines/timber-cladding.mk) on its 6100 × 2500 mm panels with the router's
spacing and margin (8 and 20 mm); the same strips cut into boards (``unfold --stock-length
2.5``: 36 boards since the strips end on the net's edge rows, 39 before; in 6 classes since
the strips of the template are cut at the same template lines, 41 classes before) on
3000 × 1500 mm. Targets (issue "nesting that scales with the facade"): the 48 Gehry parts on
16 sheets in ≤ 10 s; the boards on as few sheets as the bound allows, which rules out the
issue's 7 for today's boards: every board longer than half the sheet crosses its centre line at
its full width, and those sections add up, with the spacing, to more than seven sheets' inner
height (:mod:`dgpc_cli.nesting.bounds`).

Sample: the flat parts of a revolution-isometric net — a full-ring catenoid meridian net
(21 × 25, 24 strips) bent by Minding's bending (λ = 0.7), planarized and unfolded, at scale 100
(strips ≈ 527 × 79 mm). Sheets 1650 × 800 mm by default, margin 10, spacing 3, rotations
0/180. spyrrow packs all parts into one strip whose height is the sheet's inner height (same
rotations and spacing), seed 0, one worker. Ratio = our overall utilization (every sheet
counted in full) / spyrrow's strip density.

    python benchmarks/nesting_bench.py [--sheet 1650x800] [--time-limit 10]
        [--gehry FLAT FLAT FLAT FLAT] [--wall FLAT] [--boards FLAT] [--sheet-time 3]
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
from dgpc_cli.nesting.blf import Sheet
from dgpc_cli.nesting.geometry import CLEARANCE_MM, prepare_parts, transform
from dgpc_cli.nesting.strip import strip_density
from dgpc_cli.stages.nest import nest_parts, parse_sheet
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


ROOT = Path(__file__).resolve().parent.parent


def gehry_flats(folder: Path) -> list[Path]:
    """The four Gehry patches' flat artifacts (as in samples/projects/gehry-facade.toml)."""
    _dgpc("init", "--surface", "revolution", "--profile", ROOT / "samples/profiles/gehry.csv",
          "--rows", 21, "--cols", 13, "--span", 90, "--units", "m", "-o", folder / "base")
    out = []
    for k in range(1, 5):
        _dgpc("optimize", folder / "base", "--mode", "isometric", "--handles",
              ROOT / f"samples/handles/gehry-{k}-21x13.json", "--steps", 5, "--max-strain",
              3e-4, "--gpc-tol", 1e-4, "-o", folder / f"facade-{k}")
        _dgpc("planarize-strips", folder / f"facade-{k}", "-o", folder / f"strips-{k}")
        _dgpc("unfold", folder / f"strips-{k}", "-o", folder / f"facade-{k}-flat")
        out.append(folder / f"facade-{k}-flat")
    return out


def wall_flats(folder: Path) -> tuple[Path, Path]:
    """The demo wall's strips (pipelines/timber-cladding.mk) and the same strips cut into
    boards 2.5 m long."""
    _dgpc("init", "--surface", "revolution", "--profile", ROOT / "samples/profiles/wall.csv",
          "--rows", 21, "--cols", 13, "--span", 60, "--units", "m", "-o", folder / "base")
    _dgpc("optimize", folder / "base", "--mode", "isometric", "--handles",
          ROOT / "samples/handles/wall-21x13.json", "--steps", 5, "--max-strain", 3e-4,
          "--gpc-tol", 1e-4, "-o", folder / "wall")
    _dgpc("planarize-strips", folder / "wall", "-o", folder / "strips")
    _dgpc("unfold", folder / "strips", "-o", folder / "flat")
    _dgpc("unfold", folder / "strips", "--stock-length", 2.5, "-o", folder / "boards")
    return folder / "flat", folder / "boards"


def facade_set(name: str, stems: list[Path], sheet: Sheet, sheet_time: float) -> None:
    """Time and sheets of the default fill and of spyrrow sheet by sheet on one set, beside a
    lower bound on the sheet count."""
    from dgpc_cli.io.units import mm_per_unit
    from dgpc_cli.nesting.bounds import sheet_lower_bounds
    from dgpc_cli.stages.combine_flats import combine_flats, flat_tags

    flats = [read_flat(s) for s in stems]
    records = flats[0].parts if len(flats) == 1 else \
        combine_flats(list(zip(flat_tags(stems), flats, strict=True))).parts
    rotations = [0.0, 180.0]
    rows = {}
    for engine in ("fill", "spyrrow"):
        t0 = time.perf_counter()
        result = nest_parts(records, sheet, rotations, units=flats[0].units, engine=engine,
                            time_limit=sheet_time)
        rows[engine] = (result.sheet_count, time.perf_counter() - t0, result.engine_info)
    bound = sheet_lower_bounds(prepare_parts(records, mm_per_unit(flats[0].units)),
                               sheet.width, sheet.height, sheet.margin, sheet.spacing,
                               rotations)
    (n_f, t_f, info), (n_s, t_s, _) = rows["fill"], rows["spyrrow"]
    print(f"{name}: {len(records)} parts, sheet {sheet.width:g}x{sheet.height:g} mm, margin "
          f"{sheet.margin:g}, spacing {sheet.spacing:g}")
    print(f"  fill (default)      {n_f} sheets  {t_f:6.1f} s  ({info.get('no_fit_polygons')} "
          f"no-fit polygons, {info.get('shapes')} shapes, {info.get('pairs')} pairs)")
    print(f"  spyrrow per sheet   {n_s} sheets  {t_s:6.1f} s  (budget {sheet_time:g} s a sheet)")
    print(f"  lower bound         {bound['sheets']} sheets  (area {bound['area']}, centre "
          f"line {bound['centre_line']})")
    above = n_f - bound["sheets"]
    print(f"  ratio fill/spyrrow  sheets {n_f / n_s:.3f}, time {t_f / t_s:.3f}; fill "
          + ("at the bound" if above <= 0 else f"{above} above the bound"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sheet", default="1650x800")
    ap.add_argument("--margin", type=float, default=10.0)
    ap.add_argument("--spacing", type=float, default=3.0)
    ap.add_argument("--scale", type=float, default=100.0)
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--gehry", nargs=4, type=Path, metavar="FLAT",
                    help="the four Gehry patches' flat artifacts (else built, minutes)")
    ap.add_argument("--wall", type=Path, metavar="FLAT",
                    help="the demo wall's strips (else built, with the boards)")
    ap.add_argument("--boards", type=Path, metavar="FLAT",
                    help="the demo wall's boards (else built, with the strips)")
    ap.add_argument("--sheet-time", type=float, default=3.0,
                    help="spyrrow's budget per sheet (s) on the facade sets")
    args = ap.parse_args()
    single_strip(args)
    with tempfile.TemporaryDirectory() as tmp:
        gehry = args.gehry or gehry_flats(Path(tmp))
        facade_set("Gehry facade, 4 patches", gehry, Sheet(6000, 1250, 10, 3), args.sheet_time)
    with tempfile.TemporaryDirectory() as tmp:
        wall, boards = (args.wall, args.boards) if args.wall and args.boards else \
            wall_flats(Path(tmp))
        facade_set("demo wall (router panels)", [wall], Sheet(6100, 2500, 20, 8),
                   args.sheet_time)
        facade_set("demo wall in 2.5 m boards", [boards], Sheet(3000, 1500, 10, 3),
                   args.sheet_time)


def single_strip(args) -> None:
    """The catenoid sample beside spyrrow's single strip."""
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
