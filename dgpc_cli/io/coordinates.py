"""The range of every coordinate read from a file: finite and within ``tol.max_coordinate``
(a vertex at 1e308 overflows the first squared distance and ends deep in a stage)."""

from __future__ import annotations

import numpy as np

from ..tolerances import tol as TOL


def bad_rows(points) -> np.ndarray:
    """Indices of the rows of ``points (k, d)`` with a non-finite coordinate or one beyond
    ``±tol.max_coordinate``."""
    p = np.asarray(points, dtype=np.float64)
    p = p.reshape(len(p), -1) if p.ndim != 2 else p
    with np.errstate(invalid="ignore"):
        return np.flatnonzero(~(np.abs(p) <= TOL.max_coordinate).all(axis=1))


def coordinate_problem(row) -> str:
    """What is wrong with a row :func:`bad_rows` found: ``"a non-finite coordinate"`` or
    ``"coordinate X beyond ±1e+09"``."""
    row = np.asarray(row, dtype=np.float64).ravel()
    if not np.isfinite(row).all():
        return "a non-finite coordinate"
    worst = float(row[np.argmax(np.abs(row))])
    return (f"coordinate {worst:g} beyond ±{TOL.max_coordinate:g} (the largest dgpc accepts, "
            "in the model's unit)")
