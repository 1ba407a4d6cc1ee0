"""Strain of a deformed net f against a reference net f⁰ (paper §6.1 "Measure of isometry").

The paper's 2×2 tensor D lives at the vertices, in the (orthonormal, Lemma 2.5) basis
T^u, T^v of the tangent plane; the amount of distortion is |λ1| + |λ2| of its eigenvalues
(Fig. 13, max 4·10⁻⁵ there).
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.metrics.frames import as_grid, corner_angles

__all__ = ["mean_available", "principal_strains", "strain", "strain_tensor"]


def mean_available(*arrays: np.ndarray) -> np.ndarray:
    """Mean over the finite entries of equally shaped arrays, NaN where none is finite."""
    stack = np.stack(arrays)
    ok = np.isfinite(stack)
    count = ok.sum(axis=0)
    total = np.where(ok, stack, 0.0).sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def strain_tensor(f, f0) -> np.ndarray:
    """Strain tensor D at every vertex of f against f⁰ (paper §6.1), shape ``(m, n, 2, 2)``.

    Basis (T^u, T^v). With ε(l) = (‖l‖ − ‖l⁰‖)/‖l⁰‖ for an edge l and l⁰ its reference:

    * ``D11 = (ε(l1) + ε(l_1̄))/2`` over the u-edges δ_u f, δ_u f_1̄ at the vertex,
    * ``D22 = (ε(l2) + ε(l_2̄))/2`` over the v-edges δ_v f, δ_v f_2̄;
      on the boundary only the edge that exists is used.
    * ``D12 = D21 = tan(γ)/2`` with the shear angle
      ``γ = ¼[(α⁰12 − α12) − (α⁰_1̄2 − α_1̄2) + (α⁰_1̄2̄ − α_1̄2̄) − (α⁰_12̄ − α_12̄)]``,
      averaged over the corners that exist (each signed term alone is γ in a homogeneous
      shear, so boundary vertices average the one or two available terms).

    The off-diagonal entry printed in the paper, tan(α_1̄2̄ − α_1̄2) − tan(α_12̄ − α12), compares
    angles of the deformed net only, so it does not vanish for f = f⁰ (e.g. a rhombic reference
    net) and cannot be a strain against f⁰. We use instead the engineering shear γ (decrease of
    the angle α12 between the u- and v-directions, relative to f⁰), with D12 = tan(γ)/2 the
    tensor shear strain (= γ/2 to first order), cf. [Sadd 2009]. D = 0 for f = f⁰; D = s·I for
    a uniform scaling by 1 + s.
    """
    f = as_grid(f)
    f0 = as_grid(f0, name="reference net")
    if f.shape != f0.shape:
        raise ValueError(f"net and reference net differ in shape: {f.shape[:2]} vs "
                         f"{f0.shape[:2]}")
    m, n, _ = f.shape

    def eps(d, d0):
        length, l0 = np.linalg.norm(d, axis=-1), np.linalg.norm(d0, axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(l0 > 0, (length - l0) / np.where(l0 > 0, l0, 1.0), np.nan)

    eu = eps(f[1:] - f[:-1], f0[1:] - f0[:-1])                  # (m-1, n)
    ev = eps(f[:, 1:] - f[:, :-1], f0[:, 1:] - f0[:, :-1])      # (m, n-1)
    e1, e3 = np.full((m, n), np.nan), np.full((m, n), np.nan)
    e2, e4 = np.full((m, n), np.nan), np.full((m, n), np.nan)
    e1[:-1], e3[1:] = eu, eu
    e2[:, :-1], e4[:, 1:] = ev, ev

    a, a0 = corner_angles(f), corner_angles(f0)
    gamma = mean_available(a0.a12 - a.a12, -(a0.a1b2 - a.a1b2),
                            a0.a1b2b - a.a1b2b, -(a0.a12b - a.a12b))
    D = np.empty((m, n, 2, 2))
    D[..., 0, 0] = mean_available(e1, e3)
    D[..., 1, 1] = mean_available(e2, e4)
    D[..., 0, 1] = D[..., 1, 0] = 0.5 * np.tan(gamma)
    return D


def principal_strains(D: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigen-decomposition of symmetric 2×2 tensors ``D (..., 2, 2)`` in closed form.

    Returns ``(λ1, λ2, θ)``, each ``D.shape[:-2]``: λ1 ≥ λ2 and θ the angle of the λ1
    eigenvector ``cos θ T^u + sin θ T^v`` (the principal distortion direction, §6.1).
    """
    D = np.asarray(D, dtype=float)
    a, b, d = D[..., 0, 0], 0.5 * (D[..., 0, 1] + D[..., 1, 0]), D[..., 1, 1]
    mid = 0.5 * (a + d)
    rad = np.hypot(0.5 * (a - d), b)
    theta = 0.5 * np.arctan2(2.0 * b, a - d)
    return mid + rad, mid - rad, theta


def strain(f, f0) -> tuple[np.ndarray, dict]:
    """Amount of distortion ``|λ1| + |λ2|`` of :func:`strain_tensor` per vertex, ``(m, n)``,
    and its summary ``{"max": float, "mean": float}`` (paper §6.1, Fig. 13)."""
    lam1, lam2, _ = principal_strains(strain_tensor(f, f0))
    amount = np.abs(lam1) + np.abs(lam2)
    finite = amount[np.isfinite(amount)]
    summary = {"max": float(finite.max()) if finite.size else None,
               "mean": float(finite.mean()) if finite.size else None}
    return amount, summary
