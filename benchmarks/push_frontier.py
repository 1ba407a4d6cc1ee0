"""What an isometric push between held corners costs: strain against crease, by net size and
by weights (issue "drags that feel right"; not part of ``make bench``: a study of a few minutes).

The case: the meridian net of the built-in half sphere (radius 5, 120° wide; ``--profile``
another built-in profile), the two corners of row 0 held and its middle pushed 5 % of the radius
towards the axis, ``--mode isometric``, 5 steps (as ``tests/test_freeform_drags.py`` builds it).
Printed, one line per run: the state ``optimize`` would report, the largest strain against the
input (paper §6.1), the largest third difference across the geodesics (``crease_max``, mean
edges), the gpc angle defect (rad).

1. By size (m = n): the mode's weights, and without the crease guard.
2. At 21×21, by weights: (6) weighed 0.3, 1, 3 against the edge lengths; the guard at 1, 1e-3,
   off, or the displacement's third differences (``displacement_smoothness``) instead; with and
   without the relaxation of the drag's smoothness. Then the best strain at crease ≤ 0.05, with
   and without the gpc defect within ``--gpc-tol``.
3. With ``--fine``: the 41×41 net (about a minute) and the same deformation read on the 21×21
   net (every other vertex of the 41×41 result): the turning of row 0 and of the pushed column,
   against the start net's. Gauss's theorem at work: where row 0 flattens the meridian across it
   must curl (their normal curvatures multiply to K), and a 21×21 net's edges are too long to
   follow that without strain or a crease.
"""

from __future__ import annotations

import argparse
import itertools
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from dgpc_cli.fitting.modes import RELAX, SOFT, mode_weights
from dgpc_cli.fitting.optimize import judge, optimize_net
from dgpc_cli.io.net import read_net
from dgpc_cli.metrics.crease import crease
from dgpc_cli.metrics.residuals import gpc_angle_defect
from dgpc_cli.metrics.strain import strain
from dgpc_cli.tolerances import tol as TOL

PUSH, STEPS, CREASE, PAPER_STRAIN = 0.05, 5, 0.05, 4e-5


def sphere_net(d: Path, m: int, profile: str = "sphere") -> np.ndarray:
    stem = d / f"{profile}{m}"
    subprocess.run([sys.executable, "-m", "dgpc_cli.cli.main", "-q", "init", "--surface",
                    "revolution", "--profile", profile, "--rows", str(m), "--cols", str(m),
                    "--span", "120", "-o", str(stem), "--force"],
                   check=True, capture_output=True)
    return read_net(stem).f


def push(f: np.ndarray, overrides=(), relax: bool = True) -> tuple[dict, np.ndarray]:
    """The push of the module docstring on the net ``f``: its figures and the net."""
    n = f.shape[1]
    ids = np.array([0, n - 1, n // 2])
    targets = f.reshape(-1, 3)[ids].copy()
    p = targets[2]
    targets[2] = p - PUSH * np.array([p[0], p[1], 0.0])
    outcome = optimize_net(f, mode_weights("isometric", list(overrides)), handle_ids=ids,
                           handle_targets=targets, soft=SOFT["isometric"], steps=STEPS,
                           relax=RELAX["isometric"] if relax else None, gpc_tol=TOL.gpc_tol,
                           max_strain=TOL.max_strain)
    state, _ = judge(outcome, f, mode="isometric")
    g = outcome.f
    return {"state": state, "strain": float(np.nanmax(strain(g, f)[0])),
            "crease": float(crease(g).max()),
            "gpc": float(np.nanmax(gpc_angle_defect(g)))}, g


def line(label: str, r: dict) -> str:
    return (f"| {label} | {r['state']} | {r['strain']:.3g} | {r['crease']:.3f} | "
            f"{r['gpc']:.2g} |")


HEADER = "| run | state | strain max | crease max | gpc defect |\n|---|---|---|---|---|"


def turning(g: np.ndarray, axis: int) -> np.ndarray:
    """Turning angles (degrees) between consecutive edges along ``axis`` (0: the meridians,
    1: the rows) at the inner vertices."""
    e = np.diff(g, axis=axis)
    e = e / np.linalg.norm(e, axis=-1, keepdims=True)
    a, b = (e[:-1], e[1:]) if axis == 0 else (e[:, :-1], e[:, 1:])
    return np.degrees(np.arccos(np.clip((a * b).sum(-1), -1.0, 1.0)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fine", action="store_true", help="also the 41×41 net")
    parser.add_argument("--profile", default="sphere",
                        help="built-in profile (the issue's sphere-zone: -45° to 45°)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        print("1. by size\n" + HEADER)
        for m in (21, 25, 31):
            f = sphere_net(d, m, args.profile)
            for label, over in (("mode", ()), ("no guard", ("crease_guard=0",))):
                print(line(f"{m}×{m} {label}", push(f, over)[0]), flush=True)

        print("\n2. 21×21 by weights\n" + HEADER)
        f = sphere_net(d, 21, args.profile)
        guards = {"guard 1": ("crease_guard=1",), "guard 1e-3": ("crease_guard=1e-3",),
                  "no guard": ("crease_guard=0",),
                  "smoothness 1e-4": ("crease_guard=0", "displacement_smoothness=1e-4")}
        runs = []
        for gpc, (name, over), relax in itertools.product((0.3, 1, 3), guards.items(),
                                                           (True, False)):
            r, _ = push(f, (f"gpc={gpc}", *over), relax)
            runs.append(r)
            print(line(f"gpc {gpc}, {name}, {'relaxed' if relax else 'not relaxed'}", r),
                  flush=True)
        smooth = [r for r in runs if r["crease"] <= CREASE]
        within = [r for r in smooth if r["gpc"] <= TOL.gpc_tol]
        for label, pool in (("crease ≤ 0.05", smooth), ("crease ≤ 0.05, gpc ≤ tol", within),
                            ("any crease", runs)):
            best = min((r["strain"] for r in pool), default=float("nan"))
            print(f"best strain, {label}: {best:.3g} (paper: {PAPER_STRAIN:g})")

        if args.fine:
            print("\n3. 41×41, and its deformation read on the 21×21 net\n" + HEADER)
            f41 = sphere_net(d, 41, args.profile)
            r41, g41 = push(f41)
            print(line("41×41 mode", r41))
            g = g41[::2, ::2]
            print(line("41×41 result, every other vertex",
                       {"state": "-", "strain": float(np.nanmax(strain(g, f)[0])),
                        "crease": float(crease(g).max()),
                        "gpc": float(np.nanmax(gpc_angle_defect(g)))}))
            row, col = turning(g41, 1)[0], turning(g41, 0)[0]
            row0, col0 = turning(f41, 1)[0], turning(f41, 0)[0]
            mid = g41.shape[1] // 2
            print(f"41×41: row 0 turns {row[mid - 1]:.2f}° at the pushed vertex "
                  f"({row0[mid - 1]:.2f}° before), up to {row.max():.2f}° near the corners; "
                  f"the pushed meridian turns {col[mid]:.2f}° at row 1 ({col0[mid]:.2f}° "
                  f"before)")


if __name__ == "__main__":
    main()
