"""``dgpc inspect``: the metrics of SPEC §7 for an artifact, recomputed from its geometry."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from dgpc_cli.core.layout import NetLayout
from dgpc_cli.core.problem import Problem, constraint_error, mean_edge_length
from dgpc_cli.core.solver import parse_weight
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.modes import GPC_ONLY, SOFT
from dgpc_cli.io.artifact import recorded_file, resolve_input
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.metrics.summary import net_metrics
from dgpc_cli.mold.isometry import panel_error_summary

log = logging.getLogger(__name__)


def recorded_axis(net: NetArtifact):
    """The axis ``(point, direction)`` a net of revolution records in ``data.surface``."""
    axis = net.data.get("surface", {}).get("axis")
    if not axis:
        return None
    return np.asarray(axis["point"], float), np.asarray(axis["direction"], float)


def recorded_reference(net: NetArtifact, json_path: Path):
    """The reference mesh recorded in ``data.reference``, if the file is there unchanged (only
    its largest piece when the net says ``largest_component``)."""
    from dgpc_cli.io.mesh import load_mesh

    record = net.data.get("reference")
    if not record:
        return None
    if isinstance(record, dict) and isinstance(record.get("path"), str) \
            and not resolve_input(record, json_path).is_file():
        log.warning("%s: recorded reference %s is missing; no Hausdorff distance", json_path,
                    record["path"])
        return None
    path = recorded_file(record, json_path, "data.reference")
    return load_mesh(path, pieces=net.reference_pieces)


def recorded_weights(net: NetArtifact) -> dict:
    """The weights of the optimization that made the net, or gpc only for an initial net."""
    weights = net.parameters.get("weights")
    if not weights:
        return dict(GPC_ONLY)
    return {name: parse_weight(f"{name}={value}")[1] for name, value in weights.items()}


def recorded_soft(net: NetArtifact) -> tuple[str, ...]:
    """The soft terms of the optimization that made the net (none for an initial net)."""
    if "soft" in net.parameters:
        return tuple(net.parameters["soft"])
    return SOFT.get(net.parameters.get("mode"), ())


def handle_miss(net: NetArtifact) -> dict | None:
    """``{"max", "relative"}``: the largest distance of a handle vertex from its target, also
    relative to the net's mean edge; None for a net without handles."""
    handles = net.data.get("handles")
    if not handles:
        return None
    ids = np.asarray(handles["ids"], dtype=np.int64)
    miss = np.linalg.norm(net.f.reshape(-1, 3)[ids] - np.asarray(handles["targets"]), axis=1)
    return {"max": float(miss.max()), "relative": float(miss.max() / mean_edge_length(net.f))}


def constraint_residuals(net: NetArtifact, reference=None, against: NetArtifact | None = None,
                         surface=None):
    """Residual norm per term and the paper's R of the net under its recorded weights.

    Data-bound terms count where their data is at hand: handles from ``data.handles``,
    approximation from the reference (continued as far as the net's ``init --extend``),
    isometry from ``against``. ``surface`` is the reference's ReferenceSurface (continued as
    far as the net's extension) when the caller has it already.
    """
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.geodesics.extension import fit_surface

    f = net.f
    m, n = net.shape
    weights = recorded_weights(net)
    handles = net.data.get("handles")
    rim = net.data.get("boundary")
    problem = Problem(
        NetLayout(m, n), mean_edge_length(f), weights,
        f0=against.f if against is not None else None,
        handle_ids=np.asarray(handles["ids"], dtype=np.int64) if handles else None,
        handle_targets=np.asarray(handles["targets"], dtype=float) if handles else None,
        reference=(surface if surface is not None
                   else ReferenceSurface.from_mesh(fit_surface(reference, net.extend))
                   if reference is not None else None),
        boundary_ids=np.asarray(rim["ids"], dtype=np.int64) if rim else None,
    )
    problem.soft = recorded_soft(net)
    norms = problem.residual_norms(f)
    return norms, constraint_error(norms, {k: weights[k] for k in norms}, problem.soft)


def summarize(net: NetArtifact, *, axis=None, mesh=None,
              against: NetArtifact | None = None, surface=None,
              coverage_tol: float | None = None) -> dict:
    """All metrics of a net (SPEC §7) as a JSON-able dict; ``mesh`` a ReferenceMesh or None,
    ``surface`` the ReferenceSurface the net was fitted to (``fit_surface`` of ``mesh``, in the
    net's units) when one is built: its tree serves the residuals and, for a net not extended
    past ``mesh``, the coverage; ``coverage_tol`` the coverage's tolerance in the net's unit
    (None: its default, 0.2 % of the reference's diagonal)."""
    axis = axis if axis is not None else recorded_axis(net)
    metrics = net_metrics(net.f, axis=axis, against=against.f if against is not None else None,
                          reference=(mesh.vertices, mesh.faces) if mesh is not None else None,
                          surface=surface if mesh is not None and net.extend <= 0 else None,
                          coverage_tol=coverage_tol)
    norms, R = constraint_residuals(net, mesh, against, surface)
    metrics["R"] = R
    metrics["residuals"] = norms
    # the fabrication error of a net isometric to a surface of revolution: its quads against
    # the mold extract-mold builds from it, and against the input of an isometric deformation
    metrics["mold_panel_error"] = panel_error_summary(net.f)
    if against is not None:
        metrics["panel_error_against"] = panel_error_summary(net.f, against.f)
    miss = handle_miss(net)
    if miss is not None:
        metrics["handle_miss"] = miss
    return metrics


def net_fit_surface(net: NetArtifact, json_path: Path, mesh):
    """What the net is fitted to (None without ``mesh``, its reference): the reference
    continued past its boundary as far as the net may run (``init --extend``); for a patch's
    net recording the whole mesh as its ``data.surroundings`` (``init --patches``), the whole
    mesh around the patch instead (``geodesics.extension.surrounded``)."""
    from dgpc_cli.geodesics.extension import FIT_REACH, fit_surface, surrounded
    from dgpc_cli.io.mesh import load_mesh

    if mesh is None:
        return None
    record = net.data.get("surroundings")
    if not net.extend or not record:
        return fit_surface(mesh, net.extend)
    whole = load_mesh(recorded_file(record, json_path, "data.surroundings"),
                      pieces=net.reference_pieces)
    return surrounded(mesh, whole, FIT_REACH * net.extend)


#: The largest coverage tolerance a plain number may give, as a share of the reference's
#: bounding-box diagonal (the default is 0.2 % of it).
COVERAGE_TOL_SHARE = 0.1


def checked_coverage_tol(coverage_tol, units: str, mesh) -> float | None:
    """``--coverage-tol`` (a :class:`~dgpc_cli.io.length.Length` or None: the default) in the
    net's unit ``units``, held to the rule of every length
    (:meth:`~dgpc_cli.io.length.Length.check`): with a reference ``mesh``, a plain number is
    plausible up to :data:`COVERAGE_TOL_SHARE` of its bounding-box diagonal."""
    from dgpc_cli.io.length import Span
    from dgpc_cli.io.units import mm_per_unit

    if coverage_tol is None:
        return None
    span = None
    if mesh is not None:
        diagonal = float(np.linalg.norm(np.ptp(np.asarray(mesh.vertices, float), axis=0)))
        span = Span(0.0, COVERAGE_TOL_SHARE * diagonal * mm_per_unit(units),
                    "coverage tolerance", low_open=True,
                    high_text=f"{100 * COVERAGE_TOL_SHARE:g} % of the reference's diagonal "
                              f"({COVERAGE_TOL_SHARE * diagonal:.4g} {units})")
    return coverage_tol.check("--coverage-tol", units, span, "the net's") / mm_per_unit(units)


def inspect_net(net: NetArtifact, json_path: Path, *, axis=None,
                against: NetArtifact | None = None, coverage_tol=None) -> dict:
    """Metrics of a net artifact read from ``json_path``, with its recorded reference;
    ``coverage_tol`` a :class:`~dgpc_cli.io.length.Length` or None (the coverage's default
    tolerance; :func:`checked_coverage_tol`)."""
    if against is not None and against.shape != net.shape:
        raise DgpcError(f"--against: grid {against.shape[0]}×{against.shape[1]} differs from "
                        f"{net.shape[0]}×{net.shape[1]}", source="--against")
    from dgpc_cli.core.reference import ReferenceSurface

    mesh = recorded_reference(net, json_path)
    tol = checked_coverage_tol(coverage_tol, net.units, mesh)
    surface = (ReferenceSurface.from_mesh(net_fit_surface(net, json_path, mesh))
               if mesh is not None and net.data.get("surroundings") else None)
    return summarize(net, axis=axis, mesh=mesh, against=against, surface=surface,
                     coverage_tol=tol)
