"""The ``optimize`` run: check the net's size, read it with its reference and handles, run
guided projection and write the optimized net, not converged (exit 3) where it falls short."""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.errors import NotConverged, OptionSlip
from dgpc_cli.io.artifact import artifact_paths, load_envelope
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.handles import read_handles
from dgpc_cli.io.net import net_files, net_shape
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.layout.net_size import OPTIMIZE_BYTES_PER_VERTEX, check_net_size
from dgpc_cli.stages.optimize_artifact import (
    OptimizeSettings,
    optimize_prepared,
    optimized_artifact,
    prepare_optimize,
)

log = logging.getLogger(__name__)


def run_optimize(stem: Path, output: Path, settings: OptimizeSettings, *,
                 reference: Path | None, no_reference: bool, weights: tuple[str, ...],
                 handles: Path | None, force: bool, fmt, solver_progress: Callable,
                 written: Callable[[Path], None]) -> None:
    """Optimize the net ``stem`` with ``settings`` and write it to ``output``.

    ``reference``/``no_reference`` and ``weights`` (the ``--weight`` texts) as in
    :func:`~dgpc_cli.stages.optimize_artifact.prepare_optimize`; ``handles`` the handles JSON
    or None. ``solver_progress(label, target)`` is a context manager, the solver's callback.
    ``written(out_json)`` is called once the net is written. Raises
    :class:`~dgpc_cli.errors.OptionSlip` (before solving) where the isometric mode has no
    handles, and :class:`~dgpc_cli.errors.NotConverged` (after writing) where the run falls
    short."""
    mode = settings.mode
    json_path, _ = artifact_paths(stem)
    m, n = net_shape(load_envelope(json_path, "net")["data"], json_path)
    check_net_size(m, n, str(json_path), "optimize a coarser net (init --rows/--cols)",
                   per_vertex=OPTIMIZE_BYTES_PER_VERTEX[mode],
                   what=f"optimizing ({mode}) a net of")
    prepared = prepare_optimize(stem, settings, reference=reference, no_reference=no_reference,
                                weights=weights)
    net = prepared.net
    handle_ids = handle_targets = None
    if handles is not None:
        handle_ids, handle_targets = read_handles(handles, net.shape, net.f_mm,
                                                  scale=prepared.mm)
    if mode == "isometric" and handle_ids is None:
        raise OptionSlip("--mode isometric needs --handles")

    with solver_progress(f"optimize ({mode})", settings.tol) as progress:
        outcome = optimize_prepared(prepared, handle_ids, handle_targets, progress=progress)
    result = optimized_artifact(prepared, outcome, output, handles, handle_ids, handle_targets)
    out_json, _ = artifact_paths(output)
    write_files(with_3dm(net_files(output, result), output, fmt), force=force)
    written(out_json)
    log.info("%s: %s, %d iterations, R = %.3g", out_json, outcome.status, outcome.iterations,
             result.metrics["R"])
    if not outcome.converged:
        raise NotConverged(f"{outcome.status.replace('_', ' ')}: {outcome.message}; written "
                           "anyway", source=out_json)
