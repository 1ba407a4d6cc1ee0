"""``dgpc init``: the stage the command calls (SPEC §5). It makes the net from its source (an
analytic surface: ``stages.init``; a reference mesh: ``stages.init_mesh_net``, split into
patches with ``--patches``: ``stages.init_patch_nets``; a quad net: ``stages.init_quads``),
gives it its unit, reference and metrics, and writes it."""

from __future__ import annotations

from collections.abc import Callable
from contextlib import nullcontext
from pathlib import Path

import numpy as np

from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import held_writes, write_files
from dgpc_cli.io.net import net_files
from dgpc_cli.io.patch_set import is_patch_set, member_files, previous_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import UNIT_NAMES
from dgpc_cli.stages.init import init_revolution
from dgpc_cli.stages.init_mesh_net import Status, mesh_net
from dgpc_cli.stages.init_patch_nets import patch_nets
from dgpc_cli.stages.init_width import default_limit
from dgpc_cli.stages.inspect import summarize
from dgpc_cli.stages.patch_set_run import write_patch_set


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
              written: Callable[[Path], None] = lambda path: None) -> list[Path]:
    """Make and write the nets of ``dgpc init`` (its options checked and their lengths in
    ``units``; ``strip_width``: ``--strip-width``, None when not given: on a mesh the default
    of ``stages.init_width`` where ``init`` chooses the columns); the JSON paths written.
    ``check(stem, force, *extra)`` refuses a patch net's target before any is written;
    ``status`` makes the status line of the geodesic search; ``say``, when given, gets the
    stderr lines that say what was made; ``written(json_path)`` prints each JSON path at the
    commit (nothing is written when it fails). The nets of patches and their set are written
    in one commit."""
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
                        units=units)
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
            said: list[str] = []            # what the patches' nets were: once written
            with held_writes() as held:
                nets = patch_nets(net, mesh, patches, output,
                                  {"method": method, "base": base, "direction": direction,
                                   "angle": angle, "rows": rows, "cols": cols,
                                   "spacing": spacing,
                                   "extend": net.parameters.get("extend", 0.0),
                                   "given_extend": extend,
                                   "largest_component": largest_component,
                                   "strip_width": strip_width,
                                   "strip_width_given": given_width, "units": units},
                                  units=units, fmt=fmt, force=force, check=check,
                                  say=None if say is None else said.append,
                                  switched=switched)
            if nets:
                members = [{"name": f"p{k}", "kind": "net", "json": j, "exit_code": 0,
                            "files": member_files(j, (_patch_mesh(j),), read=held.read)}
                           for k, j in enumerate(nets, start=1)]
                write_patch_set(output, "init", members, force=force, held=held,
                                announce=lambda: [written(j) for j in [*nets, json_path]])
            for line in said:
                say(line)
            if nets:
                return [*nets, json_path]
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
        from dgpc_cli.stages.init_quads import init_from_quads

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
    files.update(with_3dm(net_files(output, net), output, fmt))
    # a patch set written here before: its members go (those it wrote itself)
    write_files(files, force=force,
                replaces=previous_files(json_path) if is_patch_set(json_path) else (),
                announce=lambda: written(json_path))
    if not units_given and say is not None:     # once written: an error is one line alone
        say(assumed_units_line(net.f, units))
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
