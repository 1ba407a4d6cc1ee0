"""Deterministic generator of the inputs of every pipeline (``pipelines/*.mk``).

Run from the repository root: ``.venv/bin/python samples/generate.py``. It writes into
``samples/`` and is idempotent and byte-deterministic (``repr`` floats, fixed parameters):

- ``profiles/gehry.csv``: a Gehry-type profile with a cylindrical section (paper Fig. 1, 16).
- ``profiles/wall.csv``: the gently waving profile behind the timber wall (paper Fig. 2, 18).
- ``handles/gehry-K-MxN.json`` (K = 1..4), ``handles/gehry-sweep-KK-MxN.json`` (a design
  sweep of the first patch, KK = 01..12), ``handles/wall-MxN.json`` and
  ``handles/gallery-NAME-MxN.json`` (six surfaces of revolution, paper Fig. 19): handles of
  ``dgpc optimize --mode isometric`` as a designer drags them on the meridian net that
  ``dgpc init --surface revolution --profile PROFILE --rows M --cols N --span SPAN`` makes:
  two corners of one end row held, the two corners of the other end row pushed away from the
  axis and towards it (``HANDLE_SETS``: a fraction of their radius). The nets this twists are
  freeform (their parallels are no circles) and stay isometric to the surface of revolution
  within 3e-4 (one mold for the four Gehry-type patches).
- ``meshes/felt.obj``: a nearly developable bent sheet (paper Fig. 8).
- ``meshes/gridshell.obj``: a doubly curved height-field patch for the gridshell (Fig. 14).

``--size MxN`` adds handle files of another net size (the pipelines' ROWS/COLS); the sizes in
``SIZES`` are always written. ``--check`` writes nothing and exits 1 naming every committed
file that the generator would change (the tests run it).

A committed file counts as the generator's output when its bytes are equal, or when its text
is equal once every number is masked and each number agrees within ``ROUNDING`` of the file's
largest one: numpy picks its exp/sin/cos kernels by CPU (AVX-512 machines use other kernels,
which round differently in the last bit), so a file written on another machine may differ by
an ulp. Such a file is kept as it is, so the committed bytes stay the pipelines' input.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from dgpc_cli.io.mesh import write_mesh_obj  # noqa: E402
from dgpc_cli.surfaces.bent_sheet import bent_sheet  # noqa: E402
from dgpc_cli.surfaces.profiles import builtin_profile, read_profile_csv  # noqa: E402
from dgpc_cli.surfaces.revolution import revolution_net  # noqa: E402

HERE = Path(__file__).resolve().parent

#: Net sizes (rows, cols) whose handle files are committed: the pipelines' defaults and the
#: small versions of the golden tests.
SIZES = [(21, 13), (9, 7)]
#: Corners and row middles of a net by name: (row, column) with -1 = the last, None = middle.
CORNERS = {"bottom-left": (0, 0), "bottom-right": (0, -1), "top-left": (-1, 0),
           "top-right": (-1, -1)}


def twist(end: str, fraction: float) -> dict:
    """A designer's drag: the corners of the other end row held, the two corners of row ``end``
    ("top" or "bottom") pushed away from the axis and towards it by ``fraction`` of their
    radius."""
    other = "bottom" if end == "top" else "top"
    return {f"{other}-left": 0.0, f"{other}-right": 0.0, f"{end}-left": fraction,
            f"{end}-right": -fraction}


#: The twists of the design sweep of the first Gehry-type patch (fractions of the radius).
SWEEP = [round(0.02 + 0.005 * k, 3) for k in range(12)]
#: Handle sets: name -> (profile: a CSV of samples/profiles or a built-in name, ``--span`` of
#: the pipeline's `dgpc init` in degrees (the .mk files use the same values), drag: corner ->
#: radial move as a fraction of its radius, 0 = held). The four Gehry-type patches twist their
#: top or bottom row (one surface of revolution, one mold for all four), the timber wall its
#: bottom row; the gallery twists six surfaces of revolution (paper Fig. 19).
HANDLE_SETS = {
    "gehry-1": ("gehry.csv", 90.0, twist("top", 0.07)),
    "gehry-2": ("gehry.csv", 90.0, twist("top", -0.06)),
    "gehry-3": ("gehry.csv", 90.0, twist("bottom", -0.035)),
    "gehry-4": ("gehry.csv", 90.0, twist("bottom", 0.035)),
    "wall": ("wall.csv", 60.0, twist("bottom", 0.05)),
    "gallery-sphere-zone": ("sphere-zone", 90.0, twist("top", 0.08)),
    "gallery-cylinder": ("cylinder", 90.0, twist("top", 0.05)),
    "gallery-catenoid": ("catenoid", 90.0, twist("top", 0.06)),
    "gallery-sphere": ("sphere", 90.0, twist("top", 0.04)),
    "gallery-bowling-pin": ("bowling-pin", 90.0, twist("top", 0.3)),
    "gallery-wall": ("wall.csv", 60.0, twist("top", 0.08)),
    # a design study of the first Gehry-type patch (samples/projects/gehry-sweep.toml): its
    # top row twisted by 2 % to 7.5 % of the radius, in 12 steps of 0.5 %
    **{f"gehry-sweep-{k:02d}": ("gehry.csv", 90.0, twist("top", SWEEP[k - 1]))
       for k in range(1, len(SWEEP) + 1)},
}


#: With ``--check``: the files that differ (nothing is written); else None.
_CHECK: list[Path] | None = None
#: Numbers of a file that agree within this fraction of its largest number are the same
#: (last-bit differences of the CPU's math kernels; see the module docstring).
ROUNDING = 1e-12
_NUMBER = re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


def same_up_to_rounding(old: bytes, new: bytes, rounding: float = ROUNDING) -> bool:
    """True when ``old`` and ``new`` are equal text once numbers are masked and every number
    agrees within ``rounding`` × the largest number of ``new``."""
    if _NUMBER.sub(b"#", old) != _NUMBER.sub(b"#", new):
        return False
    a = np.array([float(t) for t in _NUMBER.findall(old)])
    b = np.array([float(t) for t in _NUMBER.findall(new)])
    if a.size == 0:
        return True
    return bool(np.all(np.abs(a - b) <= rounding * max(np.abs(b).max(), 1e-300)))


def write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` unless the file already holds it, up to rounding (idempotent, keeps
    mtimes and the committed bytes)."""
    if path.exists() and same_up_to_rounding(path.read_bytes(), data):
        return
    if _CHECK is not None:
        _CHECK.append(path)
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    print(f"wrote {path.relative_to(ROOT)}")


def profile_csv(r: np.ndarray, h: np.ndarray) -> bytes:
    lines = ["r,h"] + [f"{a!r},{b!r}" for a, b in zip(r.tolist(), h.tolist(), strict=True)]
    return ("\n".join(lines) + "\n").encode()


def gehry_profile(samples: int = 1201):
    """r = 3 for h ∈ [0, 2], then a C¹ S-curve down to r = 2 at h = 5."""
    h = np.linspace(0.0, 5.0, samples)
    r = np.where(h <= 2.0, 3.0, 2.5 + 0.5 * np.cos(np.pi * (h - 2.0) / 3.0))
    return r, h


def wall_profile(samples: int = 1201):
    """r = 4 + 0.25 sin(0.8 h), h ∈ [0, 6]: nearly a cylinder, a gently waving wall."""
    h = np.linspace(0.0, 6.0, samples)
    return 4.0 + 0.25 * np.sin(0.8 * h), h


def handles_json(profile, m: int, n: int, span: float, drag: dict) -> bytes:
    """The handles of ``drag`` (see ``HANDLE_SETS``) on the m×n meridian net of ``profile``:
    each corner moved radially (away from the axis for a positive fraction) in its row's
    plane."""
    f = revolution_net(profile, m, n, span_deg=span)
    handles = []
    for corner, fraction in drag.items():
        u, v = (k % size for k, size in zip(CORNERS[corner], (m, n), strict=True))
        p = f[u, v]
        radial = np.array([p[0], p[1], 0.0])
        handles.append({"index": [u, v], "target": (p + fraction * radial).tolist()})
    return (json.dumps({"handles": handles}, indent=1, sort_keys=True) + "\n").encode()


def gridshell_patch(length: float = 10.0, width: float = 8.0, resolution: float = 0.2):
    """A doubly curved height field: a dome on a wave, ``(vertices, faces)``."""
    nx, ny = int(round(length / resolution)) + 1, int(round(width / resolution)) + 1
    x, y = np.meshgrid(np.linspace(0, length, nx), np.linspace(0, width, ny), indexing="ij")
    z = (1.5 * np.exp(-((x - 5.0) ** 2 + (y - 4.0) ** 2) / 16.0)
         + 0.3 * np.sin(0.6 * x) * np.cos(0.4 * y))
    vid = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return np.stack([x, y, z], -1).reshape(-1, 3), faces


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", action="append", default=[], metavar="MxN",
                    help="also write handle files for an MxN net (repeatable)")
    ap.add_argument("--check", action="store_true",
                    help="write nothing; exit 1 naming the files that would change")
    args = ap.parse_args(argv)
    global _CHECK
    _CHECK = [] if args.check else None
    extra = [tuple(int(k) for k in s.lower().split("x")) for s in args.size]

    csvs = {name: HERE / "profiles" / name for name in ("gehry.csv", "wall.csv")}
    write_bytes(csvs["gehry.csv"], profile_csv(*gehry_profile()))
    write_bytes(csvs["wall.csv"], profile_csv(*wall_profile()))
    for name, (source, span, drag) in HANDLE_SETS.items():
        # the handles are computed from the CSV as written (what `dgpc init` reads back)
        profile = (read_profile_csv(csvs[source]) if source in csvs
                   else builtin_profile(source))
        for m, n in sorted(set(SIZES) | set(extra)):
            write_bytes(HERE / "handles" / f"{name}-{m}x{n}.json",
                        handles_json(profile, m, n, span, drag))
    V, F = bent_sheet(10.0, 6.0, bump=1e-4, resolution=0.1)
    write_bytes(HERE / "meshes" / "felt.obj", write_mesh_obj("felt.obj", V, F))
    V, F = gridshell_patch()
    write_bytes(HERE / "meshes" / "gridshell.obj", write_mesh_obj("gridshell.obj", V, F))
    if _CHECK:
        for path in _CHECK:
            print(f"differs: {path.relative_to(ROOT)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
