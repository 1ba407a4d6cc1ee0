"""A nearly developable sample reference: a flat sheet bent along one direction, plus a small
smooth bump (paper §3.2, Fig. 8: a 3D shape "modeled from a piece of planar felt").

The flat rectangle ``[0, length] × [0, width]`` is bent into a general cylinder: its x-lines
follow a planar curve of arc length x whose tangent angle is ``φ(x) = angle·(x/length − ½) +
wobble·sin(2π x/length)`` (a varying curvature), its y-lines stay straight (the rulings). The
bent sheet is developable (K = 0, the Jacobi equation (2) with constant strip width holds
exactly). A Gaussian bump of height ``bump × (bounding-box diagonal)`` along the surface normal
makes it *nearly* developable.
"""

from __future__ import annotations

import numpy as np

#: Samples per unit length of the directrix integration (trapezoid rule, then interpolation).
_FINE = 20_000


def _directrix(length: float, angle: float, wobble: float):
    """``X(x), Z(x), φ(x)`` of the bent x-lines as interpolating functions of the arc length."""
    s = np.linspace(0.0, length, _FINE + 1)
    phi = angle * (s / length - 0.5) + wobble * np.sin(2 * np.pi * s / length)
    ds = np.diff(s)
    X = np.concatenate([[0.0], np.cumsum(0.5 * ds * (np.cos(phi[1:]) + np.cos(phi[:-1])))])
    Z = np.concatenate([[0.0], np.cumsum(0.5 * ds * (np.sin(phi[1:]) + np.sin(phi[:-1])))])
    return (lambda x: np.interp(x, s, X)), (lambda x: np.interp(x, s, Z)), \
        (lambda x: angle * (x / length - 0.5) + wobble * np.sin(2 * np.pi * x / length))


def bent_sheet(length: float = 10.0, width: float = 6.0, *, angle: float = 1.2,
               wobble: float = 0.15, bump: float = 1e-4, resolution: float = 0.05):
    """Triangle mesh ``(vertices (k, 3), faces (t, 3))`` of the bent sheet with its bump.

    ``angle``: total turning of the directrix (radians); ``wobble``: amplitude of the varying
    part of its tangent angle; ``bump``: height of the Gaussian bump (σ = width/5, centred at
    (0.4·length, 0.55·width)) relative to the bounding-box diagonal of the bent sheet (0: exactly
    developable); ``resolution``: target edge length of the grid triangulation. Deterministic.
    """
    nx = max(2, int(np.ceil(length / resolution))) + 1
    ny = max(2, int(np.ceil(width / resolution))) + 1
    x, y = np.meshgrid(np.linspace(0, length, nx), np.linspace(0, width, ny), indexing="ij")
    Xf, Zf, phif = _directrix(length, angle, wobble)
    P = np.stack([Xf(x), y, Zf(x)], axis=-1)
    phi = phif(x)
    normal = np.stack([-np.sin(phi), np.zeros_like(phi), np.cos(phi)], axis=-1)
    diagonal = float(np.linalg.norm(np.ptp(P.reshape(-1, 3), axis=0)))
    sigma = width / 5.0
    h = bump * diagonal * np.exp(-((x - 0.4 * length) ** 2 + (y - 0.55 * width) ** 2)
                                 / (2 * sigma**2))
    P = P + h[..., None] * normal
    vid = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return P.reshape(-1, 3), faces
