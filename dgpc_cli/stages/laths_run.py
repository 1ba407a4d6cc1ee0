"""The ``laths`` run: read two transversal nets, find the laths of their gridshell and the
crossings, and write the laths artifact with its cut list."""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.soundness import require_sound_net
from dgpc_cli.geodesics.laths import checked_gap, crossing_gap, gridshell
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.laths import laths_files
from dgpc_cli.io.net import read_net
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import same_units
from dgpc_cli.stages.input_status import check_inputs, with_accepted

log = logging.getLogger(__name__)


def _read_pair(net_a: Path, net_b: Path, accept_status: bool):
    """The nets ``net_a`` and ``net_b``, their common unit and the records of the laths'
    ``status.accepted``, refused (DgpcError) where they are one net, not sound, in different
    units, or (without ``accept_status``) not converged; warns where they record different
    references."""
    a, b = read_net(net_a), read_net(net_b)
    json_a, json_b = artifact_paths(net_a)[0], artifact_paths(net_b)[0]
    carried = check_inputs([("net_a", json_a, a.status), ("net_b", json_b, b.status)],
                           "laths", accept_status)
    if json_a.resolve() == json_b.resolve() or np.array_equal(a.f, b.f):
        raise DgpcError("is the same net as NET_A: its laths would lie on their own copies; "
                        "give two transversal nets", source=json_b)
    require_sound_net(a.f, json_a)
    require_sound_net(b.f, json_b)
    units = same_units([(str(json_a), a.units), (str(json_b), b.units)])
    ref_a, ref_b = a.data.get("reference"), b.data.get("reference")
    if ref_a and ref_b and ref_a.get("sha256") != ref_b.get("sha256"):
        log.warning("%s and %s record different references", net_a, net_b)
    return a, b, units, carried


def run_laths(net_a: Path, net_b: Path, output: Path, gap: Any, *, force: bool, fmt,
              written: Callable[[Path], None], accept_status: bool = False) -> None:
    """Write the laths artifact ``output`` of the gridshell of the nets ``net_a`` and
    ``net_b``.

    ``gap`` is a :class:`~dgpc_cli.io.length.Length` or None (the default gap).
    ``written(out_json)`` is called once the files are written. Raises
    :class:`~dgpc_cli.errors.OptionSlip` (before any work) where the gap breaks the rule of
    every length (:func:`~dgpc_cli.geodesics.laths.checked_gap`)."""
    a, b, units, carried = _read_pair(net_a, net_b, accept_status)
    gap = crossing_gap(a.f, b.f, checked_gap(a.f, b.f, gap, units))
    laths_a, laths_b, crossings = gridshell(a.f, b.f, gap=gap)
    if len(crossings.a) == 0:
        raise DgpcError("the laths of the two nets do not cross (are the nets on one reference, "
                        "in transversal directions?)", source=net_b)
    all_laths = laths_a + laths_b
    lengths = np.array([lt.length for lt in all_laths])
    json_path, _ = artifact_paths(output)
    folder = json_path.resolve().parent
    inputs = {"net_a": file_input(artifact_paths(net_a)[0], folder),
              "net_b": file_input(artifact_paths(net_b)[0], folder)}
    metrics = {"laths": len(all_laths), "crossings": int(len(crossings.a)),
               "crossing_gap_max": float(crossings.gap.max()),
               "length_total": float(lengths.sum()), "length_max": float(lengths.max())}
    files = laths_files(output, all_laths, crossings, units=units, inputs=inputs,
                        parameters={"gap": gap}, metrics=metrics,
                        status=with_accepted({}, carried))
    write_files(with_3dm(files, output, fmt), force=force)
    log.info("%d laths, %d crossings, largest gap %.3g", len(all_laths), len(crossings.a),
             metrics["crossing_gap_max"])
    written(json_path)
