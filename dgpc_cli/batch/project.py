"""The project file of ``dgpc batch`` (TOML, read with :mod:`tomllib`).

::

    [project]                 # optional
    report = true             # figures of every patch and shared stage (dgpc report)

    [defaults.init]           # stage options every patch starts from
    surface = "revolution"
    profile = "../profiles/gehry.csv"      # files: relative to the project file
    rows = 21
    ...
    [defaults.optimize]
    mode = "isometric"
    max-strain = 3e-4

    [patches.facade-1.optimize]            # a patch: its own options over the defaults
    handles = "../handles/gehry-1-21x13.json"

    [molds.gehry]             # extract-mold over these patches' final nets (one mold)
    patches = ["facade-1", "facade-2"]
    panel-size = 2

    [nest]                    # one nesting of the flat parts of these patches (default: all
    mold = "gehry"            # that unfold), with a mold's panel map
    sheet = "6000x1250"

A patch runs ``init`` and then, in this order, those of ``optimize``, ``planarize-strips`` and
``unfold`` that its defaults or its own tables name (a stage set to ``false`` in the patch is
left out). Keys are the commands' long options without ``--`` (``max-strain``, ``gpc-tol``;
``_`` stands for ``-``); ``true`` gives a flag, a list repeats an option (``weight``); init's
mesh is ``reference``. ``-o`` and ``--force`` are the batch's. Every problem is a
:class:`ProjectError` naming the file and the key.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.bounded_read import read_regular

#: The stages of a patch, in the order they run.
PATCH_STAGES = ("init", "optimize", "planarize-strips", "unfold")
#: Stages of the whole project (they read several patches' artifacts).
SHARED_STAGES = ("extract-mold", "nest")
#: Options the batch sets itself (or that would write outside the output folder).
RESERVED = {"output": "the batch names every output",
            "force": "the batch overwrites what it recomputes",
            "reference-out": "a batch writes only into its output folder",
            "patches": "a batch patch is one net: split the mesh with `dgpc init --patches` "
                       "and name each STEM.pK.patch.obj as a patch's init reference"}
#: Folder of the shared stages' artifacts in the output folder (no patch may be called so).
SHARED = "shared"
#: The batch's own files in the output folder (no patch may be called so).
BATCH_FILES = ("batch.json", "index.html")
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
#: Longest name: a patch's folder, a mold's files (``mold-NAME-report-index.html``) and their
#: hidden temporary names stay well within a file name's 255 bytes.
NAME_MAX = 64
#: Names a Windows file system keeps for devices (with any extension), compared in lower case.
DEVICES = re.compile(r"(con|prn|aux|nul|com[0-9]|lpt[0-9])(\..*)?")


class ProjectError(DgpcError):
    """A bad project file (exit 1): ``source`` is the file, the message names the key."""


@dataclass(frozen=True)
class StageSpec:
    """What a command accepts: its long options by name with their kind (``flag``, ``value``,
    ``multiple``, or ``path``/``paths`` for input files) and its optional positional input
    (init's mesh)."""

    options: dict[str, str]
    positional: str | None = None


@dataclass
class Options:
    """The options of one stage: ``values`` (name → value as given: bool, number, string or a
    list of them) and ``files`` (name → the resolved input files among them)."""

    values: dict[str, object] = field(default_factory=dict)
    files: dict[str, list[Path]] = field(default_factory=dict)


@dataclass
class Patch:
    name: str
    stages: dict[str, Options]          # PATCH_STAGES order, init first


@dataclass
class Mold:
    name: str
    patches: list[str]
    options: Options


@dataclass
class Nest:
    patches: list[str]
    mold: str | None
    options: Options


@dataclass
class Project:
    path: Path
    patches: dict[str, Patch]
    molds: dict[str, Mold]
    nest: Nest | None
    report: bool = True


def load_project(path: str | Path, specs: dict[str, StageSpec]) -> Project:
    """Read and check the project file ``path``; ``specs`` describes every stage's command."""
    path = Path(path)
    try:
        data = read_regular(path, "a project file (TOML)")
    except DgpcError as e:
        raise ProjectError(e.reason, source=path) from None
    try:
        text = data.decode("utf-8")
        doc = tomllib.loads(text)
    except UnicodeDecodeError as e:
        line = data_line(data, e.start)
        raise ProjectError(f"not UTF-8 text: byte 0x{e.object[e.start]:02x} at line {line} "
                           "(save the file as UTF-8)", source=path) from None
    except tomllib.TOMLDecodeError as e:
        raise ProjectError(f"not valid TOML: {e}", source=path) from None
    return _Reader(path, specs).project(doc)


class _Reader:
    def __init__(self, path: Path, specs: dict[str, StageSpec]):
        self.path, self.specs = path, specs
        self.folder = path.resolve().parent

    def fail(self, key: str, message: str):
        raise ProjectError(f"{key}: {message}", source=self.path)

    def table(self, value, key: str) -> dict:
        if not isinstance(value, dict):
            self.fail(key, f"must be a table, not {_type(value)}")
        return value

    def name(self, value, key: str) -> str:
        """A patch's or a mold's name: a file name on every system, none of the batch's own."""
        if not isinstance(value, str) or not NAME.fullmatch(value):
            self.fail(key, f"{value!r} is not a name: letters, digits, '.', '_' and '-', "
                           "starting with a letter or digit")
        if len(value) > NAME_MAX:
            self.fail(key, f"a name of {len(value)} characters; at most {NAME_MAX}")
        low = value.lower()
        if low in (SHARED, *BATCH_FILES) or DEVICES.fullmatch(low):
            self.fail(key, f"{value!r} is not a name for a patch or a mold: reserved (the "
                           f"batch's {SHARED}/, {', '.join(BATCH_FILES)}, or a device name on "
                           "Windows)")
        if low.endswith((".", ".json", ".obj")):
            self.fail(key, f"{value!r} ends like a file name (.json, .obj) or with '.'")
        return value

    def project(self, doc: dict) -> Project:
        unknown = sorted(set(doc) - {"project", "defaults", "patches", "molds", "nest"})
        if unknown:
            self.fail(unknown[0], "unknown table (project, defaults, patches, molds, nest)")
        settings = self.table(doc.get("project", {}), "project")
        for key in settings:
            if key != "report":
                self.fail(f"project.{key}", "unknown key (report)")
        report = settings.get("report", True)
        if not isinstance(report, bool):
            self.fail("project.report", "must be true or false")
        defaults = self.table(doc.get("defaults", {}), "defaults")
        for key in defaults:
            if key not in PATCH_STAGES:
                self.fail(f"defaults.{key}", f"not a stage of a patch ({', '.join(PATCH_STAGES)})")
        patches_doc = self.table(doc.get("patches", {}), "patches")
        if not patches_doc:
            self.fail("patches", "no patch: add a table [patches.NAME]")
        patches = {name: self.patch(name, body, defaults) for name, body in patches_doc.items()}
        molds = {}
        for name, body in self.table(doc.get("molds", {}), "molds").items():
            molds[name] = self.mold(name, body, patches)
        nest = None
        if "nest" in doc:
            nest = self.nest(self.table(doc["nest"], "nest"), patches, molds)
        self.collisions(patches, molds, report)
        return Project(self.path, patches, molds, nest, report)

    def collisions(self, patches: dict, molds: dict, report: bool) -> None:
        """No two patches share a folder and no two shared stages a stem, on a file system
        that ignores case as well (``A`` and ``a``; mold ``x-report`` and mold ``x``'s
        report)."""
        seen: dict[str, str] = {}
        for name in patches:
            other = seen.setdefault(name.lower(), f"patches.{name}")
            if other != f"patches.{name}":
                self.fail(f"patches.{name}", f"its folder collides with {other}'s (names "
                                             "differing only in case)")
        stems = {"sheets": "nest", **({"sheets-report": "nest's report"} if report else {})}
        for name in molds:
            for stem, what in [(f"mold-{name}", f"molds.{name}"),
                               *([(f"mold-{name}-report", f"molds.{name}'s report")]
                                 if report else [])]:
                other = stems.setdefault(stem.lower(), what)
                if other != what:
                    self.fail(f"molds.{name}", f"its files ({SHARED}/{stem}) collide with "
                                               f"those of {other}")

    def patch(self, name: str, body, defaults: dict) -> Patch:
        self.name(name, f"patches.{name}")
        body = self.table(body, f"patches.{name}")
        for key in body:
            if key not in PATCH_STAGES:
                self.fail(f"patches.{name}.{key}",
                          f"not a stage of a patch ({', '.join(PATCH_STAGES)})")
        stages = {}
        for stage in PATCH_STAGES:
            own = body.get(stage)
            if own is False:
                if stage == "init":
                    self.fail(f"patches.{name}.init", "every patch starts with init")
                continue
            if own is None and stage not in defaults:
                continue
            merged = {**self.table(defaults.get(stage, {}), f"defaults.{stage}"),
                      **self.table(own if own is not None else {}, f"patches.{name}.{stage}")}
            stages[stage] = self.options(stage, merged, f"patches.{name}.{stage}")
        if "init" not in stages:
            self.fail(f"patches.{name}", "no init: give [defaults.init] or "
                                         f"[patches.{name}.init]")
        if "unfold" in stages and "planarize-strips" not in stages:
            self.fail(f"patches.{name}", "unfold needs planarize-strips")
        return Patch(name, stages)

    def patch_list(self, value, key: str, patches: dict) -> list[str]:
        if not isinstance(value, list) or not value or not all(isinstance(v, str)
                                                               for v in value):
            self.fail(key, "must be a non-empty list of patch names")
        for v in value:
            if v not in patches:
                self.fail(key, f"no patch {v!r}")
        if len(set(value)) != len(value):
            self.fail(key, "a patch is named twice")
        return list(value)

    def mold(self, name: str, body, patches: dict) -> Mold:
        key = f"molds.{name}"
        self.name(name, key)
        body = dict(self.table(body, key))
        if "patches" not in body:
            self.fail(key, "needs patches = [...]: the patches that share the mold")
        members = self.patch_list(body.pop("patches"), f"{key}.patches", patches)
        return Mold(name, members, self.options("extract-mold", body, key))

    def nest(self, body: dict, patches: dict, molds: dict) -> Nest:
        body = dict(body)
        members = (self.patch_list(body.pop("patches"), "nest.patches", patches)
                   if "patches" in body else
                   [n for n, p in patches.items() if "unfold" in p.stages])
        for m in members:
            if "unfold" not in patches[m].stages:
                self.fail("nest.patches", f"patch {m!r} has no unfold stage: nothing to nest")
        if not members:
            self.fail("nest", "no patch unfolds its strips: nothing to nest")
        mold = body.pop("mold", None)
        if mold is not None and mold not in molds:
            self.fail("nest.mold", f"no mold {mold!r} (a table [molds.{mold}])")
        return Nest(members, mold, self.options("nest", body, "nest"))

    def options(self, stage: str, body: dict, key: str) -> Options:
        spec = self.specs[stage]
        out = Options()
        for raw, value in body.items():
            name = raw.replace("_", "-")
            where = f"{key}.{raw}"
            if name in RESERVED:
                self.fail(where, f"not in a project file: {RESERVED[name]}")
            if name == spec.positional:
                kind = "path"
            elif name in spec.options:
                kind = spec.options[name]
            else:
                self.fail(where, f"dgpc {stage} has no option --{name}")
            out.values[name] = self.value(value, kind, where)
            files = self.files(value, kind, stage, name)
            if files:
                out.files[name] = files
        return out

    def value(self, value, kind: str, where: str):
        if kind == "flag":
            if not isinstance(value, bool):
                self.fail(where, "a flag: true or false")
            return value
        items = value if isinstance(value, list) and kind in ("multiple", "paths") else [value]
        if isinstance(value, list) and kind not in ("multiple", "paths"):
            self.fail(where, "takes one value, not a list")
        for item in items:
            if isinstance(item, bool) or not isinstance(item, str | int | float):
                self.fail(where, f"must be a string or a number, not {_type(item)}")
        return value

    def files(self, value, kind: str, stage: str, name: str) -> list[Path]:
        """The input files an option names, resolved against the project file's folder (a
        profile that is no file there is a built-in profile's name)."""
        if kind not in ("path", "paths") and not (stage == "init" and name == "profile"):
            return []
        items = value if isinstance(value, list) else [value]
        found = [self.folder / str(v) for v in items]
        if kind not in ("path", "paths"):
            found = [p for p in found if p.is_file()]
        return found


def data_line(data: bytes, offset: int) -> int:
    """The line (from 1) of the byte at ``offset``."""
    return data.count(b"\n", 0, offset) + 1


def _type(value) -> str:
    return {dict: "a table", list: "a list", bool: "a boolean", str: "a string",
            int: "an integer", float: "a number"}.get(type(value), type(value).__name__)
