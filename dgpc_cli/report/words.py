"""Counts in the figures' titles and captions: ``1 piece``, ``2 pieces``."""

from __future__ import annotations

__all__ = ["counted"]


def counted(count: int, noun: str, plural: str | None = None) -> str:
    """``count`` and ``noun`` in the singular for 1, else in ``plural`` (default noun + s)."""
    return f"{count} {noun if count == 1 else (plural or noun + 's')}"
