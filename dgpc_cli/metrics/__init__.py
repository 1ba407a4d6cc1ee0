"""Metrics computed from the vertex positions of a net alone (SPEC §7).

* :mod:`~dgpc_cli.metrics.frames` — unit edge vectors, corner angles, T^u, T^v, N (§2.2.1)
* :mod:`~dgpc_cli.metrics.residuals` — gpc angle defect (Prop. 2.7), orthogonality (Lemma 2.5),
  arc-length, strip-width (7), ratio (5) and Jacobi (2) residuals, edge lengths
* :mod:`~dgpc_cli.metrics.curvature` — discrete Gaussian curvature from the Jacobi equation (1)
* :mod:`~dgpc_cli.metrics.strain` — strain tensor D against a reference net (§6.1)
* :mod:`~dgpc_cli.metrics.clairaut` — Clairaut's relation (9) on surfaces of revolution
* :mod:`~dgpc_cli.metrics.hausdorff` — two-sided Hausdorff distance to a reference mesh
* :mod:`~dgpc_cli.metrics.summary` — everything as one JSON-able dict
"""

from dgpc_cli.metrics.clairaut import as_axis, clairaut, clairaut_values, parse_axis
from dgpc_cli.metrics.curvature import gaussian_curvature, strip_widths
from dgpc_cli.metrics.frames import (
    as_grid,
    corner_angles,
    edge_lengths,
    net_frames,
    tangent_frames,
    unit_edge_vectors,
)
from dgpc_cli.metrics.hausdorff import hausdorff
from dgpc_cli.metrics.residuals import (
    arclength_spread,
    edge_length_stats,
    finite_max,
    gpc_angle_defect,
    gpc_angle_defect_max,
    jacobi_residual,
    orthogonality,
    ratio_spread,
    strip_width_spread,
)
from dgpc_cli.metrics.strain import principal_strains, strain, strain_tensor
from dgpc_cli.metrics.summary import jsonable, net_metrics

__all__ = [
    "arclength_spread",
    "as_axis",
    "as_grid",
    "clairaut",
    "clairaut_values",
    "corner_angles",
    "edge_length_stats",
    "edge_lengths",
    "finite_max",
    "gaussian_curvature",
    "gpc_angle_defect",
    "gpc_angle_defect_max",
    "hausdorff",
    "jacobi_residual",
    "jsonable",
    "net_frames",
    "net_metrics",
    "orthogonality",
    "parse_axis",
    "principal_strains",
    "ratio_spread",
    "strain",
    "strain_tensor",
    "strip_width_spread",
    "strip_widths",
    "tangent_frames",
    "unit_edge_vectors",
]
