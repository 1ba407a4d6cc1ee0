"""What the page sends is input: every value of a gesture (the push slider, a gizmo's
position, a click's ray) is checked on the server before it reaches the session, and a
gesture that fails a check, or whose handler fails, is dropped with one log line (stderr),
no traceback. The page's own client never sends such values; a stale tab, another client
or a hand-made websocket message may."""

from __future__ import annotations

import functools
import logging
import math
from collections.abc import Callable

import numpy as np

from dgpc_cli.io.coordinates import bad_rows, coordinate_problem

log = logging.getLogger(__name__)

#: A handle's target may lie at most this many diagonals of the net's bounding box from the
#: box's centre (farther, no net of fixed edge lengths can follow; a runaway value).
REACH = 10.0


class BadInput(ValueError):
    """A value from the page that is not of the expected type, not finite or out of range."""


def number(value, lo: float, hi: float, what: str) -> float:
    """``value`` as a finite float in ``[lo, hi]``; BadInput naming ``what`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating,
                                                         np.integer)):
        raise BadInput(f"{what}: {value!r} is not a number")
    x = float(value)
    if not math.isfinite(x) or not lo <= x <= hi:
        raise BadInput(f"{what}: {x!r} is not a finite number in [{lo:g}, {hi:g}]")
    return x


def vector(value, what: str) -> np.ndarray:
    """``value`` as a finite 3-vector (float64) within dgpc's coordinate bound; BadInput
    naming ``what`` otherwise."""
    try:
        v = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise BadInput(f"{what}: {value!r} is not three numbers") from None
    if v.shape != (3,):
        raise BadInput(f"{what}: {value!r} is not three numbers")
    if bad_rows(v[None]).size:
        raise BadInput(f"{what}: {coordinate_problem(v)}")
    return v


def direction(value, what: str) -> np.ndarray:
    """``value`` as a unit 3-vector (a finite, non-zero one); BadInput otherwise."""
    v = vector(value, what)
    length = float(np.linalg.norm(v))
    if not length > 0:
        raise BadInput(f"{what}: a zero direction")
    return v / length


def within_reach(point: np.ndarray, box: tuple[np.ndarray, np.ndarray], what: str) -> None:
    """BadInput naming ``what`` where ``point`` lies more than :data:`REACH` diagonals of the
    bounding ``box`` (lo, hi) from its centre."""
    lo, hi = box
    diagonal = float(np.linalg.norm(hi - lo)) or 1.0
    off = float(np.linalg.norm(point - 0.5 * (lo + hi)))
    if off > REACH * diagonal:
        raise BadInput(f"{what}: {off:.3g} from the net's centre, more than {REACH:g} "
                       f"diagonals of its bounding box ({diagonal:.3g})")


def guarded(what: str) -> Callable[[Callable], Callable]:
    """A handler of the page's gestures that never raises: a failure (a BadInput or any other
    error) is one warning line naming the gesture ``what``, and the gesture is dropped."""
    def wrap(fn: Callable) -> Callable:
        @functools.wraps(fn)
        def run(*args, **kwargs):
            try:
                return fn(*args, **kwargs)
            except Exception as err:  # noqa: BLE001 - a bad message must not stop the page
                log.warning("edit: a %s from the page dropped: %s", what, describe(err))
                log.debug("edit: %s", what, exc_info=True)
                return None
        return run
    return wrap


def describe(err: BaseException | None) -> str:
    """One line for an error: its message, or its type where it has none."""
    if err is None:
        return "no reason given"
    text = " ".join(str(err).split())
    if isinstance(err, BadInput):
        return text
    return f"{type(err).__name__}: {text}" if text else type(err).__name__
