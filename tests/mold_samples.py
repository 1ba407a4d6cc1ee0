"""Deterministic sample nets for the extract-mold tests (paper Fig. 1, 16, 17).

Every net here is an *exact* isometric deformation of a meridian net of a surface of revolution:
Minding's bending (Prop. 4.3, :func:`dgpc_cli.surfaces.minding.minding_bend`, which keeps every
edge and diagonal length) followed by a rigid motion, so that the tests know the exact answer.
``test_mold_cli.test_truth_through_an_isometric_optimization`` makes the deformation with
``optimize --mode isometric`` instead.
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.io.net import NetArtifact, write_net
from dgpc_cli.surfaces.minding import minding_bend
from dgpc_cli.surfaces.profiles import Profile
from dgpc_cli.surfaces.revolution import revolution_net


def write_profile_csv(path, r, h):
    """A profile CSV ``r,h`` (the format of ``dgpc init --profile FILE``)."""
    lines = ["r,h"] + [f"{a!r},{b!r}" for a, b in zip(r.tolist(), h.tolist(), strict=True)]
    path.write_text("\n".join(lines) + "\n")
    return path


def wavy_profile(samples: int = 801) -> Profile:
    """Our own profile (not a built-in): r = 2 + 0.5 sin(1.3 h) + 0.15 h, h ∈ [0, 4]
    (h increasing, so h(u) is recovered up to a shift)."""
    h = np.linspace(0.0, 4.0, samples)
    return Profile("wavy", 2.0 + 0.5 * np.sin(1.3 * h) + 0.15 * h, h)


def gehry_profile(samples: int = 1201) -> Profile:
    """A profile with a cylindrical section: r = 3 for h ∈ [0, 2], then a C¹ S-curve down to
    r = 2 at h = 5: r = 2.5 + 0.5 cos(π (h − 2)/3)."""
    h = np.linspace(0.0, 5.0, samples)
    r = np.where(h <= 2.0, 3.0, 2.5 + 0.5 * np.cos(np.pi * (h - 2.0) / 3.0))
    return Profile("gehry", r, h)


def rotation(axis, angle: float) -> np.ndarray:
    """Rotation matrix about ``axis`` by ``angle`` (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def deform(f: np.ndarray, lam: float, axis=(1.0, 0.3, 0.2), angle: float = 0.0,
           shift=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Minding bending with ``lam`` then a rigid motion: an exact isometric deformation."""
    g = minding_bend(f, lam)
    return g @ rotation(axis, angle).T + np.asarray(shift, float)


def write(stem, f: np.ndarray, units: str = "mm"):
    """Write ``f`` as a net artifact in ``units`` at ``stem``; returns the stem."""
    write_net(stem, NetArtifact(f=f, units=units))
    return stem


def sector_net(profile: Profile, m: int, n: int, span_deg: float) -> np.ndarray:
    """The meridian net of ``profile`` over ``span_deg`` (m rows at equal arc length)."""
    return revolution_net(profile, m, n, span_deg=span_deg)


def gehry_nets(m: int = 21, n: int = 13) -> list[np.ndarray]:
    """Four different isometric deformations of one 120° net of :func:`gehry_profile`, placed
    like the four façade patches of paper Fig. 1."""
    f = sector_net(gehry_profile(), m, n, 120.0)
    return [deform(f, 1.0, (0, 0, 1), 0.0, (0, 0, 0)),
            deform(f, 0.7, (0, 0, 1), 2.0, (9, 0, 0)),
            deform(f, 1.25, (1, 0, 0), 0.35, (0, 9, 0)),
            deform(f, 0.85, (0.2, 1, 0), -0.3, (9, 9, 1))]
