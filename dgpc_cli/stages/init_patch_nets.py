"""``dgpc init MESH --patches auto|K``: one net per patch of the reference (the split:
``stages.init_patches``), written as ``STEM.p1``, ``STEM.p2``, … each with its patch mesh
``STEM.pK.patch.obj`` as its reference."""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths, file_input, relative_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import NetArtifact, net_files
from dgpc_cli.io.rhino import with_3dm

log = logging.getLogger(__name__)


def _record_choice(net: NetArtifact, label: str, outcome, tried: list, options: dict) -> None:
    """What ``init`` records of its choice on a net (as for a single net)."""
    method = options["method"]
    net.parameters.update(base=options["base"] or ("auto" if method == "geodesic" else None),
                          angle=options["angle"],
                          largest_component=options["largest_component"])
    searched = "search" in net.data["init"]
    if options["extend"] > 0 and "extend" not in net.parameters and not searched:
        net.parameters["extend"] = options["extend"]
    net.data["init"]["choice"] = {"chosen": label, "coverage": outcome.coverage,
                                  "tried": tried}
    if searched:
        net.data["init"]["choice"]["search"] = net.data["init"].pop("search")
    if "strip_width" in net.data["init"]:
        net.data["init"]["choice"]["strip_width"] = net.data["init"].pop("strip_width")
    if options.get("strip_width_given"):
        net.parameters["strip_width"] = options["strip_width"]
    if outcome.note:
        log.warning("%s", outcome.note)


def _searched(m, whole, options: dict):
    """The net of one patch ``m`` of the mesh ``whole`` by ``init``'s search
    (``stages.init_search``: base curves, overhang, size, ranked after a quick fit), as for a
    single net, its overhang running onto the whole mesh around the patch
    (``geodesics.extension.surrounded``; the net's ``data.surroundings``, the whole mesh, tells
    ``optimize`` to fit it there); the search's record rides on the net
    (``data.init.search``, and its largest strip width ``data.init.strip_width``) until the
    choice is recorded. ``(grid, outcome, tried, narrowed)``: ``narrowed()`` makes the net
    within the largest strip width, once the patches are decided by the nets as chosen
    (None: nothing to do)."""
    from dgpc_cli.stages.init_mesh import DEFAULT_COLS
    from dgpc_cli.stages.init_search import search

    cols = options["cols"]
    widen_cols = cols is None and options["spacing"] is None
    if widen_cols:
        # a patch is smaller than the whole: its size not searched, only made finer where its
        # strips are wider than the largest strip width
        cols = DEFAULT_COLS
    found = search(m, base=options["base"], direction=options["direction"],
                   angle=options["angle"], rows=options["rows"], cols=cols,
                   spacing=options["spacing"], extend=None, surroundings=whole,
                   strip_width=options.get("strip_width"),
                   strip_width_given=bool(options.get("strip_width_given")),
                   widen_cols=widen_cols, defer_width=True)
    later = found.narrowed
    return (*_found_net(found), (lambda: _found_net(later())) if later is not None else None)


def _found_net(found):
    """``(grid, outcome, tried)`` of a patch's search result, its records on the net."""
    net = found.grid.net
    if found.extend > 0:
        net.parameters["extend"] = found.extend
        net.data["init"]["overhang_onto"] = "the mesh around the patch"
    net.data["init"]["search"] = found.record
    if found.width is not None:
        net.data["init"]["strip_width"] = found.width
    return found.grid, found.outcome, [t.record for t in found.trials]


def patch_nets(single: NetArtifact, mesh, patches, output: Path, options: dict, *,
               units: str, fmt: str, force: bool, check: Callable[..., None],
               say: Callable[[str], None] | None = None,
               switched: bool = False) -> list[Path] | None:
    """Make and write the patch nets of ``--patches`` (``options``: the command's mesh
    options); the JSON paths written, or None when one patch is kept (``single`` then records
    why, and the caller writes it as usual). ``check(stem, force, *extra)`` refuses a target
    before anything is written; ``say``, when given, gets the lines that say why and what.
    ``switched``: ``init`` chose ``--patches auto`` itself (the single net is poor); one net
    is then kept as it was made, recording nothing of patches, unless the patches cover more
    of the mesh than it."""
    from dgpc_cli.core.reference import ReferenceSurface
    from dgpc_cli.geodesics.extension import (
        FIT_REACH,
        continued,
        largest_unfolded,
        surrounded,
    )
    from dgpc_cli.stages.init_choice import choose
    from dgpc_cli.stages.init_patches import narrowed, plan, ratio_text
    from dgpc_cli.stages.init_width import require_met, tell, widened_choice
    from dgpc_cli.stages.inspect import summarize

    def make(m):
        if options["method"] == "geodesic" and options.get("given_extend", 0.0) is None:
            return _searched(m, mesh, options)
        # --extend is a fraction of the whole mesh's diagonal: the same length on every patch,
        # as far as the patch's continuation does not fold at its concave boundary
        fraction = options["extend"] * mesh.bbox_diagonal / m.bbox_diagonal
        try:
            domain = continued(m, fraction)
        except DgpcError:
            fraction = largest_unfolded(m, fraction)
            log.warning("%s: --extend %g folds the patch's continuation at its concave "
                        "boundary; extended by %.3g of the patch's diagonal instead",
                        m.path.name, options["extend"], fraction)
            domain = continued(m, fraction)

        def chosen(n):
            return choose(m, domain, options["method"], base=options["base"],
                          direction=options["direction"], angle=options["angle"],
                          rows=options["rows"], cols=n, spacing=options["spacing"],
                          extend_length=fraction * m.bbox_diagonal)

        grid, outcome, tried = chosen(options["cols"])
        if options.get("strip_width") is not None:
            (grid, outcome, tried), width = widened_choice(
                m, (grid, outcome, tried), chosen, options["cols"], options["strip_width"],
                bool(options.get("strip_width_given")),
                options["cols"] is None and options["spacing"] is None)
            grid.net.data["init"]["strip_width"] = width
        if fraction > 0:
            grid.net.parameters["extend"] = fraction
        return grid, outcome, tried, None

    json_path, _ = artifact_paths(output)
    stem = json_path.with_suffix("")
    folder = json_path.resolve().parent
    choice = single.data["init"]["choice"]
    count = None if patches == "auto" else int(patches)
    nets, record = plan(mesh, count, stem, single.f, choice["chosen"], choice["coverage"],
                        make)
    if switched and nets:
        area = sum(p.patch.area for p in nets)
        covered = sum(p.patch.area * p.outcome.coverage for p in nets) / area
        if covered <= choice["coverage"]:
            record["reason"] += (f"; but the patches cover {100 * covered:.1f} % of the mesh, "
                                 f"no more than one net ({100 * choice['coverage']:.1f} %)")
            nets = []
    if say is not None:
        say(f"init: {record['reason']}")
    if not nets and switched:
        return None
    if not nets:
        single.parameters["patches"] = patches
        single.data["patches"] = record
        return None
    for k, p in enumerate(nets, start=1):     # every target checked before any is written
        check(stem.parent / f"{stem.name}.p{k}", force, p.mesh.path)
    nets = [narrowed(p) for p in nets]
    made = []
    for k, p in enumerate(nets, start=1):
        net = p.net
        _record_choice(net, p.label, p.outcome, p.tried, options)
        net.parameters["patches"] = patches
        net.data["patches"] = {**record, "name": f"p{k}",
                               "own_cuts": [c.tolist() for c in p.patch.cuts]}
        net.inputs["mesh"] = file_input(mesh.path, folder)
        if net.extend and net.data["init"].get("overhang_onto"):
            net.data["surroundings"] = net.inputs["mesh"]
        net.inputs["reference"] = net.data["reference"] = relative_input(p.mesh.path, folder,
                                                                          p.obj)
        net.units = units
        net.parameters["units"] = units
        net.metrics = summarize(net, mesh=p.mesh, surface=(
            ReferenceSurface.from_mesh(surrounded(p.mesh, mesh, FIT_REACH * net.extend))
            if net.data.get("surroundings") else None))
        out = stem.parent / f"{stem.name}.p{k}"
        # a given --strip-width no patch net meets: refused before any is written
        require_met(net.data["init"]["choice"].get("strip_width"), options.get("units", ""),
                    what=f"{out.name}: ")
        made.append((out, net, p))
    written = []
    for out, net, p in made:
        files = {p.mesh.path: p.obj, **with_3dm(net_files(out, net), out, fmt)}
        write_files(files, force=force)
        if say is not None:
            say(f"init: {out.name}: {p.label}, {net.shape[0]} x {net.shape[1]} net "
                f"covering {100 * p.outcome.coverage:.1f} % of its patch, strips "
                f"varying up to {ratio_text(p.width['ratio'])} in width")
        tell(net.data["init"]["choice"].get("strip_width"), options.get("units", ""), say,
             what=f"{out.name}: ")
        written.append(artifact_paths(out)[0])
    return written
