"""``dgpc init``: a sensible initial net (SPEC §5). Here: analytic surfaces of revolution."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.io.artifact import file_input, relative_input
from dgpc_cli.io.mesh import write_mesh_obj
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.io.units import DEFAULT_UNITS, from_mm, mm_per_unit
from dgpc_cli.stages.net_size import check_net_size
from dgpc_cli.surfaces.profiles import BUILTIN_PROFILES, Profile, profile_from_spec
from dgpc_cli.surfaces.revolution import (
    extended,
    revolution_mesh,
    revolution_net,
    surface_record,
)

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
