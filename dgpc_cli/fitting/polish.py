"""``optimize --mode fit`` on a net that is already nearly gpc only polishes it (issue: "``fit``
keeps the area the initial net covered").

Every net ``init`` makes on a mesh is nearly a discrete gpc net (angle defect (6) within
:data:`~dgpc_cli.metrics.degenerate.GPC_LIMIT`; traced geodesics, or a projected grid shrunk
to where it is sound): a few damped Gauss–Newton steps on gpc and approximation (paper §5.1)
make it exact and leave it where it is. The fit preset's fairness (0.01→0), boundary and rim
terms are there for rough starts; on such a net they only pull: second differences shorten a
curved net while approximation lets every vertex slide along the reference (a dome's net lost
a tenth of its coverage that way), a rim held on a reference boundary that is not a geodesic
parallel fights the angle condition, and so does a rim held from coming in (the rim term, which
stops fairness drawing a rough start in). So for such a net, unless ``--weight`` sets them,
fitting drops all three (the artifact records the weights used). A net corrugated across its
geodesics (``metrics.residuals.pleat`` above half the pleat tolerance: a coarse net traced over
a wavy surface) is not polished: the fairness term is what smooths it out.
"""

from __future__ import annotations

import logging

import numpy as np

from dgpc_cli.core.solver import Schedule, parse_weight
from dgpc_cli.metrics.degenerate import GPC_LIMIT
from dgpc_cli.metrics.residuals import gpc_angle_defect_max, pleat
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)

#: Terms a polish leaves out.
PULLING = ("fairness", "boundary", "rim")


def polish_weights(f, schedules: dict, overrides=()) -> dict:
    """The fit weights ``schedules`` for the net ``f (m, n, 3)`` unless ``overrides``
    (``--weight NAME=...`` texts) set one of :data:`PULLING`: fairness, boundary and rim at 0
    when the net is nearly gpc; the rim term at 0 when it is far from gpc (a rough start's rim
    has to move: a twisted net on a bowling pin folds when its rim is held); all three on for a
    nearly gpc net corrugated across its geodesics (fairness smooths it out, and the rim term
    keeps fairness from drawing it in)."""
    named = {parse_weight(text)[0] for text in overrides}
    if named & set(PULLING):
        return schedules
    defect = gpc_angle_defect_max(f)
    if defect is None or defect > GPC_LIMIT:
        return {**schedules, **({"rim": Schedule.constant(0.0)} if "rim" in schedules else {})}
    corrugation = pleat(f)
    if corrugation.size and float(np.abs(corrugation).max()) > 0.5 * TOL.pleat:
        log.info("the net is corrugated across its geodesics (%.3g of its mean edge): fitted "
                 "with fairness, its rim held from coming in", float(np.abs(corrugation).max()))
        return schedules
    log.info("the net is nearly gpc already (angle defect %.3g rad): a polish, without %s",
             defect, ", ".join(PULLING))
    return {**schedules, **{name: Schedule.constant(0.0) for name in PULLING
                            if name in schedules}}
