"""``dgpc init MESH --method geodesic|project``: the net on a reference mesh, with the record of
how it was chosen (SPEC §5).

The mesh is loaded, the candidates are tried (``stages.init_search`` for ``geodesic``,
``stages.init_choice`` for ``project`` and a given base), and the net chosen gets the
command's parameters and ``data.init.choice``: the candidate, its coverage and every candidate
tried (``geodesic``: and the search's record).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from pathlib import Path

from dgpc_cli.io.mesh import ReferenceMesh
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.stages.net_size import check_net_size

log = logging.getLogger(__name__)

#: A status line the search updates: a context manager giving a ``progress(text)`` callback.
Status = Callable[[], AbstractContextManager]


@dataclass
class MeshNet:
    """The net made on ``mesh`` (the reference, loaded)."""

    net: NetArtifact
    mesh: ReferenceMesh
    #: Why one net is poor here (``--method geodesic``: it covers less than the search aims
    #: at, or folds, after its quick fit), None when it is not.
    poor: str | None = None


def _poor(found) -> str | None:
    """Why the net the search chose is poor (see :class:`MeshNet`), or None."""
    from dgpc_cli.stages.init_search import EXTEND_BELOW

    quick = found.chosen.quick or {}
    if "coverage" not in quick:
        return None
    folds = bool(quick.get("folded"))
    if quick["coverage"] >= EXTEND_BELOW and not folds:
        return None
    return (f"the net covers {100 * quick['coverage']:.1f} % of the mesh after a quick fit"
            + (" and folds" if folds else ""))


def _summary(method: str, net: NetArtifact, mesh: ReferenceMesh, label: str, outcome,
             tried: list, found) -> str:
    """The stderr line that says which candidate was chosen, its coverage, and why."""
    if method == "geodesic":
        quick = found.chosen.quick or {}
        after = (f", {100 * quick['coverage']:.1f} % after a quick fit"
                 if "coverage" in quick else "")
        return (f"init: {found.chosen.describe()}, {net.shape[0]} x {net.shape[1]} net "
                f"covering {100 * outcome.coverage:.1f} % of {mesh.path.name}{after}: "
                f"chosen of {len(tried)} candidates because it {found.why} "
                f"(options: {found.record['options']})")
    others = ", ".join(f"{t['candidate']} {100 * t['coverage']:.1f} %" for t in tried
                       if "coverage" in t and t["candidate"] != label)
    return (f"init: {label}, {net.shape[0]} x {net.shape[1]} net covering "
            f"{100 * outcome.coverage:.1f} % of {mesh.path.name}"
            + (f" (also tried: {others})" if others else ""))


def mesh_net(reference: Path, method: str, *, base: str | None, direction, angle: float | None,
             rows: int | None, cols: int | None, spacing: float | None,
             largest_component: bool, extend: float | None, status: Status = nullcontext,
             say: Callable[[str], None] | None = None) -> MeshNet:
    """The net of ``init REFERENCE --method METHOD`` (lengths in the mesh's unit; ``extend``:
    the fraction of ``--extend``, None when not given). ``status`` makes the status line the
    geodesic search updates; ``say``, when given, gets the line that says which net was
    chosen."""
    from dgpc_cli.geodesics.extension import continued
    from dgpc_cli.io.mesh import load_mesh
    from dgpc_cli.stages.init_choice import choose
    from dgpc_cli.stages.init_search import search

    if rows is not None and cols is not None:  # refused before the mesh is read
        check_net_size(rows, cols, "--rows/--cols", "use fewer --rows or --cols")
    mesh = load_mesh(reference, pieces="largest" if largest_component else "one")
    found = None
    if method == "geodesic":
        with status() as progress:
            found = search(mesh, base=base, direction=direction, angle=angle, rows=rows,
                           cols=cols, spacing=spacing, extend=extend, progress=progress)
        grid, outcome, extend = found.grid, found.outcome, found.extend
        tried = [t.record for t in found.trials]
    else:
        extend = extend or 0.0
        grid, outcome, tried = choose(mesh, continued(mesh, extend), method, base=base,
                                      direction=direction, angle=angle, rows=rows, cols=cols,
                                      spacing=spacing, extend_length=extend * mesh.bbox_diagonal)
    net = grid.net
    net.parameters.update(base=base or ("auto" if method == "geodesic" else None),
                          angle=angle, largest_component=largest_component)
    if extend > 0:
        net.parameters["extend"] = extend
    net.data["init"]["choice"] = {"chosen": grid.label, "coverage": outcome.coverage,
                                  "tried": tried}
    if method == "geodesic":
        net.data["init"]["choice"]["search"] = found.record
    if outcome.note:
        log.warning("%s", outcome.note)
    if say is not None:
        say(_summary(method, net, mesh, grid.label, outcome, tried, found))
    return MeshNet(net=net, mesh=mesh, poor=_poor(found) if found is not None else None)
