"""``dgpc init``: an initial net on an analytic surface, on a reference mesh, or imported from
a quad net (SPEC §5)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.options import check_writable, force_opt, format_opt, output_opt
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths, file_input
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.net import net_files
from dgpc_cli.io.rhino import with_3dm
from dgpc_cli.io.units import DEFAULT_UNITS, UNIT_MM
from dgpc_cli.stages.init import init_revolution
from dgpc_cli.stages.inspect import summarize
from dgpc_cli.stages.net_size import check_net_size
from dgpc_cli.surfaces.profiles import describe_builtins


def parse_direction(text: str | None):
    """``"x,y,z"`` → three floats, not all zero; DgpcError naming --direction otherwise."""
    if text is None:
        return None
    try:
        d = [float(p) for p in text.split(",")]
    except ValueError:
        d = []
    if len(d) != 3 or not all(abs(x) < float("inf") for x in d) or not any(d):
        raise DgpcError(f"{text!r} is not a direction: give three numbers x,y,z, not all zero",
                        source="--direction")
    return d


def _mesh_net(reference, method, direction, rows, cols, spacing, largest_component, extend):
    from dgpc_cli.geodesics.extension import continued
    from dgpc_cli.io.mesh import load_mesh
    from dgpc_cli.stages.init_mesh import init_geodesic, init_project

    if rows is not None and cols is not None:  # refused before the mesh is read
        check_net_size(rows, cols, "--rows/--cols", "use fewer --rows or --cols")
    mesh = load_mesh(reference, pieces="largest" if largest_component else "one")
    domain = continued(mesh, extend)
    if method == "geodesic":
        net = init_geodesic(domain, direction=direction, rows=rows, cols=cols, spacing=spacing)
    else:
        net = init_project(domain, direction=direction, rows=rows, cols=cols, spacing=spacing)
    net.parameters["largest_component"] = largest_component
    if extend > 0:
        net.parameters["extend"] = extend
    return net, mesh


@click.command(short_help="Make an initial net.",
               epilog="Built-in profiles:\n\n\b\n" + describe_builtins())
@click.argument("reference", required=False, type=click.Path(path_type=Path))
@click.option("--surface", type=click.Choice(["revolution"]),
              help="Analytic surface: 'revolution' (profile revolved about the z axis).")
@click.option("--profile", metavar="NAME|FILE",
              help="With --surface: built-in profile name, or a CSV file with header 'r,h'.")
@click.option("--method", type=click.Choice(["geodesic", "project"]),
              help="With REFERENCE (a triangle mesh, OBJ/PLY/STL/OFF): 'geodesic' traces "
                   "geodesics orthogonally from the section of the mesh by the plane through "
                   "its area centroid orthogonal to --direction (default direction: the "
                   "longest principal axis); 'project' projects a planar grid onto the mesh "
                   "along --direction (required). Both keep the largest rectangle of the grid "
                   "that lies on the mesh. A closed mesh works: geodesics are cut at its extent "
                   "along the direction; rays hit the side the direction points to.")
@click.option("--direction", metavar="x,y,z",
              help="Direction for --method: normal of the base plane (geodesic) or of the "
                   "projection (project).")
@click.option("--from-quads", "from_quads", type=click.Path(path_type=Path),
              metavar="FILE.obj",
              help="Import a regular quad net from an OBJ file: the m×n grid is detected, the "
                   "family with the smaller gpc angle defect becomes the geodesics (u-lines). "
                   "REFERENCE, if given, is recorded for `optimize --mode fit`.")
@click.option("--largest-component", is_flag=True,
              help="Keep the largest connected piece of REFERENCE instead of rejecting a mesh "
                   "of several pieces.")
@click.option("--extend", type=FiniteFloat(min=0), default=0.0, show_default=True,
              metavar="FRACTION",
              help="With --method: let the net run beyond the mesh's outer boundary by up to "
                   "FRACTION of its bounding-box diagonal (paper Fig. 14): the net is traced "
                   "on the mesh continued in its boundary's tangent planes, and `optimize` "
                   "fits it to that continuation (reaching twice as far, so the net's rim "
                   "meets no boundary); the net records the mesh itself.")
@click.option("--rows", "rows", type=click.IntRange(min=3),
              help="m: vertices along the geodesics (default with a mesh: square quads).")
@click.option("--cols", "cols", type=click.IntRange(min=3),
              help="n: vertices across the geodesics (default with a mesh: 21).")
@click.option("--spacing", type=FiniteFloat(min=0, min_open=True),
              help="With a mesh, instead of --cols: vertex spacing in model units (also along "
                   "the geodesics unless --rows is given).")
@click.option("--span", "span", type=FiniteFloat(), default=180.0, show_default=True,
              help="--surface: angle covered by the v-lines, degrees (360: a full ring).")
@click.option("--twist", type=FiniteFloat(), default=0.0, show_default=True,
              help="--surface: shear T, radians: the angle of f(u, v) gets T·s(u)/s_total "
                   "added, so the initial u-lines are not meridians (paper Fig. 11).")
@click.option("--reference-out", type=click.Path(dir_okay=False, path_type=Path),
              help="--surface: also write the triangulated surface (OBJ), fine enough to be "
                   "the reference for `optimize --mode fit`.")
@click.option("--units", type=click.Choice(list(UNIT_MM)), default=DEFAULT_UNITS,
              show_default=True,
              help="Length unit of the coordinates (of the profile, mesh or quad net, and of "
                   "the net made): every later stage carries it on; DXF files are in mm.")
@output_opt
@force_opt
@format_opt
def init(reference, surface, profile, method, direction, from_quads, largest_component, extend,
         rows, cols, spacing, span, twist, reference_out, units, output, force, fmt):
    """Make an initial m×n net (u-lines: the geodesics).

    \b
    dgpc init --surface revolution --profile NAME|FILE --rows M --cols N -o STEM
    dgpc init MESH --method geodesic [--direction x,y,z] [--rows M] [--cols N|--spacing S]
              [--extend F] -o STEM
    dgpc init MESH --method project --direction x,y,z [--rows M] [--cols N|--spacing S]
              [--extend F] -o STEM
    dgpc init --from-quads NET.obj [MESH] -o STEM

    With --surface the z axis is the axis of revolution and a CSV profile is resampled by arc
    length. With a mesh, the net records it (path and sha256) as the reference of
    `optimize --mode fit`.
    """
    sources = [s for s in (surface and "--surface", method and "--method",
                           from_quads and "--from-quads") if s]
    if len(sources) != 1:
        raise click.UsageError("give one of --surface, REFERENCE with --method, or --from-quads"
                               + (f" (got {', '.join(sources)})" if sources else ""))
    if surface:
        if reference is not None or spacing is not None or direction is not None:
            raise click.UsageError("--surface takes no REFERENCE, --direction or --spacing")
        if profile is None or rows is None or cols is None:
            raise click.UsageError("--surface needs --profile, --rows and --cols")
    elif method:
        if reference is None:
            raise click.UsageError("--method needs a REFERENCE mesh")
        if cols is not None and spacing is not None:
            raise click.UsageError("give --cols or --spacing, not both")
        if method == "project" and direction is None:
            raise click.UsageError("--method project needs --direction x,y,z")
    if extend > 0 and not method:
        raise click.UsageError("--extend goes with REFERENCE and --method")
    if (profile or reference_out) and not surface:
        raise click.UsageError("--profile and --reference-out go with --surface")
    d = parse_direction(direction)
    check_writable(output, force, *([reference_out] if reference_out else []))
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
        net, mesh = _mesh_net(reference, method, d, rows, cols, spacing, largest_component,
                              extend)
    else:
        from dgpc_cli.stages.init_mesh import init_from_quads

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
    write_files(files, force=force)
    click.echo(str(json_path))
