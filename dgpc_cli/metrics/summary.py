"""All metrics of a net in one JSON-able dict (SPEC §7), for artifacts and ``dgpc inspect``."""

from __future__ import annotations

import math

import numpy as np

from dgpc_cli.metrics.clairaut import as_axis, clairaut
from dgpc_cli.metrics.coverage import coverage
from dgpc_cli.metrics.crease import crease
from dgpc_cli.metrics.curvature import gaussian_curvature
from dgpc_cli.metrics.frames import as_grid
from dgpc_cli.metrics.freeform import parallel_departure
from dgpc_cli.metrics.hausdorff import hausdorff
from dgpc_cli.metrics.residuals import (
    arclength_spread,
    edge_length_stats,
    finite_max,
    gpc_angle_defect,
    jacobi_residual,
    orthogonality,
    pleat,
    ratio_spread,
    strip_width_spread,
    u_edge_spread,
)
from dgpc_cli.metrics.strain import strain

__all__ = ["jsonable", "net_metrics"]


def jsonable(value):
    """Recursively convert numpy scalars/arrays, tuples and non-finite floats (→ None) into
    plain JSON types (dict with str keys, list, int, float, bool, str, None)."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [jsonable(v) for v in (value.tolist() if isinstance(value, np.ndarray) else value)]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else None
    return value


def _stats(x: np.ndarray) -> dict:
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    if not x.size:
        return {"min": None, "max": None, "mean": None}
    return {"min": float(x.min()), "max": float(x.max()), "mean": float(x.mean())}


def net_metrics(f, *, axis=None, against=None, reference=None, surface=None,
                coverage_tol: float | None = None) -> dict:
    """Metrics of a net ``f (m, n, 3)`` from its vertex positions (SPEC §7).

    Always::

        shape [m, n]; gpc_angle_defect_max (rad, Prop. 2.7 (ii)); orthogonality_max
        (|⟨T^u, T^v⟩|, Lemma 2.5); arclength_spread_max (§5.1); strip_width_spread_max ((7));
        ratio_spread_max ((5)); u_spread_max (u-edges per row, §4.2.1); pleat_max
        (period-2 corrugation across the geodesics, × mean edge); crease_max (largest third
        difference across the geodesics along a row, × mean edge); jacobi_residual_max
        (|(2)| / mean v-edge);
        edges {min, mean, max, min_ratio, folded}; gaussian_curvature {min, max, mean} ((1));
        parallel_departure {max, relative, row} (rows against their best-fit circles: 0 on a
        surface of revolution)

    and, when given, ``clairaut`` (axis: ``(point, direction)`` or ``"px,py,pz,dx,dy,dz"``;
    equation (9), see :func:`~dgpc_cli.metrics.clairaut.clairaut`), ``strain`` {max, mean}
    against the reference net ``against (m, n, 3)`` (§6.1), ``hausdorff`` to ``reference`` =
    ``(vertices (k, 3), faces (l, 3))`` (see :func:`~dgpc_cli.metrics.hausdorff.hausdorff`) and
    ``coverage`` of it (area fraction, vertex distances; see
    :func:`~dgpc_cli.metrics.coverage.coverage`; ``surface``, the reference's
    :class:`~dgpc_cli.core.reference.ReferenceSurface` if one is built, lends it its tree;
    ``coverage_tol`` its tolerance, in the net's unit, None for the default).
    Values are plain floats/ints/lists; undefined values are None, never NaN.
    """
    f = as_grid(f)
    m, n, _ = f.shape
    out = {
        "shape": [m, n],
        "gpc_angle_defect_max": finite_max(gpc_angle_defect(f)),
        "orthogonality_max": finite_max(orthogonality(f)),
        "arclength_spread_max": finite_max(arclength_spread(f)),
        "strip_width_spread_max": finite_max(strip_width_spread(f)),
        "ratio_spread_max": finite_max(ratio_spread(f)),
        "u_spread_max": finite_max(u_edge_spread(f)),
        "pleat_max": finite_max(pleat(f)) or 0.0,
        "crease_max": finite_max(crease(f)) or 0.0,
        "jacobi_residual_max": finite_max(jacobi_residual(f), absolute=True),
        "edges": edge_length_stats(f),
        "gaussian_curvature": _stats(gaussian_curvature(f)),
        "parallel_departure": parallel_departure(f),
    }
    if axis is not None:
        out["clairaut"] = clairaut(f, as_axis(axis))
    if against is not None:
        out["strain"] = strain(f, against)[1]
    if reference is not None:
        try:
            vertices, faces = reference
        except (TypeError, ValueError):
            raise ValueError("reference must be a (vertices, faces) pair") from None
        out["hausdorff"] = hausdorff(f, vertices, faces)
        out["coverage"] = coverage(f, vertices, faces, surface=surface, tolerance=coverage_tol)
    return jsonable(out)
