"""The commit of a multi-file write (SPEC §3): a journal that makes a set of renames
happen as one.

Every file of an artifact is first written under a hidden temporary name; then a journal
``.NAME.journal`` listing every rename (temp -> target) and every file to remove is made
visible in one rename: that is the commit. The renames follow and the journal is removed. A
process killed before the commit leaves the old set untouched (its temporary files are removed
by the next writer, :func:`remove_leftovers`); killed after it, the journal lets the next
reader or writer finish the renames, so it sees the new set whole (:func:`finish_interrupted`).

A journal is obeyed only where it names the files of its own artifact (:func:`family`): the
manifest's ``STEM.*`` (a report's ``PREFIX-*``), in the journal's folder, each renamed from
a temporary file of its own name. Any other entry (a journal placed by hand, or one of
another program) is refused before anything is renamed or removed, and left alone.
"""

from __future__ import annotations

import glob
import json
import logging
import os
import re
import tempfile
import time
from pathlib import Path

from ..errors import DgpcError
from .lock import output_lock

log = logging.getLogger(__name__)


def write_temp(path: Path, data: bytes, mode: int) -> Path:
    """Write ``data`` to a hidden temp file beside ``path`` (flushed and fsynced)."""
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    tmp = Path(name)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return tmp


def fsync_dir(directory: Path) -> None:
    """Flush a directory entry (renames) to disk where the system allows it."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


#: How long a reader waits for a live writer to finish its renames (seconds).
JOURNAL_WAIT = 30.0


def journal_path(manifest: str | Path) -> Path:
    """``.NAME.journal`` beside the artifact JSON (or first file) ``manifest``."""
    manifest = Path(manifest)
    return manifest.parent / f".{manifest.name}.journal"


def manifest_of(paths: list[Path]) -> Path:
    """The file of a set that names its journal: the first JSON, else the first index page
    (a report's ``PREFIX-index.html``), else the first file."""
    return next((p for p in paths if p.suffix == ".json"),
                next((p for p in paths if p.name.endswith("index.html")), paths[0]))


#: Pages written in one set with a JSON of another stem (the batch's summary).
COMPANIONS = {"batch.json": ("index.html",)}
#: A temporary file of :func:`write_temp` for the file ``NAME``: ``.NAME.<random>.tmp``.
_TEMP = re.compile(r"\.(?P<name>.+)\.[A-Za-z0-9_]+\.tmp")
#: A backup of :mod:`.atomic` of the file ``NAME``: ``.NAME.<hex>.bak``.
_BACKUP = re.compile(r"\.(?P<name>.+)\.[0-9a-f]+\.bak")


def family(manifest: str) -> tuple[str, tuple[str, ...]]:
    """The prefix the names of the artifact ``manifest`` begin with (``STEM.`` of a JSON or
    OBJ, ``PREFIX-`` of a report's ``PREFIX-index.html``), and its companion names."""
    for suffix in (".json", ".obj"):
        if manifest.endswith(suffix):
            return manifest[: -len(suffix)] + ".", COMPANIONS.get(manifest, ())
    if manifest.endswith("-index.html"):
        return manifest[: -len("index.html")], ()
    return manifest, ()


def _plan(doc, journal: Path) -> tuple[list[tuple[Path, Path]], list[Path]]:
    """The renames and removals of a journal, every one checked to belong to its artifact;
    a DgpcError naming the journal and the first entry that does not (nothing done)."""
    def refuse(what: str):
        raise DgpcError(f"the journal of an interrupted write names {what}, which is not a "
                        "file of its artifact: nothing done; remove the journal if it is not "
                        "dgpc's", source=journal)

    manifest = journal.name[1: -len(".journal")] if journal.name.startswith(".") \
        and journal.name.endswith(".journal") else ""
    prefix, companions = family(manifest)

    def own(name) -> bool:
        return isinstance(name, str) and bool(manifest) and "/" not in name \
            and "\\" not in name and name not in ("", ".", "..") \
            and (name == manifest or name in companions or name.startswith(prefix))

    if not isinstance(doc, dict) or not isinstance(doc.get("replace", []), list) \
            or not isinstance(doc.get("remove", []), list) or set(doc) - {"replace", "remove"}:
        refuse("something other than its replace and remove lists")
    directory = journal.parent
    renames, targets = [], set()
    for pair in doc.get("replace", []):
        if not (isinstance(pair, list) and len(pair) == 2 and own(pair[1])
                and isinstance(pair[0], str) and "/" not in pair[0]):
            refuse(repr(pair))
        temp = _TEMP.fullmatch(pair[0])
        if temp is None or temp["name"] != pair[1]:
            refuse(repr(pair[0]))
        renames.append((directory / pair[0], directory / pair[1]))
        targets.add(pair[1])
    removals = []
    for name in doc.get("remove", []):
        backup = _BACKUP.fullmatch(name) if isinstance(name, str) and "/" not in name else None
        if not (own(name) or (backup is not None and backup["name"] in targets)):
            refuse(repr(name))
        removals.append(directory / name)
    return renames, removals


def _relative(path: Path, directory: Path) -> str:
    return Path(os.path.relpath(os.path.abspath(path), os.path.abspath(directory))).as_posix()


def commit(journal: Path, renames: list[tuple[Path, Path]], remove: list[Path]) -> None:
    """Make the journal of ``renames`` (temp -> target) and ``remove`` visible in one rename."""
    directory = journal.parent
    doc = {"replace": [[_relative(t, directory), _relative(p, directory)] for t, p in renames],
           "remove": [_relative(p, directory) for p in remove]}
    tmp = write_temp(journal, (json.dumps(doc, indent=1) + "\n").encode(), 0o600)
    os.replace(tmp, journal)
    fsync_dir(directory)


def _replay(journal: Path) -> None:
    """Finish the renames a committed journal lists, remove what it lists, then the journal."""
    try:
        doc = json.loads(journal.read_bytes())
    except (OSError, ValueError, RecursionError) as e:
        raise DgpcError(f"cannot read the journal of an interrupted write ({e}); remove it to "
                        "keep the files as they are, or write the artifact again after removing "
                        "it", source=journal) from None
    directory = journal.parent
    renames, removals = _plan(doc, journal)
    for tmp, path in renames:
        if tmp.exists():
            os.replace(tmp, path)
    for path in removals:
        path.unlink(missing_ok=True)
    journal.unlink(missing_ok=True)
    fsync_dir(directory)
    log.info("%s: finished a write that was interrupted after its commit", journal.parent)


def enclosing_manifests(manifest: str | Path) -> list[Path]:
    """The JSONs whose journal may hold a write of ``manifest``: itself and, for a member
    ``STEM.pK.json`` of a patch set, ``STEM.json`` (every shorter dotted stem of its name),
    whose one commit writes the set and its members together."""
    manifest = Path(manifest)
    parts = manifest.name.split(".")
    found = [manifest]
    if manifest.suffix == ".json":
        found += [manifest.with_name(".".join(parts[:k]) + ".json")
                  for k in range(len(parts) - 2, 0, -1)]
    return found


def finish_interrupted(manifest: str | Path) -> None:
    """Before reading the artifact ``manifest``: finish a write of it that was interrupted
    after its commit, so that the reader sees the new set whole (never a mix): its own
    journal's, or that of the patch set it is a member of (:func:`enclosing_manifests`).

    A live writer in the middle of its renames is waited for (at most :data:`JOURNAL_WAIT`
    seconds). Nothing to do, and a ``stat`` per dotted part of its name, when no journal
    lies beside it.
    """
    for each in enclosing_manifests(manifest):
        if journal_path(each).exists():
            _finish(each)


def _finish(manifest: Path) -> None:
    journal = journal_path(manifest)
    deadline = time.monotonic() + JOURNAL_WAIT
    while journal.exists():
        with output_lock(manifest, wait=True) as held:
            if held:
                try:
                    _replay(journal)
                except OSError as e:
                    raise DgpcError(f"cannot finish an interrupted write of it: "
                                    f"{e.strerror or e}", source=manifest) from None
                return
        if time.monotonic() > deadline:
            raise DgpcError("another dgpc process is still writing it; try again when it "
                            "has ended", source=manifest)
        time.sleep(0.05)


def remove_leftovers(targets: list[Path]) -> None:
    """Temporary and backup files of the targets (and of their journal) left by a killed
    writer; to be called by the writer holding the lock of the output."""
    for path in [*targets, journal_path(manifest_of(targets))]:
        pattern = glob.escape(str(path.parent / f".{path.name}.")) + "*"
        for name in glob.glob(pattern + ".tmp") + glob.glob(pattern + ".bak"):
            Path(name).unlink(missing_ok=True)
