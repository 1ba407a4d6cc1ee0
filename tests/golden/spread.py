"""How well the golden figures are determined: run every pipeline's small version with
another OpenBLAS kernel (``OPENBLAS_CORETYPE``, as on a CPU of another kind) and print, per
figure, its deviation from tests/golden/NAME.json beside the tolerance the tests apply.

    .venv/bin/python tests/golden/spread.py [KERNEL]      (default Prescott)

A figure whose deviation comes within a tenth of its tolerance is marked ``<-- tight``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from pipelines import FLOOR, GOLDEN, SIZES, collect, coord_tol, rel_tol, run  # noqa: E402


def _collect_all(out: Path) -> None:
    """Run and collect every pipeline (in this process, under the caller's environment)."""
    docs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in SIZES:
            docs[name] = collect(name, run(name, Path(tmp)))
    out.write_text(json.dumps(docs))


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--collect":
        _collect_all(Path(argv[1]))
        return 0
    kernel = argv[0] if argv else "Prescott"
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "spread.json"
        subprocess.run([sys.executable, __file__, "--collect", str(out)], check=True,
                       env={**os.environ, "OPENBLAS_CORETYPE": kernel})
        got = json.loads(out.read_text())
    for name in SIZES:
        want = json.loads((GOLDEN / f"{name}.json").read_text())
        print(name)
        for key, w in want["metrics"].items():
            g = got[name]["metrics"][key]
            dev = abs(g - w) / max(abs(g), abs(w), 1e-300)
            tol = rel_tol(name, key)
            floor = max(abs(g), abs(w)) <= FLOOR
            mark = "" if floor or dev * 10 <= tol else "  <-- tight"
            print(f"  {key:32s} rel {dev:9.2e}  tol {tol:7.0e}{' (floor)' if floor else ''}{mark}")
        for stem, w in want["nets"].items():
            w, g = np.array(w), np.array(got[name]["nets"][stem])
            diagonal = np.linalg.norm(np.ptp(w.reshape(-1, 3), axis=0))
            dev = float(np.abs(g - w).max() / diagonal)
            tol = coord_tol(name)
            mark = "" if dev * 10 <= tol else "  <-- tight"
            print(f"  net {stem:28s} rel {dev:9.2e}  tol {tol:7.0e}{mark}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
