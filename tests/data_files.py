"""Files the tests read from ``tests/data/`` (their source and license: tests/data/README.md)."""

from pathlib import Path

DATA = Path(__file__).resolve().parent / "data"
#: A freeform architectural patch, 3,021 vertices, 5,705 triangles, about 43.6 × 44.0 × 6.1.
WAVE = DATA / "wave.obj"
