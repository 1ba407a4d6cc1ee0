"""``make bench``: ``init`` and ``optimize --mode fit`` on the arched roof of two corners
(tests/outline_meshes.py: an arch in a vertical plane, a curved ground edge, bumps and
saddles), as a user runs them: the default init, and the options that cover most
(``--extend 0.2 --direction 1,0,0``), at 21, 41 and 61 columns. Prints the wall time of each
command, the candidates init tried with their coverage, and the coverage before and after the
fit (deterministic figures beside the noisy times); then ``init --patches auto`` and the fit
of every patch's net, with the coverage of the roof by the patch nets (each net's coverage of
its patch, weighted by the patch's area) before and after the fits."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DGPC = str(Path(sys.executable).parent / "dgpc")
sys.path.insert(0, str(ROOT / "tests"))

from outline_meshes import arch_roof, write  # noqa: E402

#: (label, init options) of the runs.
RUNS = [("default", []), ("extend 0.2, along x", ["--extend", "0.2", "--direction", "1,0,0"])]
COLUMNS = (21, 41, 61)


def _timed(argv: list[str]) -> tuple[float, int, str]:
    t0 = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True)
    return time.perf_counter() - t0, done.returncode, done.stderr


def _coverage(stem: Path) -> float:
    out = subprocess.run([DGPC, "inspect", str(stem)], capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out)["coverage"]["area_fraction"]


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        roof = write(d / "roof.obj", arch_roof())
        for label, options in RUNS:
            for cols in COLUMNS:
                stem = d / f"n{len(options)}-{cols}"
                t_init, code, _ = _timed([DGPC, "-q", "init", str(roof), "--method", "geodesic",
                                          "--units", "m", "--cols", str(cols), *options,
                                          "-o", str(stem)])
                if code != 0:
                    print(f"arch roof, {label}, {cols} columns: init exit {code}")
                    continue
                choice = json.loads(stem.with_suffix(".json").read_text())["data"]["init"]
                tried = ", ".join(f"{t.get('candidate')} {100 * t['coverage']:.1f} %"
                                  for t in choice.get("choice", {}).get("tried", [])
                                  if "coverage" in t)
                t_fit, code, _ = _timed([DGPC, "-q", "optimize", str(stem), "--mode", "fit",
                                         "-o", f"{stem}-fit"])
                state = json.loads(Path(f"{stem}-fit.json").read_text())["status"]
                print(f"arch roof, {label}, {cols} columns: init {t_init:.1f} s, fit {t_fit:.1f} s"
                      f" ({state['iterations']} iterations, {state['state']}); coverage "
                      f"{100 * _coverage(stem):.2f} % -> {100 * _coverage(Path(f'{stem}-fit')):.2f}"
                      f" %" + (f"; init tried: {tried}" if tried else ""))
        for cols in COLUMNS:
            _patches(d, roof, cols)
    return 0


def _patches(d: Path, roof: Path, cols: int) -> None:
    """``init --patches auto`` at ``cols`` columns, the fit of every patch net; one line."""
    stem = d / f"p-{cols}"
    t_init, code, _ = _timed([DGPC, "-q", "init", str(roof), "--method", "geodesic", "--units",
                              "m", "--cols", str(cols), "--patches", "auto", "-o", str(stem)])
    if code != 0:
        print(f"arch roof, --patches auto, {cols} columns: init exit {code}")
        return
    nets = sorted(d.glob(f"p-{cols}.p*.json"))
    before = after = area = t_fit = 0.0
    chosen = []
    for net in nets:
        doc = json.loads(net.read_text())
        record = doc["data"]["patches"]
        a = next(p["area"] for p in record["patches"] if p["name"] == record["name"])
        choice = doc["data"]["init"]["choice"]
        options = choice.get("search", {}).get("options", choice["chosen"])
        chosen.append(f"{record['name']}: {options} ({len(choice['tried'])} tried)")
        pstem = net.with_suffix("")
        t, _, _ = _timed([DGPC, "-q", "optimize", str(pstem), "--mode", "fit", "-o",
                          f"{pstem}-fit"])
        t_fit += t
        before += a * _coverage(pstem)
        after += a * _coverage(Path(f"{pstem}-fit"))
        area += a
    print(f"arch roof, --patches auto, {cols} columns: init {t_init:.1f} s, {len(nets)} patch "
          f"nets fitted in {t_fit:.1f} s; coverage {100 * before / area:.2f} % -> "
          f"{100 * after / area:.2f} %; " + "; ".join(chosen))


if __name__ == "__main__":
    sys.exit(main())
