"""Refresh tests/golden/NAME.json from small runs of every pipeline (``make golden``).

Run only after a reviewed change of the pipelines' numbers; review the diff of tests/golden/.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from pipelines import GOLDEN, SIZES, collect, dumps, run  # noqa: E402


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        for name in SIZES:
            d = run(name, Path(tmp))
            path = GOLDEN / f"{name}.json"
            path.write_text(dumps(collect(name, d)))
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
