"""The surface of revolution a net is isometric to (paper §4.2, §4.2.2, Prop. 4.3).

A net f (m, n, 3) (u along the geodesics) is discrete isometric to a surface of revolution when it
is in discrete geodesic parallel coordinates and the ratio of v-edge lengths of any two rows does
not depend on v, equation (5); equal v-edges per row (§4.2.1, (7)) is the special case. Then its
strip widths factor as ``w_j(u) = c_j d(u)`` with

    d(u) = 1/(n−1) Σ_j ‖δ_v f(u, j)‖                      (mean v-edge of row u, §4.2.2)
    l(u) = 1/n Σ_v ‖δ_u f(u, v)‖                          (mean meridian segment, §4.2.2)

and ``c_j = 1`` for equal v-edges. With N segments per full turn the surface of revolution has

    r(u) = d(u) / (2 sin(π/N)),   x(u) = √(l(u)² − (r(u+1) − r(u))²),   h(u) = Σ_{i<u} x(i),

and column j of the net covers the angle θ_j = 2 arcsin(c_j sin(π/N)) of it, so that every
v-edge keeps its length (θ_j = 2π/N when c_j = 1). N = n−1 is one full turn (the paper's
choice); any other N is Minding's bending (Prop. 4.3) of that surface with λ = N/(n−1): radii
about λ times larger, angles 1/λ times smaller. x(u) is real iff sin(π/N) ≥ |Δd(u)| / (2 l(u))
for every u, so too large a λ is lowered to the largest admissible one.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.metrics.frames import edge_lengths
from dgpc_cli.metrics.residuals import ratio_spread, spread
from dgpc_cli.surfaces.minding import circumradius, height_steps_squared

log = logging.getLogger(__name__)

#: Relative size (of l(u)²) of a negative x(u)² that counts as rounding and is taken as 0.
X2_ROUNDING = 1e-12
#: Rows listed in an error message about equation (5).
WORST_ROWS = 3


@dataclass(frozen=True)
class NetWidths:
    """The intrinsic data of one net isometric to a surface of revolution.

    ``d (m,)`` mean v-edge per row, ``l (m−1,)`` mean u-edge per row step, ``w (m, n−1)`` the
    strip widths ‖δ_v f(u, j)‖, ``residual (m−1,)`` the relative spread of (5) per row pair.
    """

    d: np.ndarray
    l: np.ndarray  # noqa: E741 - the paper's name
    w: np.ndarray
    residual: np.ndarray


def net_widths(f: np.ndarray) -> NetWidths:
    """d(u), l(u) of §4.2.2 and the residual of (5) of a net ``f (m, n, 3)``."""
    lu, lv = edge_lengths(f)
    return NetWidths(d=lv.mean(axis=1), l=lu.mean(axis=1), w=lv, residual=ratio_spread(f))


def check_revolution(widths: NetWidths, tol: float, source: str) -> None:
    """DgpcError naming ``source`` and the worst row pairs when (5) fails beyond ``tol``.

    (5) is checked for consecutive rows (which implies it for all pairs): per row pair u, u+1
    the relative spread over v of ‖δ_v f(u, v)‖ / ‖δ_v f(u+1, v)‖.
    """
    res = np.where(np.isfinite(widths.residual), widths.residual, np.inf)
    bad = np.flatnonzero(res > tol)
    if bad.size == 0:
        return
    worst = bad[np.argsort(-res[bad], kind="stable")][:WORST_ROWS]
    rows = ", ".join(f"rows {u}-{u + 1} ({res[u]:.2e})" for u in worst)
    raise DgpcError(f"not isometric to a surface of revolution: the ratio of v-edge lengths "
                    f"(equation (5)) varies along {bad.size} of {res.size} row pairs beyond "
                    f"--revolution-tol {tol:g}; worst: {rows}", source=source)


def check_same_surface(ref: NetWidths, other: NetWidths, tol: float, source: str,
                       ref_source: str) -> None:
    """DgpcError naming ``source`` when its net is not isometric to the same surface of
    revolution as ``ref``: same rows, proportional d(u) and equal l(u), within ``tol``."""
    if other.d.size != ref.d.size:
        raise DgpcError(f"has {other.d.size} rows (along the geodesics), {ref_source} has "
                        f"{ref.d.size}: nets on one mold must span the same rows", source=source)
    q = other.d / ref.d
    q_spread = float(spread(q, axis=0))
    if not q_spread <= tol:
        u = int(np.argmax(np.abs(q / q.mean() - 1.0)))
        raise DgpcError(f"not isometric to the same surface of revolution as {ref_source}: "
                        f"its strip widths are not proportional to those of {ref_source} "
                        f"(the ratio varies by {q_spread:.2e} relative over the rows, worst at "
                        f"row {u}; --revolution-tol {tol:g})", source=source)
    dl = np.abs(other.l - ref.l) / ref.l
    if not float(dl.max()) <= tol:
        u = int(np.argmax(dl))
        raise DgpcError(f"not isometric to the same surface of revolution as {ref_source}: "
                        f"its meridian edges differ by up to {float(dl.max()):.2e} relative "
                        f"(rows {u}-{u + 1}; --revolution-tol {tol:g})", source=source)


@dataclass(frozen=True)
class Meridian:
    """The discrete surface of revolution (§4.2.2): N segments per turn, λ = N/(n−1).

    ``r (m,)``, ``h (m,)`` the meridian polyline (h(0) = 0), ``x (m−1,)`` its height steps,
    ``d (m,)``, ``l (m−1,)`` the data it was built from; ``lowered`` tells whether λ was
    lowered to keep x(u) real, ``requested`` the N asked for.
    """

    r: np.ndarray
    h: np.ndarray
    x: np.ndarray
    d: np.ndarray
    l: np.ndarray  # noqa: E741 - the paper's name
    segments: float
    lam: float
    requested: float
    lowered: bool

    @property
    def angle_step(self) -> float:
        """2π/N, radians."""
        return 2.0 * math.pi / self.segments

    def column_angles(self, c: np.ndarray) -> np.ndarray:
        """θ_j = 2 arcsin(c_j sin(π/N)) of columns with widths ``c_j d(u)``, radians."""
        return 2.0 * np.arcsin(np.asarray(c, dtype=float) * math.sin(math.pi / self.segments))

    @property
    def length(self) -> float:
        """Length of the meridian polyline (= Σ l(u))."""
        return float(self.l.sum())


def admissible_sine(d: np.ndarray, l: np.ndarray) -> tuple[float, int]:  # noqa: E741 - the paper's l(u)
    """``(s_min, u)``: x(u) of §4.2.2 is real for every u iff sin(π/N) ≥ s_min = max_u
    |d(u+1) − d(u)| / (2 l(u)); u is the row where the maximum is reached."""
    with np.errstate(divide="ignore", invalid="ignore"):      # a collapsed row: l(u) = 0
        ratio = np.abs(np.diff(d)) / (2.0 * l)
    u = int(np.argmax(ratio))
    return float(ratio[u]), u


def meridian(d: np.ndarray, l: np.ndarray, n0: int, *, segments: float | None = None,  # noqa: E741
             lam: float | None = None, c_max: float = 1.0) -> Meridian:
    """The meridian of the surface of revolution with data ``d (m,)``, ``l (m−1,)``.

    N = ``segments``, else ``lam·n0``, else ``n0`` (= n−1, one full turn). When x(u) would be
    imaginary for some u, N (and λ = N/n0) is lowered to the largest value that makes every
    x(u) real, ``π / arcsin(s_min)`` (see :func:`admissible_sine`), and a warning says so.
    ``c_max`` is the widest column factor c_j: its angle needs c_max sin(π/N) ≤ 1.
    """
    requested = float(segments) if segments is not None else \
        float(lam) * n0 if lam is not None else float(n0)
    source = "--segments" if segments is not None else "--lambda" if lam is not None else None
    if not requested >= 2.0:
        raise DgpcError(f"gives N = {requested:g} segments per turn; N must be at least 2 "
                        "(λ ≥ 2/(n−1))", source=source or "--segments")
    s_min, u_worst = admissible_sine(d, l)
    if s_min > 1.0:
        raise DgpcError(f"no surface of revolution fits: the strip width changes faster than "
                        f"twice the meridian step at rows {u_worst}-{u_worst + 1}",
                        source=source)
    N, lowered = requested, False
    if math.sin(math.pi / requested) < s_min:
        N, lowered = math.pi / math.asin(s_min), True
        log.warning("x(u) would be imaginary with λ = %.6g (N = %.6g segments per turn) at rows "
                    "%d-%d; lowered λ to %.6g (N = %.6g), the largest value that keeps every "
                    "x(u) real", requested / n0, requested, u_worst, u_worst + 1, N / n0, N)
    if c_max * math.sin(math.pi / N) > 1.0:
        raise DgpcError(f"N = {N:g} segments per turn is too few for the widest column "
                        f"(width factor {c_max:.4g}); ask for more segments", source=source)
    r = circumradius(d, 2.0 * math.pi / N)
    x2 = height_steps_squared(l, r)
    if np.any(x2 < -X2_ROUNDING * l**2):   # cannot happen after lowering; a guard
        u = int(np.argmin(x2 / l**2))
        raise DgpcError(f"x(u) is imaginary at rows {u}-{u + 1}", source=source)
    x = np.sqrt(np.maximum(x2, 0.0))
    h = np.concatenate([[0.0], np.cumsum(x)])
    return Meridian(r=r, h=h, x=x, d=np.asarray(d, float), l=np.asarray(l, float),
                    segments=N, lam=N / n0, requested=requested, lowered=lowered)


def row_turning(f: np.ndarray) -> np.ndarray:
    """The angle ``Φ(u) (m,)`` (radians) through which each row (v-line) of a net ``f (m, n, 3)``
    turns, n ≥ 3: the sum of the angles between its consecutive v-edges, scaled by
    (n−1)/(n−2) to the arc's central angle. On a surface of revolution a row is a parallel
    circle and Φ(u) = (n−1)·θ exactly, the angle the net spans; the net bent isometrically
    keeps it roughly."""
    e = np.diff(np.asarray(f, dtype=float), axis=1)
    a, b = e[:, :-1], e[:, 1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        cos = np.einsum("ijk,ijk->ij", a, b) / (np.linalg.norm(a, axis=-1)
                                                * np.linalg.norm(b, axis=-1))
    n = f.shape[1]
    return np.arccos(np.clip(cos, -1.0, 1.0)).sum(axis=1) * (n - 1) / (n - 2)


#: The least turn (radians) of the rows for which :func:`design_lambda` measures a λ.
MIN_TURNING = 1e-6


def design_lambda(nets: list[np.ndarray]) -> tuple[float, float] | None:
    """``(λ, Φ)``: Minding's λ (relative to the full turn, Prop. 4.3) of the surface of
    revolution the nets are drawn on, λ = 2π/Φ with Φ the median of :func:`row_turning` over
    the rows of every net: exact for a net on a surface of revolution (λ = 360°/span), the
    surface whose parallels turn as the rows do for a net bent from one. None when it cannot
    be measured (a net of one column, or straight rows)."""
    turns = [row_turning(f) for f in nets if f.shape[1] >= 3]
    if not turns:
        return None
    phi = float(np.nanmedian(np.concatenate(turns)))
    if not phi > MIN_TURNING:
        return None
    # 10 digits: a measured λ, not the last bits of the rows' angles (a full ring is λ = 1)
    return float(f"{2.0 * math.pi / phi:.10g}"), phi


def column_factors(w: np.ndarray, d: np.ndarray) -> np.ndarray:
    """c_j of strip widths ``w (m, n−1) ≈ c_j d(u)``: the mean over u of w_j(u)/d(u), ``(n−1,)``."""
    return (w / d[:, None]).mean(axis=0)


def mold_grid(mer: Meridian, theta: np.ndarray) -> np.ndarray:
    """The mold patch of a net with column angles ``theta (n−1,)``: ``(m, n, 3)`` with
    ``M(u, v) = (r(u) cos φ(v), r(u) sin φ(v), h(u))``, φ(v) = Σ_{j<v} θ_j."""
    phi = np.concatenate([[0.0], np.cumsum(theta)])
    return np.stack([mer.r[:, None] * np.cos(phi)[None, :],
                     mer.r[:, None] * np.sin(phi)[None, :],
                     np.broadcast_to(mer.h[:, None], (mer.r.size, phi.size))], axis=-1)
