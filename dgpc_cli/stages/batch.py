"""``dgpc batch``: run a project's tasks on a Dask cluster (``dask.distributed`` futures).

The client walks the task graph (:mod:`dgpc_cli.batch.graph`): a task whose dependencies
have finished with their artifacts written is either reused (:mod:`dgpc_cli.batch.cache`)
or submitted to the cluster, one Dask future per dgpc command, and results are taken as they
complete (``distributed.as_completed``), so independent patches run side by side and the
shared stages start as soon as their patches are done. A task whose dependency failed is not
run (``blocked``); the other patches go on.

The function that runs a task on a worker is passed in (``runner``): the command line's
:func:`dgpc_cli.cli.batch_tasks.run_task`, which invokes the dgpc command itself.
"""

from __future__ import annotations

import asyncio
import logging
import os
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from dgpc_cli.batch.cache import fingerprint, load_previous, reusable
from dgpc_cli.batch.graph import Task
from dgpc_cli.errors import DgpcError

log = logging.getLogger(__name__)

#: Exit codes after which the next stages run (the artifact was written).
WRITTEN = (0, 3)


#: Seconds a scheduler has to answer, and then to have a worker (``dgpc batch --timeout``).
CONNECT_TIMEOUT = 20.0
#: The address forms a scheduler may be given in (Dask's default scheme is tcp).
SCHEMES = ("tcp",)


def machine_cores() -> int:
    """The cores this process may run on (its CPU affinity, else the machine's count)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def scheduler_address(address: str) -> str:
    """``tcp://HOST:PORT`` of ``address`` (``HOST:PORT`` or ``tcp://HOST:PORT``); another
    scheme, or no port, is a DgpcError naming ``--scheduler``."""
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme.lower() not in SCHEMES:
        raise DgpcError(f"{address}: the scheme {scheme}:// is not supported; give "
                        "tcp://HOST:PORT", source="--scheduler")
    host, colon, port = rest.rpartition(":")
    if not colon or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise DgpcError(f"{address}: not HOST:PORT (e.g. tcp://10.0.0.5:8786)",
                        source="--scheduler")
    return f"tcp://{rest}"


def probe_scheduler(address: str, timeout: float) -> dict:
    """Ask the Dask scheduler at ``address`` who it is (its ``identity``), within ``timeout``
    seconds for the connection, the handshake and the answer together: Dask bounds only the
    connection, so a silent peer would hang and a non-Dask server's reply be read as a frame
    of exabytes. A DgpcError in one line otherwise."""
    import socket

    from distributed.core import rpc

    # a plain TCP connection first: a refused or unreachable address is told as such at once
    # (Dask retries a refused connection until its timeout, and would report it as silent)
    host, _, port = address.removeprefix("tcp://").rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=timeout).close()
    except TimeoutError:
        raise DgpcError(f"{address}: no answer within {timeout:g} s (nothing accepts a "
                        "connection there)", source="--scheduler") from None
    except OSError as err:
        reason = " ".join(str(err).split()) or type(err).__name__
        raise DgpcError(f"{address}: cannot connect: {reason}", source="--scheduler") from None

    async def ask():
        async with rpc(address, timeout=timeout) as scheduler:
            return await scheduler.identity()

    try:
        info = asyncio.run(asyncio.wait_for(ask(), timeout))
    except TimeoutError:
        raise DgpcError(f"{address}: no answer from a Dask scheduler within {timeout:g} s "
                        "(a silent port, or not a Dask scheduler)", source="--scheduler") \
            from None
    except OSError as err:
        reason = " ".join(str(err).split()) or type(err).__name__
        raise DgpcError(f"{address}: cannot connect: {reason}", source="--scheduler") from None
    except Exception as err:  # noqa: BLE001 - any reply Dask cannot read (HTTP, MemoryError)
        raise DgpcError(f"{address}: not a Dask scheduler (its answer could not be read: "
                        f"{type(err).__name__})", source="--scheduler") from None
    if not isinstance(info, dict) or info.get("type") != "Scheduler":
        raise DgpcError(f"{address}: not a Dask scheduler (it answers as "
                        f"{info.get('type') if isinstance(info, dict) else 'something else'})",
                        source="--scheduler")
    return info


def connect(scheduler: str | None, workers: int | None, timeout: float = CONNECT_TIMEOUT):
    """A Dask client, its local cluster (None with ``scheduler``) and what to record of it.

    ``scheduler``: its address (checked, probed within ``timeout`` and waited for a worker
    as long); else a new local cluster of ``workers`` single-threaded processes on the
    loopback address (default: one per core, :func:`machine_cores`). Nothing is written:
    the caller makes its output folder once this returns."""
    from distributed import Client, LocalCluster

    from dgpc_cli.batch.cluster import local_cluster_options

    if scheduler is not None:
        address = scheduler_address(scheduler)
        probe_scheduler(address, timeout)
        try:
            client = Client(address, timeout=f"{timeout}s")
        except (OSError, TimeoutError, ValueError) as err:
            reason = " ".join(str(err).split()) or type(err).__name__
            raise DgpcError(f"{scheduler}: cannot connect: {reason}",
                            source="--scheduler") from None
        try:
            client.wait_for_workers(1, timeout=timeout)
        except TimeoutError:
            client.close()
            raise DgpcError(f"{scheduler}: the scheduler has no workers (none joined within "
                            f"{timeout:g} s); start some with `dask worker {address} "
                            "--nthreads 1`", source="--scheduler") from None
        return client, None, {"scheduler": scheduler,
                              "workers": len(client.scheduler_info()["workers"])}
    n = workers or machine_cores()
    cluster = LocalCluster(**local_cluster_options(n))
    return Client(cluster), cluster, {"scheduler": "local", "workers": n}


@dataclass
class Progress:
    """Where a batch stands: groups (patches, then ``shared``) and tasks finished."""

    groups_done: int
    groups_total: int
    tasks_done: int
    tasks_total: int
    elapsed_s: float
    eta_s: float | None
    group: str


@dataclass
class BatchRun:
    """Per task its record (``batch.json``'s ``tasks``) and whether it ran in this batch."""

    records: dict[str, dict] = field(default_factory=dict)
    executed: dict[str, bool] = field(default_factory=dict)
    wall_time_s: float = 0.0


def task_spec(task: Task, out: Path, base: Path) -> dict:
    """What the worker needs to run ``task``: the command, its arguments and the folders."""
    return {"id": task.id, "command": task.command, "args": task.args, "cwd": str(base),
            "out": str(out), "artifact": task.artifact}


def run_batch(tasks: dict[str, Task], out: Path, base: Path, client, runner: Callable,
              *, progress: Callable[[Progress], None] | None = None) -> BatchRun:
    """Run ``tasks`` (writing into ``out``, their paths relative to ``base``) on the Dask
    ``client`` with ``runner`` on the workers; see the module."""
    from distributed import as_completed

    out, base = Path(out).resolve(), Path(base).resolve()
    previous = load_previous(out / "batch.json")
    run = BatchRun()
    start = time.perf_counter()
    groups = list(dict.fromkeys(t.group for t in tasks.values()))
    left = {g: sum(1 for t in tasks.values() if t.group == g) for g in groups}
    pending = dict(tasks)
    futures = {}
    executed_time = [0.0, 0]            # wall time of the tasks run here, and their count
    workers = max(1, len(client.scheduler_info().get("workers", {})))

    def finish(task: Task, record: dict, executed: bool) -> None:
        run.records[task.id] = record
        run.executed[task.id] = executed
        if executed:
            executed_time[0] += record["wall_time_s"]
            executed_time[1] += 1
        left[task.group] -= 1
        if left[task.group] == 0 and progress is not None:
            progress(_progress(task.group))

    def _progress(group: str) -> Progress:
        done = len(run.records)
        elapsed = time.perf_counter() - start
        remaining = len(tasks) - done
        eta = None
        if executed_time[1]:
            eta = remaining * executed_time[0] / executed_time[1] / workers
        return Progress(sum(1 for g in groups if left[g] == 0), len(groups), done,
                        len(tasks), elapsed, 0.0 if remaining == 0 else eta, group)

    def schedule() -> list:
        """Settle every task whose dependencies are settled; return the new futures."""
        new = []
        changed = True
        while changed:
            changed = False
            for tid, task in list(pending.items()):
                deps = [run.records.get(d) for d in task.deps]
                if any(d is None for d in deps):
                    continue
                del pending[tid]
                changed = True
                failed = [dep for dep, rec in zip(task.deps, deps, strict=True)
                          if rec["exit_code"] not in WRITTEN]
                if failed:
                    finish(task, {"command": task.argv, "exit_code": None, "status": "blocked",
                                  "message": f"not run: {failed[0]} did not write its "
                                             "artifact", "warnings": [], "outputs": {},
                                  "wall_time_s": 0.0}, False)
                    continue
                fp = fingerprint(task, base)
                old = previous.get(tid)
                if reusable(old, fp, task, out):
                    finish(task, {**old, "command": task.argv}, False)
                    continue
                key = f"dgpc-{tid.replace('/', '-')}-{uuid.uuid4().hex[:12]}"
                future = client.submit(runner, task_spec(task, out, base), key=key)
                futures[future] = (task, fp)
                new.append(future)
        return new

    completed = as_completed(schedule())
    for future in completed:
        task, fp = futures.pop(future)
        try:
            result = future.result()
        except Exception as err:  # noqa: BLE001 - a worker lost or a task that could not run
            reason = " ".join(str(err).split()) or type(err).__name__
            result = {"exit_code": 1, "message": f"the task could not run on the cluster "
                                                 f"({type(err).__name__}): {reason}",
                      "warnings": [], "outputs": {}, "wall_time_s": 0.0}
        record = {"command": task.argv, "fingerprint": fp, "exit_code": result["exit_code"],
                  "status": status_of(result["exit_code"]), "message": result["message"],
                  "warnings": result["warnings"], "outputs": result["outputs"],
                  "wall_time_s": result["wall_time_s"]}
        finish(task, record, True)
        completed.update(schedule())
    for task in pending.values():     # unreachable with a well-formed graph
        finish(task, {"command": task.argv, "exit_code": None, "status": "blocked",
                      "message": "not run: its dependencies never finished", "warnings": [],
                      "outputs": {}, "wall_time_s": 0.0}, False)
    run.wall_time_s = time.perf_counter() - start
    return run


def status_of(exit_code: int | None) -> str:
    """``ok`` (0), ``not_converged`` (3: artifact written), ``failed`` (1, 2), ``blocked``."""
    return {0: "ok", 3: "not_converged", None: "blocked"}.get(exit_code, "failed")
