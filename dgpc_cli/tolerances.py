"""One place for the numerical tolerances and defaults (cf. trimesh's ``constants.tol``)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    #: Solver stop on R (net scaled to mean edge length 1), SPEC §7.
    solver_R: float = 1e-9
    #: Iteration limit of an optimization run, per handle step (`optimize --max-iter` default).
    max_iter: int = 200
    #: Shortest edge, relative to the mean, below which a net counts as folded.
    min_edge_ratio: float = 0.1
    #: Edge length below which an edge counts as degenerate (relative to the mean).
    degenerate_edge: float = 1e-9


tol = Tolerances()
