"""Guided projection (Tang et al. 2014) over the constraint terms of SPEC §4."""

from dgpc_cli.core.solver.guided_projection import SolverResult, Term, guided_projection
from dgpc_cli.core.solver.schedule import Schedule, parse_weight

__all__ = ["SolverResult", "Term", "guided_projection", "Schedule", "parse_weight"]
