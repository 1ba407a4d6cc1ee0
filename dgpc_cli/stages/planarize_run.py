"""The ``planarize-strips`` run: read the net, fit the strips (one template or each on its
own), trim them, build and write the strips artifact, warn and report what failed."""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

from dgpc_cli.errors import DgpcError, NotConverged
from dgpc_cli.fitting.soundness import require_sound_net
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import StripsArtifact, strips_files
from dgpc_cli.stages.input_status import check_inputs, with_accepted
from dgpc_cli.stages.strip_fabrication import (
    DEVIATION_WARN,
    SEAM_STEP_WARN,
    fabrication_metrics,
    fabrication_warnings,
    missed_targets,
)
from dgpc_cli.strips.planarize import (
    FLAT_ANGLE,
    MAX_RULING_TURN,
    POLISH_ABOVE,
    RULING_FAIRNESS,
    SEAM_WEIGHT,
    crossed_strips,
    parse_strip_range,
    planarize_strips,
    refine_rows,
    strips_metrics,
    template_qualifies,
    template_strips,
    trim_records,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PlanarizeOptions:
    """The options of ``planarize-strips`` (see its help)."""

    strip_range: str | None = None
    flat_angle: float = FLAT_ANGLE
    trim: bool = False
    per_strip: bool = False
    seam_weight: float = SEAM_WEIGHT
    ruling_fairness: float = RULING_FAIRNESS
    max_ruling_turn: float = MAX_RULING_TURN
    refine: int | None = None       # None: --refine auto
    accept_status: bool = False     # go on with a net not converged (stages.input_status)


def _outline(net, json_path):
    """The reference the net records, for --trim; DgpcError naming --trim without one."""
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.stages.inspect import recorded_reference

    mesh = recorded_reference(net, json_path)
    if mesh is None:
        raise DgpcError(f"--trim clips to the reference the net records, and {json_path} "
                        "records none that is there", source="--trim")
    return ReferenceSurface.from_mesh(mesh)


def _fit(net, columns, opts: PlanarizeOptions, refine: int, reason, progressbar):
    """The strips of ``refine`` rulings per net row, in the net's units: one template where
    ``reason`` is None and the fit is accepted, else each strip on its own. Returns the
    strips, the template record (None without one) and the rejected fit's record (or None)."""
    f_mm = refine_rows(net.f_mm, refine)
    with progressbar(len(columns), "planarize strips") as bar:
        strips = planarize_strips(f_mm, columns, flat_angle=opts.flat_angle,
                                  progress=bar.update)
    template = fallback = None
    if reason is None:
        log.info("planarize-strips: one template for all strips (the net is isometric to a "
                 "surface of revolution with equal strip widths)")
        fitted, record = template_strips(f_mm, strips, net.units,
                                         seam_weight=opts.seam_weight,
                                         ruling_fairness=opts.ruling_fairness,
                                         max_ruling_turn=opts.max_ruling_turn)
        if fitted is None:
            log.warning("planarize-strips: every strip on its own, no shared template: %s",
                        record["rejected"])
            fallback = record
        else:
            template = record
        strips = fitted or strips
    elif not opts.per_strip:
        log.warning("planarize-strips: every strip on its own, no shared template: the net %s",
                    reason)
    return [s.in_units(net.units) for s in strips], template, fallback


@dataclass
class _Fitted:
    """One fit made into the strips artifact, with what its run reports."""

    art: StripsArtifact
    strips: list
    notes: list[str]          # what the trim dropped


def _artifact(net, inputs: dict, columns, outline, opts: PlanarizeOptions, refine: int,
              fit) -> _Fitted:
    """The strips artifact of the fit ``(strips, template, fallback)`` (trimmed to
    ``outline`` where given), its ``inputs`` record ``inputs``."""
    strips, template, fallback = fit
    m, n = net.shape
    records = [s.record() for s in strips]
    if outline is not None:
        trims, notes = trim_records(strips, outline)
        for record, cut in zip(records, trims, strict=True):
            record["trim"] = cut
    else:
        notes = []
    polished = [s for s in strips if s.polish.get("applied")]
    failed = [s.id for s in polished if s.polish.get("status") != "converged"]
    crossed = crossed_strips(strips, records, net.f)
    art = StripsArtifact(
        geometry=[(s.A, s.B) for s in strips], records=records,
        source_shape=(m, n), units=net.units,
        parameters={"strips": [columns[0], columns[-1]], "flat_angle": opts.flat_angle,
                    "polish_above": POLISH_ABOVE, "trim": opts.trim,
                    "method": "per-strip" if template is None else "template",
                    "seam_weight": opts.seam_weight, "ruling_fairness": opts.ruling_fairness,
                    "max_ruling_turn": opts.max_ruling_turn,
                    **({"refine": refine} if refine > 1 else {}),
                    **({"template_rejected": fallback} if fallback else {})},
        template=template,
        inputs=inputs,
        metrics={**strips_metrics(records, net.units),
                 "fabrication": fabrication_metrics(net.f, net.units, records,
                                                    [(s.A, s.B) for s in strips], outline,
                                                    refine=refine)},
        status={"polished": len(polished), "polish_not_converged": failed,
                "rulings_cross": crossed})
    return _Fitted(art, strips, notes)


def _figures(art: StripsArtifact) -> dict:
    """The largest deviation from the net and seam step, relative to the mean strip width."""
    fab = art.metrics["fabrication"]
    return {"deviation": fab.get("max_deviation_relative"),
            "seam_step": fab.get("max_seam_step_relative")}


def _better(fine: dict, coarse: dict) -> bool:
    """Whether the refined strips' figures ``fine`` beat ``coarse``: a lower seam step and a
    deviation no higher."""
    if any(v is None or v != v for v in (*fine.values(), *coarse.values())):
        return False
    return fine["seam_step"] < coarse["seam_step"] and fine["deviation"] <= coarse["deviation"]


def _percent(figures: dict) -> str:
    def pct(v):
        return "n/a" if v is None or v != v else f"{100 * v:.2f} %"
    return f"deviation {pct(figures['deviation'])}, seam step {pct(figures['seam_step'])}"


def _auto_refine(first: _Fitted, fit_again) -> _Fitted:
    """``--refine auto``: the strips of one template ``first`` (K = 1) where they meet the
    targets, else the strips of ``fit_again()`` (K = 2) where :func:`_better`; the choice is
    recorded in the kept artifact's ``parameters.refine_auto`` and said in one stderr line."""
    coarse = _figures(first.art)
    if first.art.template is None or not missed_targets(first.art.metrics["fabrication"]):
        return first
    second = fit_again()
    fine = _figures(second.art)
    keep = second if _better(fine, coarse) else first
    k = 2 if keep is second else 1
    keep.art.parameters["refine_auto"] = {
        "tried": [1, 2], "kept": k,
        "figures": {"1": coarse, "2": fine},
        "against": {"1": "net", "2": "refined net"}}
    log.warning("planarize-strips: --refine auto: K = 1 misses the targets (%s of the mean "
                "strip width; targets %g %% and %g %%), K = 2 gives %s (against the refined "
                "net): K = %d kept", _percent(coarse), 100 * DEVIATION_WARN,
                100 * SEAM_STEP_WARN, _percent(fine), k)
    return keep


@contextlib.contextmanager
def _no_progress(length: int, label: str):
    """A progress bar that shows nothing."""
    yield SimpleNamespace(update=lambda n: None)


def planarized(net, columns: list[int], opts: PlanarizeOptions, *, outline=None,
               inputs: dict | None = None, progressbar: Callable = _no_progress) -> _Fitted:
    """The strips ``planarize-strips`` makes of the strips ``columns`` of the net ``net`` (a
    :class:`~dgpc_cli.io.net.NetArtifact`, read or in memory) with ``opts``, in memory: one
    template where the net qualifies, else each strip on its own; ``--refine auto``
    (``opts.refine`` None) as :func:`_auto_refine`; trimmed to ``outline`` where given. The
    artifact records ``inputs``. Nothing is written or said but the log."""
    reason = "--per-strip" if opts.per_strip else template_qualifies(net.f_mm, columns)

    def run(refine: int) -> _Fitted:
        return _artifact(net, inputs or {}, columns, outline, opts, refine,
                         _fit(net, columns, opts, refine, reason, progressbar))

    if opts.refine is None:
        return _auto_refine(run(1), lambda: run(2))
    return run(opts.refine)


def run_planarize_strips(stem: Path, output: Path, opts: PlanarizeOptions, *, force: bool,
                         fmt, progressbar: Callable, written: Callable[[Path], None]) -> None:
    """Planarize the strips of the net ``stem`` into the strips artifact ``output``.

    ``opts.refine`` None is ``--refine auto``: K = 1, and K = 2 where one template's K = 1
    strips miss the deviation or seam-step target and K = 2 does better
    (:func:`_auto_refine`). ``progressbar(length, label)`` is a context manager with
    ``update``; ``written(out_json)`` is called once the files are written, before the
    warnings. Raises NotConverged (after writing) where a polish did not converge or rulings
    cross."""
    json_path, _ = artifact_paths(stem)
    net = read_net(stem)
    carried = check_inputs([("net", json_path, net.status)], "planarize-strips",
                           opts.accept_status)
    require_sound_net(net.f, json_path, gpc=False)
    columns = parse_strip_range(opts.strip_range, net.shape[1])
    outline = _outline(net, json_path) if opts.trim else None
    out_json, _ = artifact_paths(output)
    done = planarized(net, columns, opts, outline=outline, progressbar=progressbar,
                      inputs={"net": file_input(json_path, out_json.resolve().parent)})
    art = done.art
    art.status = with_accepted(art.status, carried)
    failed, crossed = art.status["polish_not_converged"], art.status["rulings_cross"]
    for note in done.notes:
        log.warning("%s", note)
    write_files(with_3dm(strips_files(output, art), output, fmt), force=force)
    written(out_json)
    for note in fabrication_warnings(art.metrics["fabrication"]):
        log.warning("%s: %s", out_json, note)
    log.info("%s: %d strips, max planarity %.3g of the diagonal, max deviation %.3g of the "
             "width", out_json, len(done.strips), art.metrics["max_planarity_diagonal_relative"],
             art.metrics["max_deviation_relative"])
    if failed:
        raise NotConverged(f"the polish of {', '.join(failed)} did not reach its tolerance "
                           f"(max planarity {art.metrics['max_planarity_diagonal_relative']:.3g}"
                           " of the diagonal); written anyway",
                           source=out_json)
    if crossed:
        raise NotConverged(f"the rulings of {', '.join(crossed)} cross (folded quads, the "
                           "strip cannot be unfolded); written anyway", source=out_json)
