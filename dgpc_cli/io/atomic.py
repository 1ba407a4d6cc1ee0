"""All-or-nothing writing of several files (SPEC §3: temp files, one commit, renames; nothing
partial, never a mix of an old and a new set: :mod:`.journal`).

Writes made inside :func:`held_writes` (a patch set's members, each written by its own stage)
are checked and held instead, so that the caller commits them with the set's own JSON in one
:func:`write_files`: the set and its members change together, or not at all.

What a command prints on stdout about its output (the paths written) is printed by
``announce`` at the commit point, after the journal is visible and before the renames: when
stdout cannot be written (a full disk, a closed pipe) the commit is withdrawn and nothing is
written; a reader that meets the journal waits for the writer's lock, so the paths a consumer
reads from stdout are never older than the files.
"""

from __future__ import annotations

import contextvars
import logging
import os
import secrets
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import DgpcError
from .journal import (
    commit,
    finish_interrupted,
    fsync_dir,
    journal_path,
    manifest_of,
    remove_leftovers,
    write_temp,
)
from .patch_set import previous_files

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
    """Files of the previous output (those its artifact JSONs wrote and still hold as they
    wrote them, a patch set's members included: :func:`~dgpc_cli.io.patch_set.previous_files`,
    or in ``replaces``) that are not among ``targets``."""
    keep = {os.path.abspath(p) for p in targets}
    previous = [*replaces]
    for path in targets:
        if path.suffix == ".json" and path.is_file():
            previous += previous_files(path)
    stale, seen = [], set()
    for path in previous:
        key = os.path.abspath(path)
        if key not in keep and key not in seen and Path(path).is_file():
            seen.add(key)
            stale.append(Path(path))
    return stale


@dataclass
class Held:
    """The writes held by :func:`held_writes`, in order: each ``(files, stale, announce)``."""

    writes: list[tuple[dict[Path, bytes], list[Path], Callable[[], None] | None]] = \
        field(default_factory=list)

    @property
    def files(self) -> dict[Path, bytes]:
        """Every held ``path → bytes`` (a later write of a path wins)."""
        return {p: d for files, _, _ in self.writes for p, d in files.items()}

    @property
    def stale(self) -> list[Path]:
        """The files of the outputs being replaced that the held writes remove."""
        return [p for _, stale, _ in self.writes for p in stale]

    def announce(self) -> None:
        """Print what each held write would have printed at its commit, in order."""
        for _, _, announce in self.writes:
            if announce is not None:
                announce()

    def read(self, path: Path) -> bytes:
        """The bytes held for ``path``, else the file's."""
        key = os.path.abspath(path)
        for p, data in reversed(list(self.files.items())):
            if os.path.abspath(p) == key:
                return data
        return Path(path).read_bytes()

    def holds(self, path: Path) -> bool:
        key = os.path.abspath(path)
        return any(os.path.abspath(p) == key for p in self.files)

    def mark(self) -> int:
        return len(self.writes)

    def drop_since(self, mark: int) -> None:
        """Forget the writes held since :meth:`mark` (a member that failed after writing)."""
        del self.writes[mark:]


_HELD: contextvars.ContextVar[Held | None] = contextvars.ContextVar("dgpc_held_writes",
                                                                   default=None)


@contextmanager
def held_writes() -> Iterator[Held]:
    """Within the block, :func:`write_files` checks its targets and holds the files instead of
    writing them; the caller commits :attr:`Held.files` after the block, in one
    :func:`write_files` (with :attr:`Held.stale` among its ``replaces`` and
    :meth:`Held.announce` in its ``announce``), or drops them."""
    held = Held()
    token = _HELD.set(held)
    try:
        yield held
    finally:
        _HELD.reset(token)


def _announce(announce: Callable[[], None]) -> None:
    """Run ``announce`` (it prints on stdout); an OSError is stdout's: a DgpcError saying
    that nothing was written."""
    try:
        announce()
    except OSError as e:
        raise DgpcError(f"cannot write to stdout ({e.strerror or e}), so nothing was "
                        "written", source="stdout") from None


def write_files(files: dict[Path, bytes], *, force: bool = False,
                replaces: Iterable[Path] = (),
                announce: Callable[[], None] | None = None) -> None:
    """Write every ``path → bytes`` of ``files`` or none of them.

    All targets are checked first (parent directory exists; target absent unless ``force``),
    then each is written to a hidden temp file in its own directory, flushed and fsynced, and
    only then moved onto its target with ``os.replace``. On any failure the temp files are
    removed, targets already replaced in this call are restored from a hard-link backup (or
    removed if they did not exist before), and the error is raised (an ``OSError`` as a
    DgpcError naming the file).

    With ``force``, the files of the output being replaced that the new set does not hold are
    removed once every new file is in place: those that each existing artifact JSON among the
    targets wrote and still holds as it wrote them (a patch set's members among them:
    :func:`~dgpc_cli.io.patch_set.previous_files`; nest sheets of a previous, longer layout)
    and ``replaces`` (e.g. the figures an earlier report linked).

    ``announce`` (printing on stdout what was written) runs once the journal is committed,
    before the renames; if it fails, the commit is withdrawn and nothing is written. Within
    :func:`held_writes` the targets are checked and the files held, not written.
    """
    items = [(Path(p), bytes(d)) for p, d in files.items()]
    if not items:
        return
    targets = [p for p, _ in items]
    held = _HELD.get()
    if held is not None:
        _check_targets(targets, force)
        held.writes.append((dict(items), _stale_files(targets, replaces) if force else [],
                            announce))
        return
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
        if announce is not None:
            _announce(announce)
        for (path, _), tmp in zip(items, temps, strict=True):
            current = path
            os.replace(tmp, path)
            replaced.append(path)
    except BaseException as e:
        if not replaced:        # withdraw the commit first: a reader then keeps the old set
            journal.unlink(missing_ok=True)
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
