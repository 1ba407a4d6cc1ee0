"""The golden tolerances hold on any machine (tests/golden/tolerances.py): every pipeline's
small version run again with its input nets moved by 1e-12 of their size, and with OpenBLAS on
another CPU's kernels, moves every compared figure by less than a tenth of its tolerance
against the same pipeline run here as it is, and no count.

A figure that moved more would expose a step whose result the last bits of its input decide:
the one known is the twisted net's fit on the bowling pin (below)."""

import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "golden"))

from pipelines import SIZES, collect, compare, run  # noqa: E402

#: How far the input nets move: a fraction of their bounding-box diagonal.
PERTURBATION = 1e-12
#: The oldest x86-64 kernel OpenBLAS has for double precision that every such CPU runs.
KERNEL = {"OPENBLAS_CORETYPE": "Sandybridge"}

#: The fit of the twisted 21x11 net to the bowling pin picks one of a family of nets (it may
#: turn about the axis and slide along its geodesics); from a start moved by 1e-12 the fit
#: folds two quads at a corner (rows 0-1, columns 0-1) and optimize exits 3. Its golden
#: figures are bounds for that reason; the fold is a defect of the fit, not of the tolerance.
FOLDS = {"bowling-pin-clairaut"}

CASES = [pytest.param(name, "perturbed", marks=pytest.mark.xfail(
             raises=subprocess.CalledProcessError, strict=True,
             reason="the twisted fit on the bowling pin folds from a start moved by 1e-12"))
         if name in FOLDS else (name, "perturbed") for name in SIZES]
CASES += [(name, "kernel") for name in SIZES]


@pytest.mark.parametrize(("name", "variant"), CASES)
def test_a_tenth_of_the_tolerance_holds_every_figure(pipeline_run, tmp_path, name, variant):
    want = collect(name, pipeline_run(name))
    if variant == "perturbed":
        d = run(name, tmp_path, perturb=PERTURBATION, figures=False)
    else:
        d = run(name, tmp_path, env=KERNEL, figures=False)
    got = collect(name, d)
    drift = compare(name, got, want, drift=True)
    worst = max(drift, key=lambda k: drift[k][0] / drift[k][1])
    print(f"{name} {variant}: largest drift {worst} "
          f"{drift[worst][0] / drift[worst][1]:.2g} of its tolerance")
    for figure, (deviation, tolerance) in drift.items():
        assert deviation <= 0.1 * tolerance, (figure, deviation, tolerance)
    assert got["counts"] == want["counts"]
    assert got["dxf"] == want["dxf"]
