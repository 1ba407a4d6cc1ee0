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

Then a sweep at facade scale: ``--sweep N`` generated patches (the Gehry-type profile at
9×7, each with its own twist, 0.05° to N × 0.05°; init and one strip of planarize-strips:
2N tasks) on a local cluster of ``--workers`` processes from an empty folder, and a rerun
that must recompute nothing: wall time, scheduler overhead per task (workers × batch −
tasks) / tasks, tasks run again.

    python benchmarks/batch_bench.py [--project samples/projects/gehry-sweep.toml]
        [--sweep 100] [--workers 2]
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


def sweep_project(folder: Path, n: int) -> Path:
    """A project of ``n`` patches in ``folder``: the Gehry-type profile at 9×7, twists 0.05° to
    ``n`` × 0.05°, init and one strip of planarize-strips each, no figures."""
    profile = (ROOT / "samples" / "profiles" / "gehry.csv").as_posix()
    lines = ["[project]", "report = false", "", "[defaults.init]", 'surface = "revolution"',
             f'profile = "{profile}"', "rows = 9", "cols = 7", "span = 90", 'units = "m"', "",
             "[defaults.planarize-strips]", 'strips = "0:0"', ""]
    for k in range(1, n + 1):
        lines += [f"[patches.twist-{k:03d}.init]", f"twist = {0.05 * k:.2f}", ""]
    path = folder / "sweep.toml"
    path.write_text("\n".join(lines), encoding="utf-8")
    return path


def sweep(n: int, workers: int) -> None:
    """The ``n``-patch sweep from an empty folder and its rerun; prints the figures."""
    with tempfile.TemporaryDirectory(prefix="dgpc-batch-sweep-") as tmp:
        project = sweep_project(Path(tmp), n)
        first = run_batch(project, Path(tmp) / "out", workers)
        again = run_batch(project, Path(tmp) / "out", workers)
    overhead = (workers * first["batch"] - first["tasks"]) / first["n"]
    print(f"sweep: {n} patches, {first['n']} tasks on {workers} local workers: wall "
          f"{first['wall']:.1f} s, batch {first['batch']:.1f} s, tasks {first['tasks']:.1f} s, "
          f"overhead per task {1000 * overhead:.0f} ms ({first['status']})")
    print(f"sweep: rerun recomputed {again['n']} tasks, wall {again['wall']:.1f} s, batch "
          f"{again['batch']:.2f} s")


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
    ap.add_argument("--sweep", type=int, default=100, metavar="N",
                    help="patches of the generated sweep (0: none)")
    ap.add_argument("--workers", type=int, default=2, help="local workers of the sweep")
    ap.add_argument("--sweep-only", action="store_true", help="only the generated sweep")
    args = ap.parse_args(argv)
    if args.sweep_only:
        sweep(args.sweep, args.workers)
        return 0
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
    if args.sweep:
        sweep(args.sweep, args.workers)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
