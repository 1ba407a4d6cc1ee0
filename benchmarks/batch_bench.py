"""Batch scaling (``dgpc batch``): the 12-variant design sweep of the first Gehry-type patch
(samples/projects/gehry-sweep.toml: init + isometric optimize per variant) on a local Dask
cluster of 1 and of 2 worker processes, each from an empty output folder (nothing reused),
and what Dask's scheduling costs per task.

* wall: the whole command, cluster start and stop included; batch: from the first task
  submitted to the last result (batch.json's this_run.wall_time_s); tasks: the sum of the
  tasks' own wall times on the workers;
* ratio: the 1-worker batch time over the 2-worker one (2 on an idle 2-core machine at best);
* overhead per task: (batch − tasks) / tasks with 1 worker — the client's fingerprints and
  submissions, the transfers and the worker's bookkeeping —, and the round trip of an empty
  Dask task (submit, run, result) on a 1-worker local cluster, one after another.

    python benchmarks/batch_bench.py [--project samples/projects/gehry-sweep.toml]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DGPC = str(Path(sys.executable).parent / "dgpc")


def run_batch(project: Path, out: Path, workers: int) -> dict:
    """Run the project with ``workers`` local workers; wall time and batch.json's figures."""
    start = time.perf_counter()
    proc = subprocess.run([DGPC, "-q", "batch", str(project), "-o", str(out), "--workers",
                           str(workers)], cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode not in (0, 3):
        raise SystemExit(f"dgpc batch exited {proc.returncode}: {proc.stderr.strip()}")
    doc = json.loads((out / "batch.json").read_text())
    run = doc["this_run"]
    executed = run["executed"]
    return {"wall": wall, "batch": run["wall_time_s"], "n": len(executed),
            "tasks": sum(run["tasks"][t]["wall_time_s"] for t in executed),
            "status": doc["status"]}


def _noop(x):
    return x


def round_trip(n: int = 100) -> float:
    """Mean seconds of an empty task's submit → result on a 1-worker local cluster."""
    from distributed import Client, LocalCluster

    from dgpc_cli.batch.cluster import local_cluster_options

    with LocalCluster(**local_cluster_options(1)) as cluster, \
            Client(cluster) as client:
        client.submit(_noop, -1, pure=False).result()          # warm up
        start = time.perf_counter()
        for k in range(n):
            client.submit(_noop, k, pure=False).result()
        return (time.perf_counter() - start) / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--project", type=Path, default=Path("samples/projects/gehry-sweep.toml"))
    args = ap.parse_args(argv)
    print(f"batch: {args.project} from an empty output folder, local cluster")
    print(f"{'workers':>8} {'wall s':>8} {'batch s':>8} {'tasks s':>8} {'tasks':>6}  status")
    results = {}
    with tempfile.TemporaryDirectory(prefix="dgpc-batch-bench-") as tmp:
        for workers in (1, 2):
            r = run_batch(args.project, Path(tmp) / f"w{workers}", workers)
            results[workers] = r
            print(f"{workers:>8} {r['wall']:8.1f} {r['batch']:8.1f} {r['tasks']:8.1f} "
                  f"{r['n']:>6}  {r['status']}")
    one, two = results[1], results[2]
    print(f"batch: 1 worker / 2 workers = {one['batch'] / two['batch']:.2f} "
          f"(wall {one['wall'] / two['wall']:.2f})")
    overhead = (one["batch"] - one["tasks"]) / one["n"]
    print(f"batch: overhead per task (1 worker, batch − tasks) = {1000 * overhead:.0f} ms; "
          f"empty Dask task round trip = {1000 * round_trip():.1f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
