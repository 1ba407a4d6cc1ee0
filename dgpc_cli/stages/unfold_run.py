"""The ``unfold`` run: read the strips, develop them in mm (cut into boards where asked),
group them into templates, warn, and write the flat artifact with its template DXFs."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.soundness import require_sound_strips
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.flat import FlatArtifact, flat_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import mm_per_unit, to_mm
from dgpc_cli.stages.input_status import check_inputs, with_accepted
from dgpc_cli.stages.unfold import (
    checked_lengths,
    flat_metrics,
    narrow_warnings,
    records_in_units,
    scale_warnings,
    template_dxfs,
    unfold_strips,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class UnfoldOptions:
    """The options of ``unfold`` (see its help). The lengths are
    :class:`~dgpc_cli.io.length.Length` (``stock_length`` and ``stagger`` may be None)."""

    congruence_tol: Any
    label_style: str
    mirror_ok: bool = False
    stock_length: Any = None
    stagger: Any = None
    accept_status: bool = False     # go on with strips that fell short (stages.input_status)


def _read_sound(stem: Path, accept_status: bool):
    """The strips artifact ``stem``, its JSON path and the records of the flat's
    ``status.accepted``; refused (DgpcError) where its status falls short (without
    ``accept_status``), or a strip or a trimmed part of one is not sound."""
    json_path, _ = artifact_paths(stem)
    strips = read_strips(stem)
    carried = check_inputs([("strips", json_path, strips.status)], "unfold", accept_status)
    require_sound_strips(strips.geometry, [r["id"] for r in strips.records], json_path,
                         [[p["rows"] for p in r["trim"]["parts"]] if r.get("trim") else None
                          for r in strips.records],
                         [[p["outline"] for p in r["trim"]["parts"]] if r.get("trim") else None
                          for r in strips.records])
    return strips, json_path, carried


def run_unfold(stem: Path, output: Path, opts: UnfoldOptions, *, force: bool, fmt,
               written: Callable[[Path], None]) -> None:
    """Unfold the strips artifact ``stem`` into the flat artifact ``output``.

    The strips are developed in mm and the records written in the strips' unit.
    ``written(out_json)`` is called once the files are written. Raises
    :class:`~dgpc_cli.errors.OptionSlip` (before any work) where a length breaks the rule of
    every length (:func:`~dgpc_cli.stages.unfold.checked_lengths`)."""
    strips, json_path, carried = _read_sound(stem, opts.accept_status)
    units = strips.units                 # computed in mm (dgpc_cli.io.units)
    stock_length, stagger, congruence_tol = opts.stock_length, opts.stagger, opts.congruence_tol
    geometry = [(to_mm(A, units), to_mm(B, units)) for A, B in strips.geometry]
    tol_mm, stock_mm, stagger_mm = checked_lengths(geometry, units, congruence_tol,
                                                   stock_length, stagger)
    try:
        parts, classes, joints = unfold_strips(
            geometry, [r["id"] for r in strips.records], [r["v"] for r in strips.records],
            congruence_tol=tol_mm, mirror_ok=opts.mirror_ok,
            stock_length=stock_mm, stagger=None if stagger is None else stagger_mm,
            source=json_path,
            trims=[r.get("trim") for r in strips.records],
            cut_edges=[r.get("cut_edges") for r in strips.records],
            template=strips.template is not None and "rejected" not in strips.template,
            refine=strips.parameters.get("refine", 1))
    except DgpcError as err:
        typed = {"--stock-length": stock_length, "--stagger": stagger}.get(err.source)
        if typed is None:
            raise
        # the length as the user typed it, with its unit (the boards compute in mm)
        raise DgpcError(err.reason, source=f"{err.source} {typed.said(units)}") from None
    for line in scale_warnings(parts, geometry, units, stock_length) + narrow_warnings(parts,
                                                                                      units):
        log.warning("%s: %s", json_path, line)
    templates = template_dxfs(parts, classes, opts.label_style)
    parts, classes, joints = records_in_units(parts, classes, joints, units)
    out_json, _ = artifact_paths(output)
    art = FlatArtifact(
        parts=parts, classes=classes, units=units, joints=joints, templates=templates,
        parameters={"mirror_ok": opts.mirror_ok, "congruence_tol": congruence_tol.text(),
                    "label_style": opts.label_style,
                    "congruence_tol_mm": congruence_tol.to_mm(units),
                    "stock_length": None if stock_mm is None else stock_mm / mm_per_unit(units),
                    "stagger": None if stagger_mm is None else stagger_mm / mm_per_unit(units)},
        inputs={"strips": file_input(json_path, out_json.resolve().parent)},
        metrics=flat_metrics(parts, classes, units),
        status=with_accepted({"n_classes": len(classes)}, carried))
    write_files(with_3dm(flat_files(output, art), output, fmt), force=force)
    written(out_json)
