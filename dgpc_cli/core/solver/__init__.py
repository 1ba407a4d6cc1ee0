"""Guided projection (Tang et al. 2014) over the constraint terms of SPEC §4."""

from dgpc_cli.core.solver.guided_projection import (
    PredictorStep,
    SolverResult,
    Term,
    guided_projection,
    predictor_step,
)
from dgpc_cli.core.solver.schedule import Schedule, parse_weight

__all__ = ["PredictorStep", "SolverResult", "Term", "guided_projection", "predictor_step",
           "Schedule", "parse_weight"]
