"""A run that fell short travels down the chain: a stage refuses an input whose status says so
(SPEC §2: exit 3 writes the artifact anyway, its status recorded), unless told to go on.

What falls short, by the input's ``status``:

- a net whose ``state`` is not ``converged`` (``max_iter``, ``stagnated``,
  ``missed_tolerance``, ``degenerate``, ``pleated``, ...): ``optimize`` wrote it with exit 3
  (``init``'s nets record no state, a mold's is ``ok``);
- strips whose polish missed its tolerance (``polish_not_converged``) or whose rulings cross
  (``rulings_cross``): ``planarize-strips`` wrote them with exit 3;
- any artifact built from such an input with ``--accept-status``: its ``status.accepted``
  carries the state it was built on, so the next stage asks again and the cut sheets of a
  failed drag are never made without the user saying so at every step.

``planarize-strips``, ``extract-mold``, ``laths``, ``unfold`` and ``nest`` refuse such an input
(exit 1, one line naming the input and its status) before any work; with ``--accept-status``
they go on, say so on stderr and record ``status.accepted`` (``[{"input": "net", "state":
"stagnated"}]``: the input's name among the artifact's ``inputs`` and the state it fell short
with). ``optimize`` takes any net (it is the stage that makes a net converge), ``inspect``
and ``report`` show any artifact.
"""

from __future__ import annotations

import logging
from pathlib import Path

from dgpc_cli.errors import DgpcError

log = logging.getLogger(__name__)

#: The states of a run that reached what it was asked for.
GOOD_STATES = ("converged", "ok")
#: The option that lets a stage go on with an input that fell short.
ACCEPT = "--accept-status"


def shortfall(status: dict) -> tuple[str, str] | None:
    """``(state, words)`` of an artifact's ``status`` that says its run fell short
    (module), or None."""
    if not isinstance(status, dict):
        return None
    state = status.get("state")
    if state is not None and state not in GOOD_STATES:
        message = " ".join(str(status.get("message") or "").split())
        return str(state), f"{state}" + (f" ({message})" if message else "")
    for key in ("polish_not_converged", "rulings_cross"):
        if status.get(key):
            return key, f"{key} ({', '.join(map(str, status[key]))})"
    accepted = status.get("accepted")
    if accepted:
        first = accepted[0]
        return str(first["state"]), (f"{first['state']} (built from its input "
                                     f"{first['input']} with {ACCEPT})")
    return None


def check_inputs(inputs: list[tuple[str, str | Path, dict]], stage: str,
                 accept: bool) -> list[dict]:
    """Refuse (DgpcError naming the file, exit 1) the first of ``inputs`` — ``(name among
    the output's inputs, its JSON path, its status)`` — whose status falls short
    (:func:`shortfall`), unless ``accept``; then say each on stderr and return the records
    of the output's ``status.accepted`` (empty when every input is sound)."""
    carried = []
    for name, path, status in inputs:
        found = shortfall(status)
        if found is None:
            continue
        state, words = found
        if not accept:
            raise DgpcError(f"its status is {words}, not converged: {stage} builds only on a "
                            f"run that reached its tolerance; make it again (its status says "
                            f"what to try), or give {ACCEPT} to go on with it", source=path)
        log.warning("%s: status %s; going on with it (%s)", path, words, ACCEPT)
        carried.append({"input": name, "state": state})
    return carried


def with_accepted(status: dict, carried: list[dict]) -> dict:
    """``status`` with ``accepted`` set to ``carried`` where there is any."""
    return {**status, "accepted": carried} if carried else status


ACCEPT_HELP = ("Go on with an input whose status says its run fell short (a net not "
               "converged: max_iter, stagnated, missed_tolerance, ...; strips whose polish "
               "missed or whose rulings cross; anything built from one of these), which is "
               "refused otherwise; the output records it in status.accepted, so the next "
               "stage asks again.")
