"""Checks of a refused command (issue "nothing destroyed, nothing corrupt"): its exit code,
exactly one line on stderr, no traceback, and the files of a folder unchanged."""

from __future__ import annotations

from pathlib import Path


def tree(folder: Path) -> dict[str, bytes]:
    """Every file below ``folder`` (hidden ones too) by relative path, with its bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(Path(folder).rglob("*")) if p.is_file() and not p.is_symlink()}


def refused(stderr: str, exit_code: int, expected: int, *needles: str) -> str:
    """Assert the exit code, one stderr line starting ``Error:`` holding every needle and
    no traceback; the line."""
    assert exit_code == expected, (exit_code, stderr)
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), stderr
    assert "Traceback" not in stderr and "internal error" not in stderr, stderr
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]
