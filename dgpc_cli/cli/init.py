"""``dgpc init``: an initial net on an analytic surface, on a reference mesh, or imported from
a quad net (SPEC §5)."""

from __future__ import annotations

from pathlib import Path

import click

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.length import LengthParam, length_help
from dgpc_cli.cli.options import (
    check_writable,
    force_opt,
    format_opt,
    from_old_name,
    old_name,
    output_opt,
    show_progress,
)
from dgpc_cli.cli.patch_count import PatchCount
from dgpc_cli.cli.progress import StatusLine
from dgpc_cli.io.units import DEFAULT_UNITS, UNIT_MM, mm_per_unit
from dgpc_cli.stages.init import init_nets
from dgpc_cli.surfaces.profiles import describe_builtins
from dgpc_cli.surfaces.revolution import MAX_TWIST


def parse_direction(text: str | None):
    """``"x,y,z"`` → three floats, not all zero; a usage error (exit 2) naming --direction
    otherwise."""
    if text is None:
        return None
    try:
        d = [float(p) for p in text.split(",")]
    except ValueError:
        d = []
    if len(d) != 3 or not all(abs(x) < float("inf") for x in d) or not any(d):
        raise click.BadParameter(f"{text!r} is not a direction: give three numbers x,y,z, "
                                 "not all zero", param_hint="'--direction'")
    return d


@click.command(short_help="Make an initial net.",
               epilog="Built-in profiles (their numbers in the unit of --units: a radius 5 "
                      "is 5 mm by default, 5 m with --units m):\n\n\b\n" + describe_builtins())
@click.argument("reference", required=False, type=click.Path(path_type=Path))
@click.option("--surface", type=click.Choice(["revolution"]),
              help="Analytic surface: 'revolution' (profile revolved about the z axis).")
@click.option("--profile", metavar="NAME|FILE",
              help="With --surface: built-in profile name (below), or a CSV file with header "
                   "'r,h', its numbers in the unit of --units.")
@click.option("--method", type=click.Choice(["geodesic", "project"]),
              help="With REFERENCE (a triangle mesh, OBJ/PLY/STL/OFF; default 'geodesic'): "
                   "'geodesic' traces "
                   "geodesics orthogonally from a base curve (--base); 'project' projects a "
                   "planar grid onto the mesh along --direction (default: the mesh's overall "
                   "normal). Both keep the largest rectangle of the grid that lies on the "
                   "mesh, and never a folded or collapsed one. Without --base, --direction or "
                   "--angle, init tries a sweep of sections, the boundary curves and the "
                   "sections across the longest extents (geodesic: and, without --extend and "
                   "--cols, overhangs and sizes), ranks them after a quick fit and keeps the "
                   "net that covers most of the mesh (stderr and data.init.choice say which, "
                   "and why). A closed mesh works: geodesics are cut at its "
                   "extent along the direction; rays hit the side the direction points to.")
@click.option("--base", metavar="auto|section|boundary|bK",
              help="--method geodesic: the base curve. 'section': the section by the plane "
                   "through the area centroid orthogonal to --direction (default: the longest "
                   "principal axis) turned by --angle; 'boundary': the boundary curve (the "
                   "boundary loops cut at their corners) that covers most; 'b1', 'b2', ...: "
                   "that boundary curve, longest first (-v lists them); 'auto' (default): "
                   "sections and boundary curves, the best.")
@click.option("--direction", metavar="x,y,z",
              help="Direction for --method: normal of the base plane (geodesic) or of the "
                   "projection (project).")
@click.option("--angle", type=FiniteFloat(min=-360, max=360), metavar="DEG",
              help="In-plane angle, degrees: geodesic: the base plane's normal turned about "
                   "the mesh's normal axis; project: the grid turned about the direction.")
@click.option("--from-quads", "from_quads", type=click.Path(path_type=Path),
              metavar="FILE.obj",
              help="Import a regular quad net from an OBJ file: the m×n grid is detected, the "
                   "family with the smaller gpc angle defect becomes the geodesics (u-lines). "
                   "REFERENCE, if given, is recorded for `optimize --mode fit`.")
@click.option("--largest-component", is_flag=True,
              help="Keep the largest connected piece of REFERENCE instead of rejecting a mesh "
                   "of several pieces.")
@click.option("--extend", type=FiniteFloat(min=0, max=1), default=None,
              metavar="FRACTION",
              help="With --method: let the net run beyond the mesh's outer boundary by up to "
                   "FRACTION of its bounding-box diagonal (a ratio, no unit; paper Fig. 14): "
                   "the net is traced "
                   "on the mesh continued in its boundary's tangent planes, and `optimize` "
                   "fits it to that continuation (reaching twice as far, so the net's rim "
                   "meets no boundary); the net records the mesh itself. Not given: 0, or "
                   "with --method geodesic searched when the net would cover less than 97 % "
                   "of the mesh.")
@click.option("--patches", type=PatchCount(), metavar="auto|K",
              help="With --method: split the mesh into K patches along the necks and valleys "
                   "between its lobes and make one net on each (STEM.p1, STEM.p2, ..., each "
                   "with its patch STEM.pK.patch.obj as its reference, so that `optimize "
                   "--mode fit` and `planarize-strips --trim` keep to the patch), and STEM the "
                   "patch set listing them, which the later stages take as they take one net; "
                   "'auto': only where the single net's strips vary in width more than 3x along "
                   "them (else one net, STEM). stdout lists the nets and the set; data.patches "
                   "says why. Not given: 'auto' where init chose the net itself (no --base, "
                   "--direction, --angle, --extend, --rows, --cols, --edge-length) and it covers "
                   "less than 97 % after a quick fit or folds; '1' keeps one net.")
@click.option("--rows", "rows", type=click.IntRange(min=3),
              help="m: vertices along the geodesics (required with --surface; default with a "
                   "mesh: square quads).")
@click.option("--cols", "cols", type=click.IntRange(min=3),
              help="n: vertices across the geodesics (required with --surface; default with a "
                   "mesh: 21).")
@click.option("--edge-length", "spacing", type=LengthParam(min=0, min_open=True),
              metavar="LENGTH", callback=from_old_name("--edge-length"),
              help=length_help("With a mesh, instead of --cols: the vertex spacing, the length "
                               "of the net's edges across the geodesics (also along them "
                               "unless --rows is given), > 0.",
                               where="in the model's unit (--units)",
                               plausible="up to half the mesh's bounding-box diagonal"))
@old_name("--spacing", "--edge-length", type=LengthParam(min=0, min_open=True))
@click.option("--strip-width", "strip_width", type=LengthParam(min=0, min_open=True),
              metavar="LENGTH",
              help=length_help("With a mesh: the largest strip width, > 0: no strip of the net "
                               "is wider anywhere along it (its v-edges on the mesh). Where "
                               "init chooses the columns (no --cols or --edge-length) a net "
                               "too wide is made again with more columns (stderr and "
                               "data.init.choice.strip_width say so); given --cols or "
                               "--edge-length win, and init only warns. Default with --units: "
                               "2.4m, the width of a 2500 mm sheet (nest --sheet 6100x2500) "
                               "less its margins and some room for a board that curves; "
                               "without --units, none (the mesh's size is not known); a width "
                               "no net of at most 101 columns meets is refused.",
                               where="in the model's unit (--units)",
                               plausible="from a thousandth of the mesh's bounding-box "
                                         "diagonal to the diagonal"))
@click.option("--span", "span", type=FiniteFloat(min=0, min_open=True, max=360), default=180.0,
              show_default=True,
              help="--surface: angle covered by the v-lines, degrees (360: a full ring).")
@click.option("--twist", type=FiniteFloat(min=-MAX_TWIST, max=MAX_TWIST), default=0.0,
              show_default=True,
              help="--surface: shear T, radians: the angle of f(u, v) gets T·s(u)/s_total "
                   "added, so the initial u-lines are not meridians (paper Fig. 11).")
@click.option("--reference-out", type=click.Path(dir_okay=False, path_type=Path),
              help="--surface: also write the triangulated surface (OBJ), fine enough to be "
                   "the reference for `optimize --mode fit`.")
@click.option("--units", type=click.Choice(list(UNIT_MM)), default=None,
              help="Length unit of the coordinates (of the profile, mesh or quad net, and of "
                   "the net made): every later stage carries it on; DXF files are in mm. "
                   f"[default: {DEFAULT_UNITS}, and stderr says so with the net's size: a "
                   "built-in profile of radius 5 is then 5 mm]")
@output_opt
@force_opt
@format_opt
@click.pass_context
def init(ctx, reference, surface, profile, method, base, direction, angle, from_quads,
         largest_component, extend, patches, rows, cols, spacing, strip_width, span, twist,
         reference_out, units, output, force, fmt):
    """Make an initial m×n net (u-lines: the geodesics).

    \b
    dgpc init --surface revolution --profile NAME|FILE --rows M --cols N -o STEM
    dgpc init MESH [--method geodesic] [--base auto|section|boundary|bK] [--direction x,y,z]
              [--angle DEG] [--rows M] [--cols N|--edge-length L] [--strip-width W]
              [--extend F] -o STEM
    dgpc init MESH --method project [--direction x,y,z] [--angle DEG] [--rows M]
              [--cols N|--edge-length L] [--strip-width W] [--extend F] -o STEM
    dgpc init MESH --method geodesic|project --patches auto|K [...] -o STEM
    dgpc init --from-quads NET.obj [MESH] -o STEM

    With --surface the z axis is the axis of revolution and a CSV profile is resampled by arc
    length. With a mesh, the net records it (path and sha256) as the reference of
    `optimize --mode fit`.
    """
    if reference is not None and not (surface or method or from_quads):
        method = "geodesic"                 # a mesh alone: the default method
    sources = [s for s in (surface and "--surface", method and "--method",
                           from_quads and "--from-quads") if s]
    if len(sources) != 1:
        raise click.UsageError("give one of --surface, REFERENCE with --method, or --from-quads"
                               + (f" (got {', '.join(sources)})" if sources else ""))
    if surface:
        if reference is not None or spacing is not None or direction is not None:
            raise click.UsageError("--surface takes no REFERENCE, --direction or --edge-length")
        if profile is None or rows is None or cols is None:
            raise click.UsageError("--surface needs --profile, --rows and --cols")
    elif method:
        if reference is None:
            raise click.UsageError("--method needs a REFERENCE mesh")
        if cols is not None and spacing is not None:
            raise click.UsageError("give --cols or --edge-length, not both")
        if method == "project" and base is not None:
            raise click.UsageError("--base goes with --method geodesic")
        if base not in (None, "auto", "section") and (direction is not None or angle is not None):
            raise click.UsageError(f"--base {base} takes no --direction or --angle")
    if strip_width is not None and not method:
        raise click.UsageError("--strip-width goes with REFERENCE and --method")
    if patches is not None and not method:
        raise click.UsageError("--patches goes with REFERENCE and --method")
    if patches is not None and base not in (None, "auto", "section", "boundary"):
        raise click.UsageError(f"--base {base} names a boundary curve of the whole mesh; with "
                               "--patches give auto, section or boundary")
    if extend is not None and extend > 0 and not method:
        raise click.UsageError("--extend goes with REFERENCE and --method")
    if (base or angle is not None) and not method:
        raise click.UsageError("--base and --angle go with REFERENCE and --method")
    if (profile or reference_out) and not surface:
        raise click.UsageError("--profile and --reference-out go with --surface")
    d = parse_direction(direction)
    given_units = units
    units = units or DEFAULT_UNITS
    # the one rule of every length (dgpc_cli.io.length): its limit now, in the net's unit, and
    # a plain number's plausible span once the mesh's size is known
    given = {"--edge-length": spacing, "--strip-width": strip_width}
    if spacing is not None:
        spacing = spacing.check("--edge-length", units) / mm_per_unit(units)
    if strip_width is not None:
        strip_width = strip_width.check("--strip-width", units) / mm_per_unit(units)

    def check_lengths(diagonal: float) -> None:
        from dgpc_cli.layout.width import plausible_spans

        spans = plausible_spans(diagonal, units)
        for option, length in given.items():
            if length is not None:
                length.check(option, units, spans[option], "the net's")

    check_writable(output, force, *([reference_out] if reference_out else []))
    say = (lambda text: click.echo(text, err=True)) if show_progress(ctx) else None
    written = init_nets(output, units=units, units_given=given_units is not None, fmt=fmt,
                        force=force, surface=surface, profile=profile, reference=reference,
                        method=method, from_quads=from_quads, base=base, direction=d,
                        angle=angle, rows=rows, cols=cols, spacing=spacing, span=span,
                        twist=twist, reference_out=reference_out,
                        largest_component=largest_component, extend=extend, patches=patches,
                        strip_width=strip_width, check_lengths=check_lengths,
                        check=check_writable, status=lambda: StatusLine(ctx, "init"), say=say)
    for path in written:
        click.echo(str(path))
