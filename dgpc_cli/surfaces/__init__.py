"""Analytic reference surfaces for ``dgpc init --surface`` (SPEC §5)."""

from dgpc_cli.surfaces.profiles import (
    BUILTIN_PROFILES,
    BuiltinProfile,
    Profile,
    arc_length,
    builtin_profile,
    describe_builtins,
    profile_from_spec,
    read_profile_csv,
    resample,
)
from dgpc_cli.surfaces.revolution import (
    AXIS,
    default_along,
    revolution_mesh,
    revolution_net,
    surface_record,
)

__all__ = [
    "AXIS", "BUILTIN_PROFILES", "BuiltinProfile", "Profile", "arc_length", "builtin_profile",
    "default_along", "describe_builtins", "profile_from_spec", "read_profile_csv", "resample",
    "revolution_mesh", "revolution_net", "surface_record",
]
