"""Discrete Minding bending of a meridian net of revolution (paper §4.2.2, Prop. 4.3).

A meridian net of a surface of revolution with rows of radius r(u) and angular step Δθ is bent
isometrically into the meridian net of another surface of revolution with angular step Δθ/λ:
the v-edges (chords 2 r sin(Δθ/2)) keep their lengths when the radii become
ρ(u) = r(u) sin(Δθ/2) / sin(Δθ/(2λ)), and the u-edges keep their lengths l(u) when the heights
step by x(u) = √(l(u)² − (ρ(u+1) − ρ(u))²). Every edge length is kept exactly, and the result
is again a net of discrete geodesic parallel coordinates: an exact isometric deformation.
"""

from __future__ import annotations

import numpy as np


def circumradius(d, dtheta):
    """Radius of the parallel circle whose chords of angle ``dtheta`` have length ``d``.

    Paper §4.2.2: ``r(u) = d(u) / (2 sin(Δθ/2))``; with N segments per full turn Δθ = 2π/N,
    i.e. ``r = d / (2 sin(π/N))``. Broadcasts over ``d``.
    """
    return np.asarray(d, dtype=float) / (2.0 * np.sin(0.5 * np.asarray(dtheta, dtype=float)))


def height_steps_squared(l, r):  # noqa: E741 - the paper's l(u)
    """``x(u)² = l(u)² − (r(u+1) − r(u))²`` of paper §4.2.2 (Fig. 9 right), shape ``(m−1,)``.

    ``l (m−1,)`` are the meridian segment lengths and ``r (m,)`` the radii of the parallels;
    x(u) is the height step between the parallels u and u+1, real where the result is ≥ 0.
    """
    return np.asarray(l, dtype=float) ** 2 - np.diff(np.asarray(r, dtype=float)) ** 2


def minding_bend(f: np.ndarray, lam: float) -> np.ndarray:
    """The Minding bending with factor ``lam`` of a meridian net ``f (m, n, 3)`` about the z axis.

    ``f`` must be a meridian net of a surface of revolution about the z axis with constant
    angular step (as made by ``revolution_net`` without twist). Raises ValueError where
    x(u) would be imaginary (λ too large for the profile's slope).
    """
    f = np.asarray(f, dtype=float)
    m, n, _ = f.shape
    r = np.hypot(f[:, 0, 0], f[:, 0, 1])
    theta = np.unwrap(np.arctan2(f[0, :, 1], f[0, :, 0]))
    dtheta = (theta[-1] - theta[0]) / (n - 1)
    chord = np.linalg.norm(f[1:, 0] - f[:-1, 0], axis=-1)             # l(u), (m-1,)
    rho = circumradius(2.0 * r * np.sin(dtheta / 2), dtheta / lam)   # same chords d(u)
    x2 = height_steps_squared(chord, rho)
    if np.any(x2 < 0):
        raise ValueError(f"λ = {lam:g} makes the height step imaginary at row "
                         f"{int(np.argmin(x2))}")
    dh = np.sign(f[1:, 0, 2] - f[:-1, 0, 2]) * np.sqrt(x2)
    dh[dh == 0] = np.sqrt(x2[dh == 0])
    h = f[0, 0, 2] + np.concatenate([[0.0], np.cumsum(dh)])
    phi = theta.mean() + (theta - theta.mean()) / lam          # same mid-meridian
    return np.stack([rho[:, None] * np.cos(phi)[None, :], rho[:, None] * np.sin(phi)[None, :],
                     np.broadcast_to(h[:, None], (m, n))], axis=-1)
