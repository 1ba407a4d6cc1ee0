"""Sparse SPD solvers for the normal equations (SPEC §10).

* ``pardiso``  — MKL PARDISO in SPD mode (mtype 2): symbolic analysis (phase 11) once per net,
  numeric factorization (22) and solve (33) per iteration. x86_64 only.
* ``cholmod``  — cholespy's bundled CHOLMOD; it has no refactorization API, so it analyses and
  factorizes anew every iteration. The fallback where MKL is absent.
* ``spsolve``  — a fresh ``scipy.sparse.linalg.spsolve`` every iteration: what the authors' code
  does; the reference of ``make bench``.

Every backend has ``factorize(data)`` (the values of A in the fixed pattern) and ``solve(b)``
(with the last factorization). :func:`blas_on_one_thread` keeps numpy's dense BLAS on one thread
while the solver runs.
"""

from __future__ import annotations

import glob
import os
import sys
from functools import cache, wraps

import numpy as np
import scipy.sparse.linalg as spla

from dgpc_cli.core.solver.normal_matrix import NormalMatrix

#: Branches of MKL's conditional numerical reproducibility (mkl_cbwr_set, mkl_service.h): one
#: code path whatever the CPU, so that a solve rounds alike on every machine. AVX2 (every x86-64
#: CPU since 2013) where the CPU has it; else COMPATIBLE (SSE2 only: the 41×41 sphere push
#: took 2× the solver time of AVX2). AUTO (2, the branch the CPU picks: AVX-512 on one machine,
#: AVX2 on the next) moved the 9×7 timber wall by 3e-8 of its diagonal between them.
MKL_CBWR_AVX2, MKL_CBWR_COMPATIBLE = 10, 3
#: The number of threads PARDISO's factorization is reproducible with.
CNR_THREADS = 2
#: Thread policy, by problem size only (never by the machine or its load, so that artifacts are
#: the same bytes everywhere): systems below this many unknowns are solved on one thread (the
#: threads' start-up costs more than they save: a 21×21 net iterates 4–7× faster on a loaded
#: 2-core machine), larger ones on CNR_THREADS; MKL's dynamic adjustment to the load is off.
PARALLEL_FROM = 50_000


def solver_threads(size: int) -> int:
    """MKL threads for a system of ``size`` unknowns (see ``PARALLEL_FROM``)."""
    return 1 if size < PARALLEL_FROM else CNR_THREADS


@cache
def _openblas():
    """The OpenBLAS libraries loaded in this process (numpy's, scipy's), by threadpoolctl."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController().select(internal_api="openblas")


def blas_on_one_thread(func):
    """Run ``func`` with OpenBLAS on one thread (MKL, and so PARDISO, keeps its policy).

    The solver's dense BLAS work is dot products and norms of residual vectors. On more
    threads, OpenBLAS waits for cores that MKL's threads still spin on after a factorization
    (at 4,797 vertices a dot product took 2.4 ms instead of 0.01 ms, a fifth of the iteration
    beside PARDISO), and the order of a sum, so its last bit, would depend on the machine's
    number of cores.
    """
    @wraps(func)
    def on_one_thread(*args, **kwargs):
        with _openblas().limit(limits=1):
            return func(*args, **kwargs)

    return on_one_thread


@cache
def _locate_mkl_rt() -> None:
    """Point pypardiso at the MKL runtime installed beside this Python (the mkl wheel puts it
    in ``sys.prefix/lib``), so that it need not ask ``ldconfig`` and ``gcc`` for it (its
    ``ctypes.util.find_library`` starts both on Linux). Leaves a user's PYPARDISO_MKL_RT."""
    if os.environ.get("PYPARDISO_MKL_RT"):
        return
    found = sorted(glob.glob(os.path.join(sys.prefix, "lib", "libmkl_rt.so*")), key=len)
    if found:
        os.environ["PYPARDISO_MKL_RT"] = found[0]


class PardisoSPD:
    name = "pardiso"

    def __init__(self, pattern: NormalMatrix):
        _locate_mkl_rt()                # before pypardiso's import, which makes a solver
        from pypardiso.pardiso_wrapper import PyPardisoSolver

        self._solver = PyPardisoSolver(mtype=2)
        self._solver.libmkl.MKL_Set_Dynamic(0)
        self._solver.libmkl.MKL_Set_Num_Threads(solver_threads(pattern.size))
        # Conditional numerical reproducibility: PARDISO's threaded factorization otherwise
        # rounds differently from run to run and from CPU to CPU, the artifacts must be
        # byte-deterministic (SPEC §3), and near singular roots the solver amplifies such
        # differences. MKL_CBWR_Set returns 0 when the CPU runs the branch.
        if self._solver.libmkl.MKL_CBWR_Set(MKL_CBWR_AVX2) != 0:
            self._solver.libmkl.MKL_CBWR_Set(MKL_CBWR_COMPATIBLE)
        iparm = self._solver.iparm
        iparm[0] = 1                    # the values below, not PARDISO's defaults
        iparm[1] = 0                    # minimum-degree ordering: less work than METIS here
        iparm[9] = 8                    # pivot perturbation 1e-8 (the SPD default)
        iparm[33] = CNR_THREADS         # reproducible results with this many threads
        self._A = pattern.upper(np.zeros(pattern.nnz))
        self._A.has_sorted_indices = True
        self._analysed = False

    def _phase(self, phase: int, b: np.ndarray) -> np.ndarray:
        self._solver.set_phase(phase)
        return self._solver._call_pardiso(self._A, b)

    def factorize(self, data: np.ndarray) -> None:
        self._A.data[:] = data
        self._solver._check_A(self._A)
        rhs = np.zeros((self._A.shape[0], 1), order="F")
        if not self._analysed:
            self._phase(11, rhs)
            self._analysed = True
        self._phase(22, rhs)

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._phase(33, np.asfortranarray(b.reshape(-1, 1))).ravel()

    def __del__(self):
        try:
            self._solver.free_memory(everything=True)
        except Exception:  # noqa: BLE001 - best effort at interpreter shutdown
            pass


class CholmodSPD:
    name = "cholmod"

    def __init__(self, pattern: NormalMatrix):
        self._pattern = pattern

    def factorize(self, data: np.ndarray) -> None:
        from cholespy import CholeskySolverD, MatrixType

        A = self._pattern.full(data)
        self._chol = CholeskySolverD(A.shape[0], A.indptr.astype(np.int32),
                                     A.indices.astype(np.int32), A.data, MatrixType.CSC)

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = np.zeros_like(b)
        self._chol.solve(np.ascontiguousarray(b), x)
        return x


class ScipySpsolve:
    name = "spsolve"

    def __init__(self, pattern: NormalMatrix):
        self._pattern = pattern

    def factorize(self, data: np.ndarray) -> None:
        self._A = self._pattern.full(data)

    def solve(self, b: np.ndarray) -> np.ndarray:
        return spla.spsolve(self._A, b)


BACKENDS = {"pardiso": PardisoSPD, "cholmod": CholmodSPD, "spsolve": ScipySpsolve}


@cache
def available_backends() -> tuple[str, ...]:
    names = []
    try:
        _locate_mkl_rt()
        from pypardiso.pardiso_wrapper import PyPardisoSolver

        PyPardisoSolver(mtype=2)
        names.append("pardiso")
    except Exception:  # noqa: BLE001 - MKL missing or not loadable on this platform
        pass
    try:
        import cholespy  # noqa: F401

        names.append("cholmod")
    except ImportError:
        pass
    names.append("spsolve")
    return tuple(names)


def make_solver(pattern: NormalMatrix, backend: str = "auto"):
    """A solver for the pattern; ``auto`` takes the fastest available backend."""
    if backend == "auto":
        backend = available_backends()[0]
    if backend not in BACKENDS:
        raise ValueError(f"unknown linear solver {backend!r}; choose from {sorted(BACKENDS)}")
    return BACKENDS[backend](pattern)


__all__ = ["BACKENDS", "available_backends", "make_solver"]
