"""How well the golden figures are determined: run every pipeline's small version with
another OpenBLAS kernel (``OPENBLAS_CORETYPE``, as on a CPU of another kind) and print, per
figure, its deviation from tests/golden/NAME.json beside the tolerance the tests apply.

    .venv/bin/python tests/golden/spread.py [KERNEL]      (default Sandybridge)

A figure whose deviation comes within a tenth of its tolerance is marked ``<-- tight``.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from pipelines import GOLDEN, SIZES, collect, compare, run  # noqa: E402


def main(argv: list[str]) -> int:
    kernel = argv[0] if argv else "Sandybridge"
    for name in SIZES:
        with tempfile.TemporaryDirectory() as tmp:
            got = collect(name, run(name, Path(tmp), env={"OPENBLAS_CORETYPE": kernel},
                                    figures=False))
        want = json.loads((GOLDEN / f"{name}.json").read_text())
        print(name)
        for key, (dev, tol) in compare(name, got, want).items():
            mark = "" if dev * 10 <= tol else "  <-- tight"
            print(f"  {key:32s} {dev:9.2e}  tol {tol:7.0e}{mark}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
