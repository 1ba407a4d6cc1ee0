"""Drags file of ``dgpc edit --replay``: a recorded sequence of handle events
(``{"events": [{"handle": [u, v], "target": [x, y, z], "time": s, "end": bool}]}``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .coordinates import bad_rows, coordinate_problem
from .jsonable import load_schema, read_json, validate

#: The latest event time a drags file may give, in seconds (a replay runs at most as long as
#: its events' span, so at most this long before its net settles).
MAX_EVENT_TIME = 3600.0


@dataclass(frozen=True)
class DragEvent:
    """One event: ``drag`` moves the handle at grid index ``(u, v)`` to ``target`` (the net's
    unit; a vertex that is no handle becomes one), ``pin`` holds the vertex where it is,
    ``release`` lets it go. ``time`` is seconds since the first event; ``end`` ends a drag
    (the net then settles, as when the mouse button is released)."""

    action: str
    index: tuple[int, int]
    target: tuple[float, float, float] | None
    time: float
    end: bool


def read_drags(path: str | Path, shape: tuple[int, int]) -> list[DragEvent]:
    """The events of a drags file, in time order. DgpcError (one line naming the file and the
    entry, e.g. ``events[3].target``): invalid JSON, schema violation, an index outside the
    m×n grid, a drag without a target, a non-finite number, a time beyond
    :data:`MAX_EVENT_TIME`, times that go back."""
    path = Path(path)
    m, n = (int(s) for s in shape)
    doc = read_json(path)
    validate(doc, load_schema("drags"), path)
    events: list[DragEvent] = []
    for k, entry in enumerate(doc["events"]):
        u, v = (int(i) for i in entry["handle"])
        if u >= m or v >= n:
            raise DgpcError(f"events[{k}].handle: ({u}, {v}) is outside the {m} x {n} grid",
                            source=path)
        action = entry.get("action", "drag")
        target = entry.get("target")
        if action == "drag" and target is None:
            raise DgpcError(f"events[{k}].target: a drag needs a target", source=path)
        if target is not None and bad_rows(np.asarray(target, dtype=float)[None]).size:
            raise DgpcError(f"events[{k}].target: {coordinate_problem(np.asarray(target))}",
                            source=path)
        time = float(entry["time"])
        if not (math.isfinite(time) and 0 <= time <= MAX_EVENT_TIME):
            raise DgpcError(f"events[{k}].time: {time:g} s is not a time from 0 to "
                            f"{MAX_EVENT_TIME:g} s", source=path)
        if events and time < events[-1].time:
            raise DgpcError(f"events[{k}].time: {time:g} s is before the event above it",
                            source=path)
        events.append(DragEvent(action, (u, v),
                                None if target is None else tuple(float(t) for t in target),
                                time, bool(entry.get("end", False))))
    return events
