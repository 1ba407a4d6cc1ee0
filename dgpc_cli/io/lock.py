"""One writer per output stem (SPEC §3): a lock file ``.STEM.lock`` beside the output, held
with ``flock`` from the moment ``-o`` is parsed until the command ends.

A second process that asks for the same stem is refused at once (DgpcError, exit 1, one
line), and so is a writer that cannot take the lock at all (the lock path is a folder, a lock
file it may not open): a lock is never skipped. The lock file is removed when its holder
ends; one left behind by a killed process holds no lock (the kernel releases it) and the
next holder removes it.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import DgpcError

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

#: Locks this process holds: lock file (absolute) -> file descriptor. A command that reads
#: and writes one stem does not lock itself out.
_HELD: dict[str, int] = {}
_GUARD = threading.Lock()


def stem_name(output: str | Path) -> str:
    """The stem of an output path: its name without ``.json``/``.obj``."""
    name = Path(output).name
    for suffix in (".json", ".obj"):
        if name.lower().endswith(suffix) and len(name) > len(suffix):
            return name[: -len(suffix)]
    return name


def lock_path(output: str | Path) -> Path:
    """``.STEM.lock`` beside the output ``STEM``."""
    output = Path(output)
    return output.parent / f".{stem_name(output)}.lock"


def _try_lock(fd: int) -> bool:
    if fcntl is None:  # pragma: no cover - Windows
        import msvcrt
        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _acquire(path: Path) -> int | None:
    """The descriptor of ``path`` locked by this process, None if another process holds it.
    Retries when the file was removed (and maybe re-created) between open and lock."""
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        if not _try_lock(fd):
            os.close(fd)
            return None
        try:
            same = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd
        os.close(fd)


def _release(path: Path, fd: int) -> None:
    try:
        path.unlink(missing_ok=True)  # still locked: nobody can take the unlinked file
    except OSError:
        pass
    os.close(fd)


def _unusable(path: Path, err: OSError) -> DgpcError:
    """The one-line refusal of a lock that cannot be taken."""
    reason = err.strerror or str(err)
    if not path.exists() and not path.is_symlink():
        return DgpcError(f"cannot write in this folder ({reason}), so the lock of an output "
                         f"({path.name}) cannot be taken", source=path.parent)
    return DgpcError(f"cannot take this lock of the output ({reason}); if no dgpc process is "
                     "writing that output, remove it", source=path)


@contextmanager
def output_lock(output: str | Path, *, wait: bool = False) -> Iterator[bool]:
    """Hold the lock of the output stem ``output`` for the ``with`` block.

    Yields True while holding it (or when this process already holds it). Another process
    holding it raises a DgpcError naming the output, unless ``wait``: then the block runs
    without the lock and gets False. A folder that does not exist has no lock to take (the
    write itself reports the problem); the block then gets True. A lock that cannot be taken
    (the lock path is a folder, a lock file this user may not open, a folder it may not
    write) is a DgpcError naming the lock file; a reader (``wait``) goes on without it.
    """
    path = lock_path(output)
    key = os.path.abspath(path)
    fd: int | None = -1
    with _GUARD:
        reentrant = key in _HELD
        if not reentrant:
            try:
                fd = _acquire(path) if path.parent.is_dir() else -1
            except OSError as e:
                if not wait:
                    raise _unusable(path, e) from None
                fd = -1
            if fd is not None and fd >= 0:
                _HELD[key] = fd
    if reentrant:
        yield True
        return
    if fd is None:
        if not wait:
            raise DgpcError(f"another dgpc process is writing this output (it holds "
                            f"{path.name}); wait for it to end or choose another -o",
                            source=output)
        yield False
        return
    try:
        yield True
    finally:
        if fd >= 0:
            with _GUARD:
                _HELD.pop(key, None)
            _release(path, fd)
