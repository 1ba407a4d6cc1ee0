"""Constraint terms of SPEC §4. Each is ``term(x, layout, ...) -> (phi, J)``."""

from dgpc_cli.core.constraints.approximation import approximation
from dgpc_cli.core.constraints.boundary import boundary
from dgpc_cli.core.constraints.crease_guard import crease_guard
from dgpc_cli.core.constraints.fairness import (
    closeness,
    displacement_fairness,
    displacement_smoothness,
    fairness,
)
from dgpc_cli.core.constraints.gpc import gpc
from dgpc_cli.core.constraints.handles import handles
from dgpc_cli.core.constraints.isometry import isometry
from dgpc_cli.core.constraints.net import net
from dgpc_cli.core.constraints.rim import rim
from dgpc_cli.core.constraints.strip_widths import (
    arclength,
    developable,
    equal_strip_width,
    equal_u_edges,
    ratio_revolution,
)

TERMS = {
    "net": net,
    "gpc": gpc,
    "arclength": arclength,
    "equal_strip_width": equal_strip_width,
    "equal_u_edges": equal_u_edges,
    "ratio_revolution": ratio_revolution,
    "developable": developable,
    "isometry": isometry,
    "approximation": approximation,
    "boundary": boundary,
    "rim": rim,
    "handles": handles,
    "fairness": fairness,
    "displacement_fairness": displacement_fairness,
    "displacement_smoothness": displacement_smoothness,
    "closeness": closeness,
    "crease_guard": crease_guard,
}

__all__ = ["TERMS", *TERMS]
