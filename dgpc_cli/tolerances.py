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
    #: Period-2 corrugation across the geodesics (× mean edge, ``metrics.residuals.pleat``)
    #: above which a net is pleated (the pleats of the isometry study are 0.03 to 0.29; a smooth
    #: net is a fifth difference: 1e-16 on a sphere net, 0.015 on a coarse 12×8 net of wave.obj).
    pleat: float = 0.02
    #: Largest strain against the mold (isometric mode, extract-mold): 0.3 mm per metre.
    max_strain: float = 3e-4
    #: Largest gpc angle defect of an isometric deformation, radians.
    gpc_tol: float = 1e-4
    #: Largest coordinate (absolute, in the model's unit) of any point read: a mesh, net, OBJ,
    #: profile or handle beyond it is refused; squares of differences must not overflow, and a
    #: billion units (1000 km in mm, a million km in m) is beyond any building.
    max_coordinate: float = 1e9
    #: Longest length any length option takes, in mm once its unit is applied (1000 km): one
    #: limit for every command (``dgpc_cli.io.length``).
    max_length_mm: float = 1e9


tol = Tolerances()
