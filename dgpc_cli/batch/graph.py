"""A project as tasks: one dgpc command each, the same arguments a user would type.

Layout of the output folder ``DIR``::

    DIR/PATCH/base.json     init              DIR/shared/mold-NAME.json   extract-mold
    DIR/PATCH/net.json      optimize          DIR/shared/sheets.json      nest
    DIR/PATCH/strips.json   planarize-strips  DIR/shared/*-report-index.html
    DIR/PATCH/flat.json     unfold            DIR/batch.json, DIR/index.html
    DIR/PATCH/report-index.html (+ PNGs)      report of the patch's last net

Every path in a task's arguments is relative to the folder the batch runs from (``base``),
as in a Makefile run there: the artifacts record their inputs relative to themselves, and
``init`` records its ``--profile`` as given, so a batch and the same commands typed in the
same folder write the same bytes.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from dgpc_cli.io.artifact import artifact_paths

from .project import SHARED, Options, Project

#: The artifact stem each stage of a patch writes in the patch's folder.
STEMS = {"init": "base", "optimize": "net", "planarize-strips": "strips", "unfold": "flat"}
#: Prefix of the figures of ``dgpc report`` (``PREFIX-index.html``).
REPORT = "report"


@dataclass
class Task:
    """One dgpc command: ``dgpc COMMAND ARGS...`` run from ``base``.

    ``inputs`` are the files whose sha256 (with the command line) decides whether the task
    must run again; ``artifact`` its main output (an artifact's JSON, a report's index)
    relative to the output folder: the files it wrote are those this one lists (never a
    pattern, which would take a neighbour's or a user's files for its own);
    ``group`` the patch it belongs to, or ``shared``.
    """

    id: str
    command: str
    args: list[str]
    inputs: list[Path]
    artifact: str
    group: str
    deps: list[str] = field(default_factory=list)

    @property
    def argv(self) -> list[str]:
        return [self.command, *self.args]


def _rel(path: Path, base: Path) -> str:
    return Path(os.path.relpath(Path(path).resolve(), base.resolve())).as_posix()


def _option_args(options: Options, base: Path, positional: str | None = None) -> list[str]:
    """``--name value`` pairs of ``options`` (files relative to ``base``), the positional one
    first."""
    head, args = [], []
    for name, value in options.values.items():
        files = options.files.get(name)
        items = value if isinstance(value, list) else [value]
        if files is not None and len(files) == len(items):
            items = [_rel(f, base) for f in files]
        if name == positional:
            head += [str(v) for v in items]
        elif value is True:
            args.append(f"--{name}")
        elif value is False:
            continue
        else:
            for item in items:
                args += [f"--{name}", _number(item) if not isinstance(item, str) else item]
    return head + args


def _number(x) -> str:
    return repr(x) if isinstance(x, float) else str(x)


def _json(stem: Path) -> Path:
    """``STEM.json`` (a stem's name may hold dots: mold ``m.x``)."""
    return artifact_paths(stem)[0]


def _inputs(options: Options) -> list[Path]:
    return [f for files in options.files.values() for f in files]


class _Builder:
    def __init__(self, out: Path, base: Path):
        self.out, self.base = out, base
        self.tasks: dict[str, Task] = {}

    def rel(self, path: Path) -> str:
        return _rel(path, self.base)

    def artifact_task(self, tid: str, command: str, group: str, sources: list[Path],
                      options: Options, stem: Path, deps: list[str], *,
                      positional: str | None = None, extra: list[str] | None = None) -> Task:
        """A stage writing the artifact ``stem`` from the artifacts ``sources``."""
        args = ([self.rel(s) for s in sources] + _option_args(options, self.base, positional)
                + list(extra or []) + ["-o", self.rel(stem), "--force"])
        task = Task(tid, command, args,
                    inputs=[_json(s) for s in sources] + _inputs(options),
                    artifact=_rel(_json(stem), self.out), group=group, deps=deps)
        self.tasks[tid] = task
        return task

    def report_task(self, tid: str, group: str, stem: Path, prefix: Path, dep: str) -> Task:
        task = Task(tid, "report", [self.rel(stem), "-o", self.rel(prefix), "--force"],
                    inputs=[_json(stem)],
                    artifact=_rel(prefix.parent / f"{prefix.name}-index.html", self.out),
                    group=group, deps=[dep])
        self.tasks[tid] = task
        return task


def build_tasks(project: Project, out: str | Path, base: str | Path) -> dict[str, Task]:
    """Every task of ``project`` writing into ``out``, in an order that respects the
    dependencies (patches in the project's order, then the shared stages)."""
    out, base = Path(out).resolve(), Path(base).resolve()
    b = _Builder(out, base)
    last_net: dict[str, tuple[str, Path]] = {}     # patch -> (task id, stem)
    flat: dict[str, tuple[str, Path]] = {}
    for name, patch in project.patches.items():
        folder = out / name
        prev: tuple[str, Path] | None = None
        for stage, options in patch.stages.items():
            stem = folder / STEMS[stage]
            tid = f"{name}/{stage}"
            sources = [prev[1]] if prev else []
            deps = [prev[0]] if prev else []
            b.artifact_task(tid, stage, name, sources, options, stem, deps,
                            positional="reference" if stage == "init" else None)
            prev = (tid, stem)
            if stage in ("init", "optimize"):
                last_net[name] = prev
            if stage == "unfold":
                flat[name] = prev
        if project.report:
            tid, stem = last_net[name]
            b.report_task(f"{name}/report", name, stem, folder / REPORT, tid)
    shared = out / SHARED
    molds: dict[str, tuple[str, Path]] = {}
    for mold in project.molds.values():
        stem = shared / f"mold-{mold.name}"
        tid = f"{SHARED}/mold-{mold.name}"
        b.artifact_task(tid, "extract-mold", SHARED, [last_net[p][1] for p in mold.patches],
                        mold.options, stem, [last_net[p][0] for p in mold.patches])
        molds[mold.name] = (tid, stem)
        if project.report:
            b.report_task(f"{tid}/report", SHARED, stem, shared / f"mold-{mold.name}-report",
                          tid)
    if project.nest is not None:
        nest = project.nest
        stem = shared / "sheets"
        deps = [flat[p][0] for p in nest.patches]
        extra: list[str] = []
        sources = [flat[p][1] for p in nest.patches]
        inputs = []
        if nest.mold is not None:
            mtid, mstem = molds[nest.mold]
            deps.append(mtid)
            extra = ["--mold", b.rel(mstem)]
            inputs = [_json(mstem)]
        task = b.artifact_task(f"{SHARED}/nest", "nest", SHARED, sources, nest.options, stem,
                               deps, extra=extra)
        task.inputs += inputs
        if project.report:
            b.report_task(f"{SHARED}/nest/report", SHARED, stem, shared / "sheets-report",
                          task.id)
    return b.tasks


def patch_outputs(tasks: dict[str, Task], group: str) -> dict[str, str]:
    """Role → main output (relative to the output folder) of the tasks of ``group``."""
    roles = {"init": "base", "optimize": "net", "planarize-strips": "strips", "unfold": "flat",
             "report": "report", "extract-mold": "mold", "nest": "sheets"}
    out = {}
    for t in tasks.values():
        if t.group == group:
            key = roles[t.command]
            if group == SHARED and t.command == "report":
                key = f"{t.id.split('/')[1]}_report"
            elif group == SHARED and t.command == "extract-mold":
                key = t.id.split("/")[1]
            out[key] = t.artifact
    return out
