"""The commit of a multi-file write (SPEC §3): a journal that makes a set of renames
happen as one.

Every file of an artifact is first written under a hidden temporary name; then a journal
``.NAME.journal`` listing every rename (temp -> target) and every file to remove is made
visible in one rename: that is the commit. The renames follow and the journal is removed. A
process killed before the commit leaves the old set untouched (its temporary files are removed
by the next writer, :func:`remove_leftovers`); killed after it, the journal lets the next
reader or writer finish the renames, so it sees the new set whole (:func:`finish_interrupted`).
"""

from __future__ import annotations

import glob
import json
import logging
import os
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
    """The file of a set that names its journal: the first JSON, else the first file."""
    return next((p for p in paths if p.suffix == ".json"), paths[0])


def _relative(path: Path, directory: Path) -> str:
    return Path(os.path.relpath(os.path.abspath(path), os.path.abspath(directory))).as_posix()


def _inside(text: object, directory: Path) -> Path | None:
    """``directory / text`` for a relative path without ``..`` (None otherwise)."""
    if not isinstance(text, str) or not text or os.path.isabs(text) \
            or ".." in Path(text).parts:
        return None
    return directory / text


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
    except (OSError, ValueError) as e:
        raise DgpcError(f"cannot read the journal of an interrupted write ({e}); remove it to "
                        "keep the files as they are, or write the artifact again after removing "
                        "it", source=journal) from None
    directory = journal.parent
    renames = doc.get("replace", []) if isinstance(doc, dict) else []
    for pair in renames if isinstance(renames, list) else []:
        tmp, path = (_inside(x, directory) for x in pair) if isinstance(pair, list) \
            and len(pair) == 2 else (None, None)
        if tmp is None or path is None or not tmp.name.endswith(".tmp"):
            raise DgpcError("the journal of an interrupted write lists an unexpected path",
                            source=journal)
        if tmp.exists():
            os.replace(tmp, path)
    for text in doc.get("remove", []) if isinstance(doc, dict) else []:
        path = _inside(text, directory)
        if path is not None:
            path.unlink(missing_ok=True)
    journal.unlink(missing_ok=True)
    fsync_dir(directory)
    log.info("%s: finished a write that was interrupted after its commit", journal.parent)


def finish_interrupted(manifest: str | Path) -> None:
    """Before reading the artifact ``manifest``: finish a write of it that was interrupted
    after its commit, so that the reader sees the new set whole (never a mix).

    A live writer in the middle of its renames is waited for (at most :data:`JOURNAL_WAIT`
    seconds). Nothing to do, and a single ``stat``, when no journal lies beside it.
    """
    journal = journal_path(manifest)
    if not journal.exists():
        return
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
