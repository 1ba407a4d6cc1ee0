"""Analytic surfaces of revolution: initial nets and reference meshes (SPEC §5, paper Fig. 11).

The surface is the profile (r, h) revolved about the z axis:
``x(s, θ) = (r(s) cos θ, r(s) sin θ, h(s))`` with s the profile's arc length.

Orientation: a net f(u, v) here has f_u along the profile and f_v along increasing θ, so its
quad ``(u,v), (u+1,v), (u+1,v+1), (u,v+1)`` has the normal f_u × f_v ∝ (−h'(s), r'(s)) in the
(r, h) half plane: the left of the profile's direction of travel. It faces away from the axis
where the profile runs downwards and toward the axis where it runs upwards (as the built-ins
do). :func:`revolution_mesh` uses the same orientation, so a net and its reference mesh agree.
"""

from __future__ import annotations

import math

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.surfaces.profiles import BUILTIN_PROFILES, Profile, resample

#: The axis of revolution as (point, direction): the z axis through the origin.
AXIS = (0.0, 0.0, 0.0, 0.0, 0.0, 1.0)

#: Fewest profile samples of a reference mesh (``revolution_mesh``'s ``along`` default).
MIN_ALONG = 200
#: Most profile samples that the ``along`` default picks.
MAX_ALONG = 2000


#: The largest |twist|, radians (159 turns): the angles θ = twist·s/s_total then keep 13 digits.
MAX_TWIST = 1000.0


def _check_span_twist(span_deg: float, twist: float) -> None:
    if not (math.isfinite(span_deg) and 0.0 < span_deg <= 360.0):
        raise DgpcError(f"the span must be in (0, 360] degrees, got {span_deg:g}", "--span")
    if not math.isfinite(twist):
        raise DgpcError(f"the twist must be finite, got {twist}", "--twist")
    if abs(twist) > MAX_TWIST:
        raise DgpcError(f"the twist must be at most {MAX_TWIST:g} radians either way (beyond "
                        f"it the angles lose their precision), got {twist:g}", "--twist")


def revolution_net(profile: Profile, m: int, n: int, *, span_deg: float = 90.0,
                   twist: float = 0.0) -> np.ndarray:
    """An m×n net on the surface of revolution, meridians as u-lines: ``f (m, n, 3)``.

    Row u lies at the u-th of m profile points at equal arc length ``(r_u, h_u, s_u)``; column
    v at the angle ``θ(u, v) = span·(v/(n−1) − ½) + twist·s_u/s_total`` (span in degrees,
    converted; ``twist`` in radians), and ``f[u, v] = (r_u cos θ, r_u sin θ, h_u)``.

    ``twist = 0`` gives meridians (geodesics) as u-lines, symmetric about the x axis; a twist
    shears the parameter grid so that the last row is rotated by ``twist`` relative to the
    first and the u-lines are no longer meridians (paper Fig. 11). ``span_deg = 360`` closes
    the ring, so the first and last v-columns coincide. m, n ≥ 2, 0 < span ≤ 360.
    """
    m, n, span_deg, twist = int(m), int(n), float(span_deg), float(twist)
    if m < 2 or n < 2:
        raise ValueError(f"a net needs at least 2×2 vertices, got {m}×{n}")
    _check_span_twist(span_deg, twist)
    r, h, s = resample(profile, m)
    theta = (math.radians(span_deg) * (np.arange(n) / (n - 1) - 0.5)[None, :]
             + twist * (s / s[-1])[:, None])                                       # (m, n)
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta),
                     np.broadcast_to(h[:, None], theta.shape)], axis=-1)


def default_along(profile: Profile, around: int = 360) -> int:
    """Profile samples for a reference mesh: about square cells at the widest parallel.

    The spacing along the profile matches ``2π·max(r)/around``, clamped to
    [``MIN_ALONG``, ``MAX_ALONG``].
    """
    step = 2.0 * math.pi * float(np.max(profile.r)) / int(around)
    return int(np.clip(math.ceil(profile.length / step) + 1, MIN_ALONG, MAX_ALONG))


def extended(profile: Profile, margin: float) -> Profile:
    """The profile prolonged at both ends along its end tangents by ``margin`` × its length.

    A reference for fitting needs room beyond the net: a net whose end rows sit on the
    reference's boundary cannot move along it. The extension stops short of the axis (r keeps
    at least half its end value).
    """
    if margin <= 0:
        return profile
    r, h = np.asarray(profile.r, float), np.asarray(profile.h, float)
    ext = margin * profile.length
    ends = []
    for i, j in ((0, 1), (-1, -2)):
        t = np.array([r[i] - r[j], h[i] - h[j]])
        t /= np.linalg.norm(t)
        reach = ext if t[0] >= 0 else min(ext, 0.5 * r[i] / -t[0])
        ends.append((r[i] + reach * t[0], h[i] + reach * t[1]))
    return Profile(profile.name, np.concatenate([[ends[0][0]], r, [ends[1][0]]]),
                   np.concatenate([[ends[0][1]], h, [ends[1][1]]]))


def revolution_mesh(profile: Profile, *, around: int = 360,
                    along: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The whole surface of revolution (360°) as a triangle mesh for fitting.

    ``along`` profile points at equal arc length (default :func:`default_along`, ≥ 200) times
    ``around`` angles ``θ_j = 2π j/around − π``: vertex ``u·around + j`` is
    ``revolution_net(profile, along, around + 1, span_deg=360)[u, j]`` (the seam column is
    welded, no duplicate vertices). Each quad ``(u,j), (u+1,j), (u+1,j+1), (u,j+1)`` gives the
    two triangles ``(a, b, c), (a, c, d)``, orientated like the net's quads (see the module
    docstring). The only boundary edges are the two end circles of the profile.

    Returns ``vertices (along·around, 3)`` float64 and ``faces (2·(along−1)·around, 3)`` int64.
    """
    around = int(around)
    along = default_along(profile, around) if along is None else int(along)
    if around < 3 or along < 2:
        raise ValueError(f"a mesh of revolution needs around ≥ 3 and along ≥ 2, "
                         f"got around={around}, along={along}")
    vertices = revolution_net(profile, along, around + 1, span_deg=360.0)[:, :-1].reshape(-1, 3)
    u = np.arange(along - 1, dtype=np.int64)[:, None]
    j = np.arange(around, dtype=np.int64)[None, :]
    a = u * around + j
    b = a + around
    c = (u + 1) * around + (j + 1) % around
    d = u * around + (j + 1) % around
    faces = np.stack([np.stack([a, b, c], axis=-1), np.stack([a, c, d], axis=-1)], axis=2)
    return np.ascontiguousarray(vertices), faces.reshape(-1, 3)


def surface_record(profile: Profile, span_deg: float, twist: float) -> dict:
    """What a net artifact stores in ``data.surface`` (JSON-able) for a net of revolution.

    ``{"type": "revolution", "profile": name, "builtin": bool, "axis": {"point", "direction"},
    "span_deg": float, "twist": float (radians), "profile_length": float}``; the profile is
    named by its built-in name or by the CSV path it was read from.
    """
    span_deg, twist = float(span_deg), float(twist)
    _check_span_twist(span_deg, twist)
    return {
        "type": "revolution",
        "profile": profile.name,
        "builtin": profile.name in BUILTIN_PROFILES,
        "axis": {"point": list(AXIS[:3]), "direction": list(AXIS[3:])},
        "span_deg": span_deg,
        "twist": twist,
        "profile_length": profile.length,
    }


__all__ = ["AXIS", "MAX_ALONG", "MIN_ALONG", "default_along", "revolution_mesh",
           "revolution_net", "surface_record"]
