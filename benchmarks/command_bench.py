"""``make bench``: what a user waits for — whole commands, iterations to tolerance, start-up.

Runs, in one process tree and one run (so the noisy machine cancels out of the ratios):

* ``dgpc --version`` beside ``python -c "import click"`` (median of 5; ratio);
* the commands of the pipelines' stages, each timed as a whole and with its iterations (a
  deterministic count) beside the figure before the drag and stopping-rule changes:
  a 21×21 fit to a bowling pin, the demo's isometric optimize (the timber wall, 21×13, its
  samples handles), the felt's developable fit (41×25), a 4,797-vertex (123×39) fit, the
  four Gehry facades' drags (21×13), the wall's drag at 41×41 (the same handle pattern) and a
  161×81 fit;
* ``planarize-strips`` on the wall's drag (21×13): one template, ``--per-strip`` and
  ``--refine 2`` (their time ratios);
* for each optimize, the share of its time spent in the solver loop (``guided_projection``,
  from a profile of the command; the rest is reading, the reference, metrics, writing).
"""

from __future__ import annotations

import json
import pstats
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DGPC = str(Path(sys.executable).parent / "dgpc")

#: Iterations before this change (issue figures), for the comparison column.
BEFORE = {"demo isometric (wall 21×13)": 829, "felt developable (41×25)": 205,
          "bowling-pin fit (21×21)": 23, "bowling-pin fit (123×39, 4,797 vertices)": 94,
          "wall isometric (41×41)": 200, "bowling-pin fit (161×81)": 200,
          # the Gehry facades (21×13): the issue gave 318–490; these are the counts of the
          # release before the relaxation change
          "Gehry facade 1 (21×13)": 175, "Gehry facade 2 (21×13)": 173,
          "Gehry facade 3 (21×13)": 145, "Gehry facade 4 (21×13)": 145}


def _wall_handles(path: Path, m: int, n: int) -> None:
    """The demo wall's handle pattern (samples/generate.py) on an m×n net."""
    sys.path.insert(0, str(ROOT / "samples"))
    import generate

    source, span, drag = generate.HANDLE_SETS["wall"]
    profile = generate.read_profile_csv(ROOT / "samples" / "profiles" / source)
    path.write_bytes(generate.handles_json(profile, m, n, span, drag))


def _median_seconds(argv: list[str], runs: int = 5) -> float:
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, capture_output=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _run(argv: list[str], profile: Path) -> tuple[float, int]:
    """Wall time and exit code of ``dgpc ARGS`` run under cProfile (writing ``profile``)."""
    t0 = time.perf_counter()
    code = subprocess.run([sys.executable, "-m", "cProfile", "-o", str(profile), "-m",
                           "dgpc_cli.cli.main", *argv], capture_output=True).returncode
    return time.perf_counter() - t0, code


def _solver_share(stem: Path, profile: Path) -> tuple[int, float]:
    """Iterations of the optimize that wrote ``stem`` and the share of the process's time
    spent in the solver loop (``guided_projection``), from its profile."""
    status = json.loads(stem.with_suffix(".json").read_text())["status"]
    stats = pstats.Stats(str(profile))
    total = stats.total_tt
    loop = sum(cumulative for (path, _, name), (_, _, _, cumulative, callers)
               in stats.stats.items()
               if name == "guided_projection" and path.endswith("guided_projection.py")
               and not any(c[2] == "guided_projection" for c in callers))
    return status["iterations"], loop / total if total > 0 else float("nan")


def main() -> int:
    click_s = _median_seconds([sys.executable, "-c", "import click"])
    version_s = _median_seconds([DGPC, "--version"])
    print(f"start-up: dgpc --version {version_s:.3f} s, python -c 'import click' "
          f"{click_s:.3f} s, ratio {version_s / click_s:.2f} (target ≤ 3)")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        ref = d / "pin-ref.obj"
        prep = [
            [DGPC, "-q", "init", "--surface", "revolution", "--profile", "bowling-pin",
             "--rows", "21", "--cols", "21", "--twist", "3", "--reference-out", str(ref),
             "-o", str(d / "pin0")],
            [DGPC, "-q", "init", "--surface", "revolution", "--profile", "bowling-pin",
             "--rows", "123", "--cols", "39", "--span", "180", "--twist", "0.5",
             "--reference-out", str(d / "pin-big.obj"), "-o", str(d / "big0")],
            [DGPC, "-q", "init", "--surface", "revolution", "--profile",
             str(ROOT / "samples/profiles/wall.csv"), "--rows", "21", "--cols", "13",
             "--span", "60", "--units", "m", "-o", str(d / "wall0")],
            [DGPC, "-q", "init", str(ROOT / "samples/meshes/felt.obj"), "--method", "geodesic",
             "--rows", "41", "--cols", "25", "-o", str(d / "felt0")],
            [DGPC, "-q", "init", "--surface", "revolution", "--profile",
             str(ROOT / "samples/profiles/wall.csv"), "--rows", "41", "--cols", "41",
             "--span", "60", "--units", "m", "-o", str(d / "wall41")],
            [DGPC, "-q", "init", "--surface", "revolution", "--profile",
             str(ROOT / "samples/profiles/gehry.csv"), "--rows", "21", "--cols", "13",
             "--span", "90", "--units", "m", "-o", str(d / "gehry0")],
            [DGPC, "-q", "init", "--surface", "revolution", "--profile", "bowling-pin",
             "--rows", "161", "--cols", "81", "--span", "180", "--twist", "0.5",
             "--reference-out", str(d / "pin-161.obj"), "-o", str(d / "p161")],
        ]
        _wall_handles(d / "wall-41x41.json", 41, 41)
        for argv in prep:
            subprocess.run(argv, check=True, capture_output=True)
        cases = {
            "bowling-pin fit (21×21)": ([DGPC, "-q", "optimize", str(d / "pin0"), "--mode",
                                         "fit", "--reference", str(ref)], "pin"),
            "demo isometric (wall 21×13)": (
                [DGPC, "-q", "optimize", str(d / "wall0"), "--mode", "isometric", "--handles",
                 str(ROOT / "samples/handles/wall-21x13.json"), "--steps", "5"], "wall"),
            "felt developable (41×25)": (
                [DGPC, "-q", "optimize", str(d / "felt0"), "--mode", "developable",
                 "--reference", str(ROOT / "samples/meshes/felt.obj")], "felt"),
            "bowling-pin fit (123×39, 4,797 vertices)": (
                [DGPC, "-q", "optimize", str(d / "big0"), "--mode", "fit", "--reference",
                 str(d / "pin-big.obj"), "--tol", "1e-9"], "big"),
            **{f"Gehry facade {k} (21×13)": (
                [DGPC, "-q", "optimize", str(d / "gehry0"), "--mode", "isometric", "--handles",
                 str(ROOT / f"samples/handles/gehry-{k}-21x13.json"), "--steps", "5"],
                f"gehry{k}") for k in (1, 2, 3, 4)},
            "wall isometric (41×41)": (
                [DGPC, "-q", "optimize", str(d / "wall41"), "--mode", "isometric", "--handles",
                 str(d / "wall-41x41.json"), "--steps", "5"], "wall41i"),
            "bowling-pin fit (161×81)": (
                [DGPC, "-q", "optimize", str(d / "p161"), "--mode", "fit", "--reference",
                 str(d / "pin-161.obj"), "--tol", "1e-9"], "p161f"),
        }
        print(f"{'command':44s} {'wall s':>8s} {'exit':>4s} {'iterations':>10s} "
              f"{'before':>6s} {'R':>9s} {'solver loop':>11s}")
        for name, (argv, stem) in cases.items():
            profile = d / f"{stem}.prof"
            wall, code = _run([*argv[1:], "-o", str(d / stem)], profile)
            iterations, share = _solver_share(d / stem, profile)
            R = json.loads((d / f"{stem}.json").read_text())["metrics"]["R"]
            print(f"{name:44s} {wall:8.1f} {code:4d} {iterations:10d} {BEFORE[name]:6d} "
                  f"{R:9.1e} {100 * share:10.0f} %")
        # planarize-strips on the drag's wall (21×13): one template, and strip by strip
        times = {}
        runs = (("one template", []), ("--per-strip", ["--per-strip"]),
                ("--refine 2", ["--refine", "2"]))
        for k, (label, extra) in enumerate(runs):
            t0 = time.perf_counter()
            subprocess.run([DGPC, "-q", "planarize-strips", str(d / "wall"), *extra, "-o",
                            str(d / f"strips-{k}")], check=True, capture_output=True)
            times[label] = time.perf_counter() - t0
        print(f"planarize-strips (wall 21×13): one template {times['one template']:.1f} s, "
              f"--per-strip {times['--per-strip']:.1f} s, ratio "
              f"{times['one template'] / times['--per-strip']:.2f}; --refine 2 "
              f"{times['--refine 2']:.1f} s, ratio "
              f"{times['--refine 2'] / times['one template']:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
