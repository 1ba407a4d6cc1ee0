"""The ``extract-mold`` run: read the nets, check them and their unit, extract the mold, build
and write the mold artifact (profile, DXF, pieces, nets, panels, parameters, metrics, status)."""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from dgpc_cli.fitting.soundness import require_sound_net
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.mold import mold_files, mold_paths
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import mm_per_unit, same_units
from dgpc_cli.mold.dxf import profile_dxf
from dgpc_cli.mold.extract import (
    DEFAULT_FLAT_TOL,
    DEFAULT_MAX_STRAIN,
    DEFAULT_PANEL_SIZE,
    DEFAULT_TOL_FACTOR,
    check_max_length,
    extract_mold,
)
from dgpc_cli.stages.input_status import check_inputs, with_accepted

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class MoldOptions:
    """The options of ``extract-mold`` (see its help)."""

    segments: int | None = None
    lam: str | float | None = None
    panel_size: int = DEFAULT_PANEL_SIZE
    flat_tol: float = DEFAULT_FLAT_TOL
    max_length: object = None       # a Length as given (its unit or none), or None
    tol: float | None = None        # None: DEFAULT_TOL_FACTOR × max_strain
    max_strain: float = DEFAULT_MAX_STRAIN
    accept_status: bool = False     # go on with nets not converged (stages.input_status)


def _files(output: Path, opts: MoldOptions, mold, metrics: dict, loaded, unit: str, tol: float,
           max_length: float | None, carried: list[dict]) -> dict:
    """The mold artifact's files of ``mold`` (of metrics ``metrics``) extracted from the nets
    ``loaded``."""
    paths = mold_paths(output)
    folder = paths["json"].resolve().parent
    inputs = {f"net{k + 1}": file_input(name, folder) for k, (name, _) in enumerate(loaded)}
    mer = mold.meridian
    message = (f"λ lowered from {mer.requested * mer.lam / mer.segments:.6g} to {mer.lam:.6g} "
               "so that every x(u) is real" if mer.lowered else "ok")
    return mold_files(
        output,
        profile={"r": mer.r, "h": mer.h, "d": mer.d, "l": mer.l, "x": mer.x},
        units=unit,
        profile_dxf=profile_dxf(mer.r, mer.h, unit, [(p.id, p.start, p.stop)
                                                     for p in mold.pieces]),
        segments={"segments": mer.segments, "segments_requested": mer.requested,
                  "lambda": mer.lam, "lambda_lowered": mer.lowered},
        sector_deg=math.degrees(mold.sector_angle),
        pieces=[{"id": p.id, "rows": [p.start, p.stop], "meridian_length": p.length}
                for p in mold.pieces],
        nets=[{"input": f"net{k + 1}", "shape": list(p.shape),
               "column_angles_deg": [math.degrees(t) for t in p.theta.tolist()],
               "revolution_residual_max": p.residual_max} for k, p in enumerate(mold.nets)],
        net_geometry=[net.f for _, net in loaded],
        panels=mold.panel_records(),
        panel_size=opts.panel_size,
        inputs=inputs,
        parameters={"segments": opts.segments,
                    "lambda": mold.choice.how if opts.segments is None
                    and mold.choice.how != "value" else opts.lam,
                    "panel_size": opts.panel_size, "flat_tol": opts.flat_tol,
                    "mold_max_length": max_length, "revolution_tol": tol,
                    "max_strain": opts.max_strain, "units": unit},
        metrics=metrics,
        status=with_accepted({"state": "ok", "lambda_lowered": mer.lowered,
                              "message": message}, carried),
    )


def run_extract_mold(nets: list[Path], output: Path, opts: MoldOptions, *, force: bool, fmt,
                     check_units: Callable[[str, str], None],
                     chosen: Callable[[str], None],
                     written: Callable[[Path], None]) -> None:
    """Extract the mold of the nets ``nets`` into the mold artifact ``output``.

    ``check_units(unit, source)`` checks the nets' unit against the one the user expects
    (raising where they differ); a ``--mold-max-length`` that breaks the rule of every
    length raises :class:`~dgpc_cli.errors.OptionSlip` (nothing is written);
    ``chosen(line)`` is given the one line saying which surface of revolution the mold is;
    ``written(json_path)`` is called once the files are written."""
    tol = opts.tol if opts.tol is not None else DEFAULT_TOL_FACTOR * opts.max_strain
    loaded = [(str(artifact_paths(stem)[0]), read_net(stem)) for stem in nets]
    carried = check_inputs([(f"net{k + 1}", name, net.status)
                            for k, (name, net) in enumerate(loaded)], "extract-mold",
                           opts.accept_status)
    for name, net in loaded:
        require_sound_net(net.f, name)
    unit = same_units([(name, net.units) for name, net in loaded])
    check_units(unit, loaded[0][0])
    given = opts.max_length
    max_length = (None if given is None
                  else given.check("--mold-max-length", unit) / mm_per_unit(unit))
    mold = extract_mold([(name, net.f) for name, net in loaded], segments=opts.segments,
                        lam=opts.lam, panel_size=opts.panel_size, flat_tol=opts.flat_tol,
                        max_length=max_length, tol=tol, max_strain=opts.max_strain)
    check_max_length(mold, given, unit)
    chosen(mold.choice_line(unit))
    metrics = mold.metrics()
    files = _files(output, opts, mold, metrics, loaded, unit, tol, max_length, carried)
    write_files(with_3dm(files, output, fmt), force=force)
    json_path = mold_paths(output)["json"]
    written(json_path)
    mer = mold.meridian
    log.info("%s: N = %.6g (λ = %.6g), %d mold pieces, %d curved and %d flat panels, isometry "
             "error ≤ %.3g", json_path, mer.segments, mer.lam, metrics["pieces"],
             metrics["panels_curved"], metrics["panels_flat"], metrics["isometry_error_max"])
