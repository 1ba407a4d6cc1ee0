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
    #: The net within the largest strip width, made when the net is kept (``init`` first
    #: decides on patches by the net as the search chose it); None: ``net`` is that already.
    narrowed: Callable[[], MeshNet] | None = None


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
             say: Callable[[str], None] | None = None, strip_width: float | None = None,
             strip_width_given: bool = False, units: str = "") -> MeshNet:
    """The net of ``init REFERENCE --method METHOD`` (lengths in the mesh's unit, ``units``;
    ``extend``: the fraction of ``--extend``, None when not given; ``strip_width``: the
    largest strip width, ``stages.init_width``, None for none). ``status`` makes the status
    line the geodesic search updates; ``say``, when given, gets the lines that say which net
    was chosen and, where there is something to say, how wide its strips are."""
    from dgpc_cli.geodesics.extension import continued
    from dgpc_cli.io.mesh import load_mesh
    from dgpc_cli.stages.init_choice import choose
    from dgpc_cli.stages.init_search import search
    from dgpc_cli.stages.init_width import tell, widened_choice

    if rows is not None and cols is not None:  # refused before the mesh is read
        check_net_size(rows, cols, "--rows/--cols", "use fewer --rows or --cols")
    mesh = load_mesh(reference, pieces="largest" if largest_component else "one")
    found = None
    widen_cols = cols is None and spacing is None
    if method == "geodesic":
        with status() as progress:
            found = search(mesh, base=base, direction=direction, angle=angle, rows=rows,
                           cols=cols, spacing=spacing, extend=extend, progress=progress,
                           strip_width=strip_width, strip_width_given=strip_width_given,
                           defer_width=True)
        options = {"base": base, "angle": angle, "largest_component": largest_component}
        made = _searched_net(found, mesh, options, say, units, tell_width=found.narrowed is None)
        if found.narrowed is not None:
            def narrowed() -> MeshNet:
                with status() as progress:
                    later = found.narrowed(progress)
                return _searched_net(later, mesh, options, None, units, say_width=say)

            made.narrowed = narrowed
        return made
    else:
        extend = extend or 0.0
        domain = continued(mesh, extend)

        def make(n):
            return choose(mesh, domain, method, base=base, direction=direction, angle=angle,
                          rows=rows, cols=n, spacing=spacing,
                          extend_length=extend * mesh.bbox_diagonal)

        grid, outcome, tried = make(cols)
        width = None
        if strip_width is not None:
            (grid, outcome, tried), width = widened_choice(
                mesh, (grid, outcome, tried), make, cols, strip_width, strip_width_given,
                widen_cols)
    net = _recorded(grid, outcome, tried, extend, width,
                    {"base": base, "angle": angle, "largest_component": largest_component},
                    method)
    if say is not None:
        say(_summary(method, net, mesh, grid.label, outcome, tried, None))
    tell(width, units, say)
    return MeshNet(net=net, mesh=mesh)


def _recorded(grid, outcome, tried: list, extend: float, width: dict | None, options: dict,
              method: str, search_record: dict | None = None) -> NetArtifact:
    """The net of ``grid`` with the command's parameters and ``data.init.choice``."""
    net = grid.net
    net.parameters.update(base=options["base"] or ("auto" if method == "geodesic" else None),
                          angle=options["angle"],
                          largest_component=options["largest_component"])
    if extend > 0:
        net.parameters["extend"] = extend
    net.data["init"]["choice"] = {"chosen": grid.label, "coverage": outcome.coverage,
                                  "tried": tried}
    if search_record is not None:
        net.data["init"]["choice"]["search"] = search_record
    if width is not None:
        net.data["init"]["choice"]["strip_width"] = width
    if outcome.note:
        log.warning("%s", outcome.note)
    return net


def _searched_net(found, mesh: ReferenceMesh, options: dict,
                  say: Callable[[str], None] | None, units: str, tell_width: bool = True,
                  say_width: Callable[[str], None] | None = None) -> MeshNet:
    """The :class:`MeshNet` of the geodesic search's result ``found``; ``say`` gets the line
    that says which net was chosen, ``say_width`` (default ``say``; only with
    ``tell_width``) the line of its largest strip width."""
    from dgpc_cli.stages.init_width import tell

    tried = [t.record for t in found.trials]
    net = _recorded(found.grid, found.outcome, tried, found.extend, found.width, options,
                    "geodesic", found.record)
    if say is not None:
        say(_summary("geodesic", net, mesh, found.grid.label, found.outcome, tried, found))
    if tell_width:
        tell(found.width, units, say_width or say, options=found.record["options"])
    return MeshNet(net=net, mesh=mesh, poor=_poor(found))
