"""Reading a file whole, within bounds: a regular file of at most :data:`MAX_FILE_BYTES`.

A path a user gives (a mesh, an artifact's JSON, a profile) may name a device that never ends
(``/dev/zero``), a named pipe that blocks until someone writes, a symbolic link loop, or a file
larger than memory. Each is refused in one line naming the file (DgpcError, exit 1) before
anything is read: the file is opened without blocking, checked with ``fstat`` on the open
descriptor (no race with a rename), and read up to the limit.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from ..errors import DgpcError

#: The largest file dgpc reads (2 GiB): far above any mesh or artifact it makes, far below
#: what would exhaust a workstation's memory once parsed.
MAX_FILE_BYTES = 2 * 1024**3


def read_regular(path: str | Path, what: str = "a file", *,
                 limit: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of the regular file ``path``; DgpcError naming it when it is missing, a
    folder (``what`` says what was expected, e.g. ``"a mesh file"``), a device, pipe or
    socket, a symbolic link loop, unreadable, or larger than ``limit`` bytes."""
    path = Path(path)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise DgpcError("no such file", source=path) from None
    except IsADirectoryError:
        raise DgpcError(f"is a directory, expected {what}", source=path) from None
    except OSError as e:
        loop = " (a symbolic link loop?)" if e.errno == errno.ELOOP else ""
        raise DgpcError(f"cannot read: {e.strerror or e}{loop}", source=path) from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise DgpcError(f"is a directory, expected {what}", source=path)
        if not stat.S_ISREG(info.st_mode):
            raise DgpcError(f"is not a regular file (a device, a pipe or a socket), expected "
                            f"{what}", source=path)
        if info.st_size > limit:
            raise DgpcError(f"is {_size(info.st_size)}, larger than the {_size(limit)} dgpc "
                            f"reads as {what}", source=path)
        chunks, total = [], 0
        while True:
            chunk = os.read(fd, min(1 << 24, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
            if total > limit:
                raise DgpcError(f"grew past {_size(limit)} while being read, larger than dgpc "
                                f"reads as {what}", source=path)
        return b"".join(chunks)
    except OSError as e:
        raise DgpcError(f"cannot read: {e.strerror or e}", source=path) from None
    finally:
        os.close(fd)


def _size(n: int) -> str:
    return f"{n / 1024**3:.3g} GiB" if n >= 1024**3 else f"{n / 1024**2:.3g} MiB"
