"""The net artifact of ``dgpc optimize`` (SPEC §3, §4): the input net and its reference made
ready once (:func:`prepare_optimize`), then solved for a set of handles and written as an
artifact (:func:`optimized_artifact`). ``dgpc optimize`` runs it once; ``dgpc edit`` once per
settled drag, so that what it saves is what ``optimize`` writes for the same handles."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.core.solver import Schedule, parse_weight
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.modes import RELAX, SOFT, describe_weights
from dgpc_cli.fitting.optimize import OptimizeOutcome, boundary_vertices, judge, optimize_net
from dgpc_cli.fitting.polish import polish_weights
from dgpc_cli.io.artifact import artifact_paths, file_input, recorded_file, resolve_input
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import NetArtifact, read_net
from dgpc_cli.io.units import from_mm, mm_per_unit
from dgpc_cli.stages.inspect import checked_coverage_tol, net_fit_surface, summarize
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)


def reference_mesh(net: NetArtifact, json_path: Path, reference: Path | None, mode: str,
                   keep: bool = True):
    """The reference mesh: --reference, else the one the net records unless ``keep`` is off
    (--no-reference; fit needs one), checked against its recorded sha256; only its largest
    piece when the net was made with ``init --largest-component``."""
    if reference is None and keep and net.data.get("reference"):
        record = net.data["reference"]
        if isinstance(record, dict) and isinstance(record.get("path"), str) \
                and not resolve_input(record, json_path).is_file():
            raise DgpcError(f"data.reference: the reference it records, {record['path']}, is "
                            "missing (give --reference MESH, or --no-reference to drop it)",
                            source=json_path)
        reference = recorded_file(record, json_path, "data.reference")
        log.info("using the reference recorded in %s: %s", json_path, reference)
    if reference is None:
        if mode == "fit":
            raise DgpcError("--mode fit needs a reference mesh (--reference MESH)",
                            source="--no-reference" if not keep else "--reference")
        return None
    return load_mesh(reference, pieces=net.reference_pieces)


@dataclass
class OptimizeSettings:
    """The options of ``dgpc optimize`` that a run's artifact records."""

    mode: str
    schedules: dict
    steps: int = 1
    max_iter: int | None = None
    tol: float = TOL.solver_R
    max_strain: float = TOL.max_strain
    gpc_tol: float = TOL.gpc_tol
    backend: str = "auto"
    #: The coverage's tolerance, a :class:`~dgpc_cli.io.length.Length` (None: its default).
    coverage_tol: object | None = None


@dataclass
class PreparedNet:
    """The input net of an optimization, its reference mesh and what is derived from them (in
    mm): the scaled reference surface, the rim vertices the ``boundary`` term holds and how far
    the ``rim`` term lets each vertex come in (:func:`_rim_slack`)."""

    net: NetArtifact
    json_path: Path
    settings: OptimizeSettings
    mesh: object | None
    surface: ReferenceSurface | None
    rim: np.ndarray | None
    rim_slack: np.ndarray | None = None
    #: Whether the fit's ``rim`` term is on by the preset (not by ``--weight``): a fit that
    #: pleats with it is run again without it (:func:`optimize_prepared`).
    rim_by_default: bool = False

    @property
    def mm(self) -> float:
        return mm_per_unit(self.net.units)


def prepare_optimize(stem: Path, settings: OptimizeSettings, *, reference: Path | None = None,
                     no_reference: bool = False, weights: tuple[str, ...] = ()) -> PreparedNet:
    """Read the net ``stem`` and its reference; settle the weights the reference leaves on (the
    terms that need one are off without it; a fit polishes them, ``weights`` being the
    ``--weight`` overrides)."""
    json_path, _ = artifact_paths(stem)
    net = read_net(stem)
    mode, schedules = settings.mode, dict(settings.schedules)
    mesh = reference_mesh(net, json_path, reference, mode, keep=not no_reference)
    checked_coverage_tol(settings.coverage_tol, net.units, mesh)     # a slip: before solving
    if mesh is None:  # the terms that need a reference are off, and the record says so
        schedules.update({name: Schedule.constant(0.0) for name in ("approximation", "boundary")
                          if name in schedules})
    if mode == "fit":
        schedules = polish_weights(net.f, schedules, weights)
    settings.schedules = schedules
    mm = mm_per_unit(net.units)      # the stages compute in mm (dgpc_cli.io.units)
    fit = net_fit_surface(net, json_path, mesh)
    surface = ReferenceSurface(fit.vertices * mm, fit.faces) if fit is not None else None
    # a net that runs past its reference (init --extend) has no rim on its boundary
    rim = (boundary_vertices(net.f_mm, surface)
           if surface is not None and not net.extend
           and schedules.get("boundary", Schedule.constant(0)).end > 0 else None)
    rim_by_default = (mode == "fit" and schedules.get("rim", Schedule.constant(0)).end > 0
                      and "rim" not in {parse_weight(text)[0] for text in weights})
    return PreparedNet(net, json_path, settings, mesh, surface, rim,
                       _rim_slack(net, mesh, surface, mm) if surface is not None else None,
                       rim_by_default)


def _rim_slack(net: NetArtifact, mesh, surface: ReferenceSurface, mm: float) -> np.ndarray:
    """How far (mm) the ``rim`` term lets each vertex of the net come in: its distance from the
    reference mesh itself (0 on it; past its edge for a net traced beyond it, ``init
    --extend``, where ``surface`` is the mesh's continuation and the mesh alone is measured)."""
    own = surface if not net.extend else ReferenceSurface(mesh.vertices * mm, mesh.faces)
    q = net.f_mm.reshape(-1, 3)
    return np.linalg.norm(q - own.closest(q)[0], axis=1)


def optimize_prepared(prepared: PreparedNet, handle_ids: np.ndarray | None,
                      handle_targets: np.ndarray | None, progress=None) -> OptimizeOutcome:
    """Guided projection of the prepared net towards the handles (targets in mm), judged as
    ``optimize`` judges it (status and message set)."""
    outcome = _guided_projection(prepared, prepared.settings.schedules, handle_ids,
                                 handle_targets, progress)
    if outcome.status == "pleated" and prepared.rim_by_default:
        # the rim held from coming in can leave fairness too little room to smooth a
        # corrugated start: without it the fit may come in a little, but unpleated
        schedules = {**prepared.settings.schedules, "rim": Schedule.constant(0.0)}
        again = _guided_projection(prepared, schedules, handle_ids, handle_targets, progress)
        if again.status != "pleated":
            log.info("the fit pleated with its rim held; fitted again with the rim free")
            prepared.settings.schedules = schedules
            return again
    return outcome


def _guided_projection(prepared: PreparedNet, schedules: dict, handle_ids, handle_targets,
                       progress) -> OptimizeOutcome:
    s, net = prepared.settings, prepared.net
    outcome = optimize_net(
        net.f_mm, schedules, reference=prepared.surface, boundary_ids=prepared.rim,
        rim_slack=prepared.rim_slack,
        handle_ids=handle_ids, handle_targets=handle_targets, soft=SOFT[s.mode], steps=s.steps,
        max_iter=s.max_iter, tol=s.tol, backend=s.backend, progress=progress,
        relax=RELAX.get(s.mode), gpc_tol=s.gpc_tol if s.mode == "isometric" else None,
        max_strain=s.max_strain if s.mode == "isometric" else None)
    outcome.status, outcome.message = judge(outcome, net.f_mm, mode=s.mode,
                                            max_strain=s.max_strain, gpc_tol=s.gpc_tol,
                                            handles=(handle_ids, handle_targets),
                                            units=net.units)
    return outcome


def optimized_artifact(prepared: PreparedNet, outcome: OptimizeOutcome, output: Path,
                       handles: Path | None, handle_ids: np.ndarray | None,
                       handle_targets: np.ndarray | None) -> NetArtifact:
    """The net artifact ``optimize`` writes to ``output`` for ``outcome`` (inputs relative to
    the output's folder, the handles file ``handles`` among them)."""
    s, net, mm, mesh = prepared.settings, prepared.net, prepared.mm, prepared.mesh
    out_json, _ = artifact_paths(output)
    folder = out_json.resolve().parent
    inputs = {"net": file_input(prepared.json_path, folder)}
    # the analytic surface (and its axis, for Clairaut) still carries the net only when the net
    # was fitted to it; the other modes move the net off it
    data = {k: v for k, v in net.data.items() if k == "surface" and s.mode == "fit"}
    if "patches" in net.data:      # init --patches: why the reference was split, and where
        data["patches"] = net.data["patches"]
    if mesh is not None:
        inputs["reference"] = data["reference"] = file_input(mesh.path, folder)
        if net.extend and net.data.get("surroundings"):
            inputs["surroundings"] = data["surroundings"] = file_input(
                resolve_input(net.data["surroundings"], prepared.json_path), folder)
    if handle_ids is not None:
        inputs["handles"] = file_input(handles, folder)
        data["handles"] = {"ids": handle_ids.tolist(), "targets": (handle_targets / mm).tolist()}
    rim = prepared.rim
    if rim is not None and len(rim):
        data["boundary"] = {"ids": rim.tolist()}
    result = NetArtifact(
        f=from_mm(outcome.f, net.units), units=net.units,
        parameters={"mode": s.mode, "weights": describe_weights(s.schedules),
                    "soft": [*SOFT[s.mode], *outcome.released], "steps": s.steps,
                    "max_iter": outcome.max_iter, "tol": s.tol, "max_strain": s.max_strain,
                    "gpc_tol": s.gpc_tol, "solver": s.backend,
                    "coverage_tol": None if s.coverage_tol is None else s.coverage_tol.text(),
                    **net.reference_parameters()},
        inputs=inputs, data=data)
    result.status = outcome.record()
    surface = prepared.surface
    result.metrics = summarize(result, mesh=mesh,
                               against=net if s.mode == "isometric" else None,
                               surface=surface.scaled(1.0 / mm) if surface is not None else None,
                               coverage_tol=checked_coverage_tol(s.coverage_tol, net.units,
                                                                 mesh))
    return result
