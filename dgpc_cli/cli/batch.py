"""``dgpc batch``: every patch of a project, and its shared stages, on a Dask cluster.

Importing this module imports neither Dask nor a numerical library (``dgpc --version`` stays
light): they are imported when the command runs.
"""

from __future__ import annotations

import logging
from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.output_path import OutputPath

log = logging.getLogger(__name__)


def stage_specs() -> dict:
    """What each stage's dgpc command accepts, read from the commands themselves."""
    from dgpc_cli.batch.project import PATCH_STAGES, SHARED_STAGES, StageSpec
    from dgpc_cli.cli.main import cli

    ctx = click.Context(cli)
    specs = {}
    for stage in (*PATCH_STAGES, *SHARED_STAGES):
        command = cli.get_command(ctx, stage)
        options: dict[str, str] = {}
        positional = None
        for param in command.params:
            if isinstance(param, click.Argument):
                if stage == "init":
                    positional = param.name
                continue
            kind = ("flag" if getattr(param, "is_flag", False) else
                    "multiple" if param.multiple else
                    "path" if isinstance(param.type, click.Path) else "value")
            for opt in (*param.opts, *param.secondary_opts):
                if opt.startswith("--"):
                    options[opt[2:]] = kind
        specs[stage] = StageSpec(options, positional)
    return specs


def _duration(seconds: float | None) -> str:
    if seconds is None:
        return "?"
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


def _progress_line(p) -> str:
    from dgpc_cli.batch.project import SHARED

    what = "shared stages done" if p.group == SHARED else f"{p.group} done"
    return (f"batch: {p.groups_done}/{p.groups_total} {what}, {p.tasks_done}/{p.tasks_total} "
            f"tasks, {_duration(p.elapsed_s)} elapsed, ETA {_duration(p.eta_s)}")


@click.command(short_help="Run a project of many patches (a facade, a sweep) on Dask.")
@click.argument("project", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("-o", "--output", "out", required=True,
              type=OutputPath(folder=True),
              help="Output folder: DIR/PATCH/ per patch, DIR/shared/ (molds, sheets), "
                   "DIR/batch.json and DIR/index.html.")
@click.option("--scheduler", metavar="ADDRESS",
              help="A running Dask scheduler (tcp://HOST:8786) instead of a local cluster; "
                   "its workers must see the project's files and DIR at the same paths.")
@click.option("--workers", type=click.IntRange(min=1),
              help="Worker processes of the local cluster [default: the number of cores].")
@click.option("--timeout", type=FiniteFloat(min=0, min_open=True, max=3600), default=20.0,
              show_default=True, metavar="SECONDS",
              help="Seconds (up to 3600) the scheduler at --scheduler has to answer, and then "
                   "to have a worker.")
@click.option("-q", "--quiet", is_flag=True, help="No progress on stderr (as `dgpc -q`).")
@click.pass_context
def batch(ctx, project, out, scheduler, workers, timeout, quiet):
    """Run every patch of the project file PROJECT (TOML) and then its shared stages (molds,
    one nesting of all parts) with Dask: a local cluster by default, or the scheduler at
    --scheduler. Each task is the dgpc command a user would type, run from this folder, and
    writes the same files; a task whose inputs (sha256) and options have not changed since
    the last run into DIR is reused. A failed patch does not stop the others.

    Prints DIR/batch.json (per patch: status, message, key metrics, outputs; wall times
    under this_run) and writes DIR/index.html linking every report. Exit code 0 when every
    task succeeded, 3 when some only missed a tolerance, 1 otherwise.

    The project file (paths in it are relative to it):

    \b
    [defaults.init]              # options of `dgpc init` for every patch
    surface = "revolution"
    profile = "../profiles/gehry.csv"
    rows = 21
    cols = 13
    [defaults.optimize]          # then optimize, planarize-strips, unfold
    mode = "isometric"
    [patches.facade-1.optimize]  # a patch: its options over the defaults
    handles = "../handles/gehry-1-21x13.json"
    [molds.gehry]                # extract-mold over these patches
    patches = ["facade-1", "facade-2"]
    [nest]                       # one nesting of every patch's parts
    mold = "gehry"
    sheet = "6000x1250"
    """
    if scheduler is not None and workers is not None:
        raise click.UsageError("--workers sizes the local cluster; with --scheduler the "
                               "scheduler's workers run the tasks")
    from dgpc_cli.batch.graph import build_tasks
    from dgpc_cli.batch.project import load_project
    from dgpc_cli.batch.summary import batch_doc, write_summary
    from dgpc_cli.cli.batch_tasks import run_task
    from dgpc_cli.errors import DgpcError, NotConverged
    from dgpc_cli.stages.batch import connect, machine_cores, run_batch

    if workers is not None and workers > machine_cores():
        log.warning("--workers %d: this machine has %d cores; running %d worker processes "
                    "(--scheduler for a cluster's workers)", workers, machine_cores(),
                    machine_cores())
        workers = machine_cores()
    show = not quiet and ctx.obj.get("verbosity", 0) >= 0
    proj = load_project(project, stage_specs())
    if out.exists() and not out.is_dir():
        raise DgpcError("is not a folder", source=out)
    base = Path.cwd()
    tasks = build_tasks(proj, out, base)

    def progress(p):
        if show:
            click.echo(_progress_line(p), err=True)

    client, cluster, info = connect(scheduler, workers, timeout)
    try:
        out.mkdir(parents=True, exist_ok=True)
        if show:
            where = (f"the scheduler at {scheduler}" if cluster is None
                     else "a local cluster")
            click.echo(f"batch: {len(proj.patches)} patches, {len(tasks)} tasks on {where} "
                       f"of {info['workers']} workers", err=True)
        run = run_batch(tasks, out, base, client, run_task, progress=progress)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    doc = batch_doc(proj, tasks, run.records, run.executed, out, wall_time_s=run.wall_time_s,
                    cluster=info)
    path = write_summary(doc, out, announce=lambda written: click.echo(str(written)))
    ran = sum(run.executed.values())
    counts = {s: sum(1 for p in doc["patches"].values() if p["status"] == s)
              for s in ("ok", "not_converged", "failed", "blocked")}
    for name, group in [*doc["patches"].items(), *([("shared", doc["shared"])]
                                                    if "shared" in doc else [])]:
        if group["status"] == "not_converged":
            log.warning("%s: %s", name, group["message"])
        elif group["status"] != "ok":
            log.error("%s %s: %s", name, group["status"], group["message"])
    if show:
        click.echo(f"batch: {counts['ok']} ok, {counts['not_converged']} not converged, "
                   f"{counts['failed'] + counts['blocked']} failed"
                   + (f"; shared stages {doc['shared']['status']}" if "shared" in doc else "")
                   + f"; {ran} tasks ran, {len(tasks) - ran} reused or not run, in "
                   f"{_duration(run.wall_time_s)}", err=True)
    if doc["exit_code"] == 3:
        raise NotConverged("some tasks missed a tolerance (artifacts written; see "
                           "batch.json)", source=path)
    if doc["exit_code"] == 1:
        failed = [n for n, g in doc["patches"].items() if g["status"] in ("failed", "blocked")]
        what = (f"{len(failed)} of {len(doc['patches'])} patches failed ({', '.join(failed)})"
                if failed else "the shared stages failed")
        raise DgpcError(f"{what}; see batch.json", source=path)
