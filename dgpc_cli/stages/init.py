"""``dgpc init``: the stage the command calls (SPEC §5). It makes the net from its source (an
analytic surface of revolution; a reference mesh, by the layout of nets on meshes in
``dgpc_cli.layout``, split into patches with ``--patches``; a quad net, ``layout.quads``),
gives it its unit, reference and metrics, records how it was chosen, and writes it.

The net on a reference mesh (``--method geodesic|project``): the mesh is loaded, the
candidates are tried (``layout.search`` for ``geodesic``, ``layout.choice`` for ``project`` and
a given base), and the net chosen gets the command's parameters and ``data.init.choice``: the
candidate, its coverage and every candidate tried (``geodesic``: and the search's record).
With ``--patches auto|K`` one net per patch of the reference (the split: ``layout.patches``),
written as ``STEM.p1``, ``STEM.p2``, … each with its patch mesh ``STEM.pK.patch.obj`` as its
reference.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths, file_input, relative_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.mesh import ReferenceMesh, write_mesh_obj
from dgpc_cli.io.net import NetArtifact, net_files
from dgpc_cli.io.patch_set import is_patch_set, member_files, previous_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import DEFAULT_UNITS, UNIT_NAMES, from_mm, mm_per_unit
from dgpc_cli.layout.net_size import check_net_size
from dgpc_cli.layout.width import default_limit
from dgpc_cli.stages.inspect import summarize
from dgpc_cli.stages.patch_set_run import write_patch_set
from dgpc_cli.surfaces.profiles import BUILTIN_PROFILES, Profile, profile_from_spec
from dgpc_cli.surfaces.revolution import (
    extended,
    revolution_mesh,
    revolution_net,
    surface_record,
)

log = logging.getLogger(__name__)


def quick_fitter(f: np.ndarray, surface, on_mesh: bool, iterations: int):
    """``layout.search.NetFit``: ``iterations`` of ``optimize --mode fit`` (its weights, its
    polish of a nearly gpc net; the rim held to the mesh's boundary where the net is traced on
    the mesh itself, ``on_mesh``) of the net ``f`` to ``surface``; the fitted net and the
    iterations run."""
    from dgpc_cli.fitting.modes import SOFT, mode_weights
    from dgpc_cli.fitting.optimize import boundary_vertices, optimize_net
    from dgpc_cli.fitting.polish import polish_weights

    weights = polish_weights(f, mode_weights("fit"))
    rim = (boundary_vertices(f, surface) if on_mesh and weights["boundary"].end > 0
           else None)
    out = optimize_net(f, weights, reference=surface, boundary_ids=rim, soft=SOFT["fit"],
                       max_iter=iterations)
    return out.f, out.iterations

#: The reference mesh of ``--reference-out`` prolongs the profile by this fraction of its
#: length at both ends, so that a fitted net has room to move beyond its initial end rows.
REFERENCE_MARGIN = 0.1


@dataclass
class InitResult:
    """The new net and, optionally, the bytes of its reference mesh OBJ."""

    net: NetArtifact
    reference_obj: bytes | None = None


def init_revolution(profile: str, rows: int, cols: int, *, span_deg: float = 180.0,
                    twist: float = 0.0, reference_out: Path | None = None,
                    around: int = 360, units: str = DEFAULT_UNITS,
                    folder: Path | None = None) -> InitResult:
    """An ``rows × cols`` net on a surface of revolution, meridians as u-lines (Fig. 3, 11).

    ``profile`` is a built-in name or a CSV file with header ``r,h``, its numbers in ``units``
    (the net is computed in mm and stored in ``units``). With ``reference_out`` the
    triangulated surface (``around`` segments per turn, the profile resampled finely and
    prolonged by ``REFERENCE_MARGIN`` at both ends) is returned too, to be written beside the
    net; the net's ``data.reference`` names it.

    Every path the net records (``inputs.profile``, ``data.reference``, the profile file and
    ``reference_out`` among its parameters, ``data.surface.profile``) is POSIX and relative
    to ``folder``, the folder of the net's JSON (default: the working directory), so that the
    artifact does not depend on where it was made.
    """
    folder = Path.cwd() if folder is None else Path(folder)
    check_net_size(rows, cols, "--rows/--cols", "use fewer --rows or --cols")
    prof = profile_from_spec(profile)
    k = mm_per_unit(units, "--units")
    prof_mm = Profile(prof.name, prof.r * k, prof.h * k)
    f = from_mm(revolution_net(prof_mm, rows, cols, span_deg=span_deg, twist=twist), units)
    inputs = {}
    data = {"surface": surface_record(prof, span_deg, twist)}
    if profile not in BUILTIN_PROFILES:
        inputs["profile"] = file_input(profile, folder)
        profile = data["surface"]["profile"] = inputs["profile"]["path"]
    reference_obj = None
    if reference_out is not None:
        vertices, faces = revolution_mesh(extended(prof, REFERENCE_MARGIN), around=around)
        reference_obj = write_mesh_obj(reference_out, vertices, faces)
        data["reference"] = relative_input(reference_out, folder, reference_obj)
    parameters = {"surface": "revolution", "profile": profile, "rows": rows, "cols": cols,
                  "span_deg": span_deg, "twist": twist,
                  "reference_out": data["reference"]["path"] if reference_out else None}
    net = NetArtifact(f=np.asarray(f, dtype=float), units=units, parameters=parameters,
                      inputs=inputs, data=data)
    return InitResult(net=net, reference_obj=reference_obj)


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
    from dgpc_cli.layout.search import EXTEND_BELOW

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
             strip_width_given: bool = False, units: str = "",
             check_lengths: Callable[[float], None] | None = None) -> MeshNet:
    """The net of ``init REFERENCE --method METHOD`` (lengths in the mesh's unit, ``units``;
    ``extend``: the fraction of ``--extend``, None when not given; ``strip_width``: the
    largest strip width, ``layout.width``, None for none). ``status`` makes the status
    line the geodesic search updates; ``say``, when given, gets the lines that say which net
    was chosen and, where there is something to say, how wide its strips are;
    ``check_lengths(diagonal)``, when given, judges the lengths given against the mesh's
    bounding-box diagonal (in ``units``) once it is read, before any net is made."""
    from dgpc_cli.geodesics.extension import continued
    from dgpc_cli.io.mesh import load_mesh
    from dgpc_cli.layout.choice import choose
    from dgpc_cli.layout.search import search
    from dgpc_cli.layout.width import tell, widened_choice

    if rows is not None and cols is not None:  # refused before the mesh is read
        check_net_size(rows, cols, "--rows/--cols", "use fewer --rows or --cols")
    mesh = load_mesh(reference, pieces="largest" if largest_component else "one")
    if check_lengths is not None:
        check_lengths(mesh.bbox_diagonal)
    found = None
    widen_cols = cols is None and spacing is None
    if method == "geodesic":
        with status() as progress:
            found = search(mesh, fit=quick_fitter, base=base, direction=direction,
                           angle=angle, rows=rows, cols=cols, spacing=spacing,
                           extend=extend, progress=progress,
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
    from dgpc_cli.layout.width import tell

    tried = [t.record for t in found.trials]
    net = _recorded(found.grid, found.outcome, tried, found.extend, found.width, options,
                    "geodesic", found.record)
    if say is not None:
        say(_summary("geodesic", net, mesh, found.grid.label, found.outcome, tried, found))
    if tell_width:
        tell(found.width, units, say_width or say, options=found.record["options"])
    return MeshNet(net=net, mesh=mesh, poor=_poor(found))


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
    (``layout.search``: base curves, overhang, size, ranked after a quick fit), as for a
    single net, its overhang running onto the whole mesh around the patch
    (``geodesics.extension.surrounded``; the net's ``data.surroundings``, the whole mesh, tells
    ``optimize`` to fit it there); the search's record rides on the net
    (``data.init.search``, and its largest strip width ``data.init.strip_width``) until the
    choice is recorded. ``(grid, outcome, tried, narrowed)``: ``narrowed()`` makes the net
    within the largest strip width, once the patches are decided by the nets as chosen
    (None: nothing to do)."""
    from dgpc_cli.layout.grids import DEFAULT_COLS
    from dgpc_cli.layout.search import search

    cols = options["cols"]
    widen_cols = cols is None and options["spacing"] is None
    if widen_cols:
        # a patch is smaller than the whole: its size not searched, only made finer where its
        # strips are wider than the largest strip width
        cols = DEFAULT_COLS
    found = search(m, fit=quick_fitter, base=options["base"], direction=options["direction"],
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
    from dgpc_cli.layout.choice import choose
    from dgpc_cli.layout.patches import narrowed, plan, ratio_text
    from dgpc_cli.layout.width import require_met, tell, widened_choice
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


def assumed_units_line(f, units: str) -> str:
    """The stderr line of ``init`` without ``--units``: the unit assumed and the net's size in
    it (its bounding box), so that a profile or mesh drawn in metres is caught at once."""
    size = np.ptp(np.asarray(f, dtype=float).reshape(-1, 3), axis=0)
    dims = " × ".join(f"{x:.3g}" for x in size)
    other = "m" if units != "m" else "mm"
    return (f"init: no --units given: the net is in {units}, {dims} {units} (x × y × z); "
            f"a model drawn in {UNIT_NAMES.get(other, other)} needs --units {other}")


def init_nets(output: Path, *, units: str, units_given: bool, fmt: str, force: bool,
              check: Callable[..., None], surface: str | None = None,
              profile: str | None = None,
              reference: Path | None = None, method: str | None = None,
              from_quads: Path | None = None, base: str | None = None, direction=None,
              angle: float | None = None, rows: int | None = None, cols: int | None = None,
              spacing: float | None = None, span: float = 180.0, twist: float = 0.0,
              reference_out: Path | None = None, largest_component: bool = False,
              extend: float | None = None, patches=None, status: Status = nullcontext,
              say: Callable[[str], None] | None = None,
              strip_width: float | None = None,
              check_lengths: Callable[[float], None] | None = None) -> list[Path]:
    """Make and write the nets of ``dgpc init`` (its options checked and their lengths in
    ``units``; ``strip_width``: ``--strip-width``, None when not given: on a mesh the default
    of ``layout.width`` where ``init`` chooses the columns); the JSON paths written.
    ``check(stem, force, *extra)`` refuses a patch net's target before any is written;
    ``status`` makes the status line of the geodesic search; ``say``, when given, gets the
    stderr lines that say what was made; ``check_lengths(diagonal)`` judges the lengths given
    against a mesh's size (:func:`mesh_net`)."""
    json_path, _ = artifact_paths(output)
    folder = json_path.resolve().parent
    files = {}
    mesh = None
    if surface:
        result = init_revolution(profile, rows, cols, span_deg=span, twist=twist,
                                 reference_out=reference_out, units=units, folder=folder)
        net = result.net
        if result.reference_obj is not None:
            files[reference_out] = result.reference_obj
    elif method:
        given_width = strip_width is not None
        if not given_width and cols is None and spacing is None:
            strip_width = default_limit(units, units_given)
        made = mesh_net(reference, method, base=base, direction=direction, angle=angle,
                        rows=rows, cols=cols, spacing=spacing,
                        largest_component=largest_component, extend=extend, status=status,
                        say=say, strip_width=strip_width, strip_width_given=given_width,
                        units=units, check_lengths=check_lengths)
        if given_width:
            made.net.parameters["strip_width"] = strip_width
        net, mesh = made.net, made.mesh
        switched = patches is None and made.poor is not None and _search_chooses(
            method, base, direction, angle, extend, rows, cols, spacing)
        if switched:
            patches = "auto"
            if say is not None:
                say(f"init: {made.poor}: trying --patches auto (one net each where one net's "
                    "strips vary in width more than 3x; --patches 1 keeps one net)")
        if patches is not None:
            written = patch_nets(net, mesh, patches, output,
                                 {"method": method, "base": base, "direction": direction,
                                  "angle": angle, "rows": rows, "cols": cols,
                                  "spacing": spacing,
                                  "extend": net.parameters.get("extend", 0.0),
                                  "given_extend": extend,
                                  "largest_component": largest_component,
                                  "strip_width": strip_width,
                                  "strip_width_given": given_width, "units": units},
                                 units=units, fmt=fmt, force=force, check=check, say=say,
                                 switched=switched)
            if written:
                return [*written, write_patch_set(
                    output, "init", [{"name": f"p{k}", "kind": "net", "json": j,
                                      "exit_code": 0,
                                      "files": member_files(j, (_patch_mesh(j),))}
                                     for k, j in enumerate(written, start=1)], force=force)]
        elif made.poor and say is not None:
            say(f"init: {made.poor}; --patches auto cuts the mesh into patches, one net each, "
                "where one net's strips vary in width more than 3x")
        if made.narrowed is not None:
            # one net kept: now made within the largest strip width, with what the patches
            # recorded of it
            kept = made.narrowed().net
            if "patches" in net.data:
                kept.parameters["patches"] = net.parameters["patches"]
                kept.data["patches"] = net.data["patches"]
            if given_width:
                kept.parameters["strip_width"] = strip_width
            net = kept
    else:
        from dgpc_cli.layout.quads import init_from_quads

        net = init_from_quads(from_quads)
        net.inputs["quads"] = file_input(from_quads, folder)
        if reference is not None:
            from dgpc_cli.io.mesh import load_mesh

            mesh = load_mesh(reference, pieces="largest" if largest_component else "one")
    if mesh is not None:
        net.inputs["reference"] = net.data["reference"] = file_input(mesh.path, folder)
    net.units = units
    net.parameters["units"] = units
    net.metrics = summarize(net, mesh=mesh)
    if not units_given and say is not None:
        say(assumed_units_line(net.f, units))
    files.update(with_3dm(net_files(output, net), output, fmt))
    # a patch set written here before: its members go (as it lists them)
    write_files(files, force=force,
                replaces=previous_files(json_path) if is_patch_set(json_path) else ())
    return [json_path]


def _search_chooses(method: str, base, direction, angle, extend, rows, cols, spacing) -> bool:
    """Whether ``init`` chose the net itself (``--method geodesic`` without ``--base``,
    ``--direction``, ``--angle``, ``--extend``, ``--rows``, ``--cols`` or ``--edge-length``), so
    that it may also choose patches where one net is poor: explicit options win."""
    return (method == "geodesic" and base in (None, "auto")
            and all(x is None for x in (direction, angle, extend, rows, cols, spacing)))


def _patch_mesh(json_path: Path) -> Path:
    """The patch mesh ``STEM.pK.patch.obj`` written beside the patch net ``STEM.pK.json``."""
    return json_path.with_name(json_path.name[:-len(".json")] + ".patch.obj")
