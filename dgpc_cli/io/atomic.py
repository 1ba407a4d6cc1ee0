"""All-or-nothing writing of several files (SPEC §3: temp files, one commit, renames; nothing
partial, never a mix of an old and a new set: :mod:`.journal`)."""

from __future__ import annotations

import logging
import os
import secrets
from collections.abc import Iterable
from pathlib import Path

from ..errors import DgpcError
from .artifact import listed_files
from .journal import (
    commit,
    finish_interrupted,
    fsync_dir,
    journal_path,
    manifest_of,
    remove_leftovers,
    write_temp,
)

log = logging.getLogger(__name__)


def _check_targets(paths: list[Path], force: bool) -> None:
    for path in paths:
        parent = path.parent
        if not parent.is_dir():
            raise DgpcError("directory does not exist", source=parent)
        if path.is_dir():
            raise DgpcError("is a directory, cannot write a file there", source=path)
        if path.exists() and not force:
            raise DgpcError("already exists; use --force to overwrite", source=path)


def _backup(path: Path) -> Path | None:
    """Hard link of an existing target so that a failed batch can restore it (None if absent)."""
    if not path.exists():
        return None
    name = path.parent / f".{path.name}.{secrets.token_hex(6)}.bak"
    try:
        os.link(path, name)
    except OSError:  # no hard links on this file system: the old file cannot be restored
        log.debug("no backup of %s (hard links unsupported)", path)
        return None
    return name


def _stale_files(targets: list[Path], replaces: Iterable[Path]) -> list[Path]:
    """Files of the previous output (listed by its artifact JSONs, or in ``replaces``) that are
    not among ``targets``."""
    keep = {os.path.abspath(p) for p in targets}
    previous = [*replaces]
    for path in targets:
        if path.suffix == ".json" and path.is_file():
            previous += listed_files(path)
    stale, seen = [], set()
    for path in previous:
        key = os.path.abspath(path)
        if key not in keep and key not in seen and Path(path).is_file():
            seen.add(key)
            stale.append(Path(path))
    return stale


def write_files(files: dict[Path, bytes], *, force: bool = False,
                replaces: Iterable[Path] = ()) -> None:
    """Write every ``path → bytes`` of ``files`` or none of them.

    All targets are checked first (parent directory exists; target absent unless ``force``),
    then each is written to a hidden temp file in its own directory, flushed and fsynced, and
    only then moved onto its target with ``os.replace``. On any failure the temp files are
    removed, targets already replaced in this call are restored from a hard-link backup (or
    removed if they did not exist before), and the error is raised (an ``OSError`` as a
    DgpcError naming the file).

    With ``force``, the files of the output being replaced that the new set does not hold are
    removed once every new file is in place: those that each existing artifact JSON among the
    targets lists (:func:`~dgpc_cli.io.artifact.listed_files`; nest sheets of a previous,
    longer layout) and ``replaces`` (e.g. the figures an earlier report linked).
    """
    items = [(Path(p), bytes(d)) for p, d in files.items()]
    if not items:
        return
    targets = [p for p, _ in items]
    journal = journal_path(manifest_of(targets))
    if journal.parent.is_dir():
        finish_interrupted(manifest_of(targets))
        remove_leftovers(targets)
    _check_targets(targets, force)
    stale = _stale_files(targets, replaces) if force else []
    umask = os.umask(0)
    os.umask(umask)
    mode = 0o666 & ~umask
    temps: list[Path] = []
    existed = {p: p.exists() for p, _ in items}
    backups: dict[Path, Path | None] = {}
    replaced: list[Path] = []
    current = items[0][0] if items else None
    try:
        for path, data in items:
            current = path
            temps.append(write_temp(path, data, mode))
        for path in (p for p, _ in items):
            backups[path] = _backup(path)
        commit(journal, [(t, p) for t, (p, _) in zip(temps, items, strict=True)],
                stale + [b for b in backups.values() if b is not None])
        for (path, _), tmp in zip(items, temps, strict=True):
            current = path
            os.replace(tmp, path)
            replaced.append(path)
    except BaseException as e:
        for tmp in temps:
            tmp.unlink(missing_ok=True)
        for path in replaced:
            if backups.get(path) is not None:
                os.replace(backups.pop(path), path)
            elif not existed[path]:
                path.unlink(missing_ok=True)
        for bak in backups.values():
            if bak is not None:
                bak.unlink(missing_ok=True)
        journal.unlink(missing_ok=True)
        if isinstance(e, OSError):
            raise DgpcError(f"cannot write: {e.strerror or e}", source=current) from e
        raise
    for bak in backups.values():
        if bak is not None:
            bak.unlink(missing_ok=True)
    for path in stale:
        try:
            path.unlink(missing_ok=True)
        except OSError as e:
            log.warning("%s: stale file of the previous output not removed: %s", path,
                        e.strerror or e)
    journal.unlink(missing_ok=True)
    if stale:
        log.debug("removed %s", ", ".join(str(p) for p in stale))
    for directory in {p.parent for p, _ in items}:
        fsync_dir(directory)
    log.debug("wrote %s", ", ".join(str(p) for p, _ in items))
