"""The linear solver's thread policy and its library lookup (SPEC §10): artifacts are the same
bytes whatever thread count the environment asks for, and loading MKL starts no process."""

import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from dgpc_cli.core.solver.linear import CNR_THREADS, PARALLEL_FROM, solver_threads

DGPC = Path(sys.executable).parent / "dgpc"


def test_threads_follow_the_problem_size_only():
    assert solver_threads(8_043) == 1                 # a 21×21 net in the paper's layout
    assert solver_threads(PARALLEL_FROM - 1) == 1
    assert solver_threads(PARALLEL_FROM) == CNR_THREADS


def test_optimize_writes_the_same_bytes_whatever_the_environment_asks(tmp_path):
    subprocess.run([DGPC, "-q", "init", "--surface", "revolution", "--profile", "catenoid",
                    "--rows", "11", "--cols", "9", "--twist", "0.3", "-o", tmp_path / "n0"],
                   check=True, capture_output=True)
    out = {}
    for threads in ("1", "2"):
        env = {**os.environ, "MKL_NUM_THREADS": threads, "OMP_NUM_THREADS": threads,
               "OPENBLAS_NUM_THREADS": threads, "MKL_DYNAMIC": "TRUE"}
        stem = tmp_path / f"t{threads}"
        subprocess.run([DGPC, "-q", "optimize", tmp_path / "n0", "--mode", "revolution",
                        "--max-strain", "1", "-o", stem], check=True, capture_output=True,
                       env=env)
        out[threads] = (stem.with_suffix(".obj").read_bytes(),
                        stem.with_suffix(".json").read_bytes().replace(b"t1.obj", b"")
                        .replace(b"t2.obj", b""))
    assert out["1"] == out["2"]


def test_the_solver_runs_openblas_on_one_thread():
    """Inside guided projection numpy's OpenBLAS has one thread (its threads would wait for
    the cores MKL's spin on, and a sum's order would follow the core count); outside, what the
    process had before."""
    code = ("from threadpoolctl import threadpool_info, threadpool_limits\n"
            "import numpy as np\n"
            "from dgpc_cli.core.solver.linear import blas_on_one_thread\n"
            "def blas():\n"
            "    return {i['num_threads'] for i in threadpool_info()\n"
            "            if i['internal_api'] == 'openblas'}\n"
            "threadpool_limits(2, user_api='blas')\n"
            "assert blas() == {2}, 'numpy without OpenBLAS'\n"
            "inside = blas_on_one_thread(blas)()\n"
            "assert inside == {1} and blas() == {2}, (inside, blas())\n")
    subprocess.run([sys.executable, "-c", code], check=True,
                   env={**os.environ, "OPENBLAS_NUM_THREADS": "2"})


@pytest.mark.skipif(platform.machine() != "x86_64", reason="MKL PARDISO is x86_64 only")
def test_loading_mkl_starts_no_process():
    """pypardiso asks ctypes.util.find_library for mkl_rt, which runs ldconfig and gcc; the
    runtime beside this Python is named to it instead."""
    code = ("import subprocess\n"
            "def refuse(*a, **k):\n    raise AssertionError('started a process')\n"
            "subprocess.Popen.__init__ = refuse\n"
            "from dgpc_cli.core.solver.linear import available_backends\n"
            "assert available_backends()[0] == 'pardiso', available_backends()\n")
    subprocess.run([sys.executable, "-c", code], check=True,
                   env={k: v for k, v in os.environ.items() if k != "PYPARDISO_MKL_RT"})


@pytest.mark.skipif(platform.machine() != "x86_64", reason="MKL PARDISO is x86_64 only")
@pytest.mark.parametrize("asked", [None, "AUTO", "AVX512"])
def test_pardiso_runs_one_code_path_whatever_the_cpu(asked):
    """MKL's reproducibility branch is fixed (AVX2, or COMPATIBLE on a CPU without it), never
    the one the CPU or the environment would pick (AUTO: AVX-512 on one machine, AVX2 on the
    next, and solves that round differently)."""
    code = ("import numpy as np\n"
            "from dgpc_cli.core.solver.linear import MKL_CBWR_AVX2, MKL_CBWR_COMPATIBLE, "
            "PardisoSPD\n"
            "from dgpc_cli.core.solver.normal_matrix import NormalMatrix\n"
            "rows, cols = np.arange(3), np.arange(3)\n"
            "solver = PardisoSPD(NormalMatrix(rows, cols, 3, 3))\n"
            "branch = solver._solver.libmkl.MKL_CBWR_Get(1)\n"
            "assert branch in (MKL_CBWR_AVX2, MKL_CBWR_COMPATIBLE), branch\n")
    env = {k: v for k, v in os.environ.items() if k != "MKL_CBWR"}
    if asked:
        env["MKL_CBWR"] = asked
    subprocess.run([sys.executable, "-c", code], check=True, env=env)
