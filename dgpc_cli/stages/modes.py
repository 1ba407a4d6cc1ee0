"""Optimization modes of ``dgpc optimize`` (SPEC §4): presets of weights after paper §5.2."""

from __future__ import annotations

from dgpc_cli.core.constraints import TERMS
from dgpc_cli.core.solver import Schedule, parse_weight

#: Weights per mode, in the notation of ``--weight`` (a value or a schedule ``A->B``).
#: ``net`` is always 1. Data-bound terms take part only when their data is given:
#: approximation needs ``--reference``, handles ``--handles``, isometry the input net;
#: boundary needs net rim vertices that start on the reference's boundary.
MODES: dict[str, dict[str, str]] = {
    "fit": {"gpc": "1", "approximation": "1", "boundary": "1", "fairness": "0.01->0"},
    "developable": {"gpc": "1", "arclength": "1", "equal_strip_width": "1", "developable": "1",
                    "approximation": "1", "boundary": "1"},
    "revolution": {"gpc": "1", "equal_strip_width": "1", "approximation": "1", "handles": "1"},
    "isometric": {"gpc": "1", "isometry": "1", "handles": "1", "fairness": "0.01->0"},
}

#: Terms each mode treats as soft (they pull, the tolerance does not apply to them): the
#: reference of a nearly developable fit is not exactly developable (paper Fig. 8: R = 0.29),
#: nor need a reference be isometric to a surface of revolution. The reference's boundary
#: only pulls: a geodesic net need not end on it everywhere.
SOFT = {"fit": ("fairness", "boundary"), "developable": ("fairness", "approximation", "boundary"),
        "revolution": ("fairness", "approximation"), "isometric": ("fairness",)}

#: What ``dgpc init`` nets are measured against: discrete geodesic parallel coordinates.
GPC_ONLY = {"net": Schedule.constant(1.0), "gpc": Schedule.constant(1.0)}


def mode_weights(mode: str, overrides: list[str] | tuple[str, ...] = ()) -> dict[str, Schedule]:
    """The weight schedules of ``mode`` with ``--weight NAME=VALUE|NAME=A->B`` overrides.

    Raises ValueError with a one-line reason for an unknown mode or weight name or a bad value.
    """
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}")
    weights = {"net": Schedule.constant(1.0)}
    weights.update({name: parse_weight(f"{name}={value}")[1]
                    for name, value in MODES[mode].items()})
    for text in overrides:
        name, schedule = parse_weight(text)
        if name not in TERMS:
            raise ValueError(f"unknown weight {name!r}; the terms are {', '.join(TERMS)}")
        weights[name] = schedule
    return weights


def describe_weights(weights: dict[str, Schedule]) -> dict[str, str]:
    """JSON-able form of the weights (``"1"``, ``"0.01->0"``), every term listed."""
    return {name: str(weights.get(name, Schedule.constant(0.0))) for name in TERMS}
