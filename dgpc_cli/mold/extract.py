"""``dgpc extract-mold``: the surface of revolution of one or several nets, its mold pieces and
the panel-to-mold map (SPEC §6, paper §4.2.2, Prop. 4.3, §6.2.3, Fig. 1, 16, 17).

1. Each net must satisfy (5) (:func:`~dgpc_cli.mold.profile.check_revolution`); several nets must
   be isometric to the same surface of revolution as the first (same rows, proportional strip
   widths d(u), equal meridian steps l(u)).
2. From the first net's d(u), l(u): r(u), x(u), h(u) with N segments per turn or Minding's
   λ = N/(n−1) (:func:`choose_lambda`: by default the design's own surface, λ = 360°/span;
   ``compact``: λ = 1, one full turn), lowered when x(u) would be imaginary.
3. Every K×K panel of every net is compared with its patch on the mold (edges and diagonals),
   flagged flat where κ = −δ_uu w / w ≈ 0, and assigned a mold piece: the sector just wide enough
   for the widest panel, cut along the meridian into pieces no longer than the limit.
4. A panel further off its mold patch than ``max_strain`` cannot be pressed on it: the nets are
   refused, naming the worst panel.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.length import Span
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.mold.panels import (
    Piece,
    block_max,
    block_starts,
    cut_pieces,
    panel_id,
    quad_curvature,
    quad_isometry_error,
)
from dgpc_cli.mold.profile import (
    Meridian,
    check_revolution,
    check_same_surface,
    column_factors,
    design_lambda,
    meridian,
    mold_grid,
    net_widths,
)
from dgpc_cli.surfaces.minding import circumradius
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)

#: Defaults of the options (SPEC §2: every resolved default is recorded in the artifact).
#: The largest relative difference of a panel's edges and diagonals from its mold patch.
DEFAULT_MAX_STRAIN = TOL.max_strain
#: Equation (5) within twice that: a net whose panels meet it spreads its ratios by at most
#: about 2 × the strain; it also accepts nets written with 7 significant digits (float32).
DEFAULT_TOL_FACTOR = 2.0
DEFAULT_TOL = DEFAULT_TOL_FACTOR * DEFAULT_MAX_STRAIN
DEFAULT_FLAT_TOL = 1e-5
DEFAULT_PANEL_SIZE = 1
#: The choices of ``--lambda`` besides a number, the first the default.
LAMBDA_CHOICES = ("design", "compact")


@dataclass(frozen=True)
class LambdaChoice:
    """Which surface of revolution: ``how`` (design, compact, value or segments), the λ asked
    for (None: N = ``segments``) and the design's λ and row turn Φ (radians) where measured."""

    how: str
    lam: float | None
    design: tuple[float, float] | None


def choose_lambda(nets: list[np.ndarray], spec: str | float | None,
                  segments: float | None = None) -> LambdaChoice:
    """The λ of ``--lambda spec`` (``design``, ``compact`` or a number; None: ``design``
    unless ``segments`` is given). ``design`` is the surface the nets' rows turn on
    (:func:`~dgpc_cli.mold.profile.design_lambda`), ``compact`` the full-turn one (λ = 1);
    a design whose turn cannot be measured (one column, straight rows) falls back to compact."""
    design = design_lambda(nets)
    if segments is not None:
        return LambdaChoice("segments", None, design)
    if spec is None or spec == "design":
        if design is None:
            return LambdaChoice("compact", 1.0, None)
        return LambdaChoice("design", design[0], design)
    if spec == "compact":
        return LambdaChoice("compact", 1.0, design)
    return LambdaChoice("value", float(spec), design)


@dataclass(frozen=True)
class NetPanels:
    """Per net: its column angles θ_j on the mold and per-panel fields ``(I, J)``."""

    name: str
    shape: tuple[int, int]
    theta: np.ndarray          # (n-1,) radians
    residual_max: float        # max residual of (5)
    error: np.ndarray          # (I, J) isometry error against the mold patch
    curvature: np.ndarray      # (I, J) max |κ| (−inf: undefined)
    flat: np.ndarray           # (I, J) bool
    cols: np.ndarray           # (J, 2) vertex columns [v0, v1]
    angles: np.ndarray         # (J, 2) degrees on the surface of revolution


@dataclass(frozen=True)
class Mold:
    """The result of :func:`extract_mold`."""

    meridian: Meridian
    nets: list[NetPanels]
    rows: np.ndarray           # (I, 2) vertex rows [u0, u1] of the panel rows
    pieces: list[Piece]
    piece_of_row: np.ndarray   # (I,) piece index per panel row, −1 = none
    sector_angle: float        # radians, the widest panel
    panel_size: int
    choice: LambdaChoice | None = None

    def choice_line(self, units: str) -> str:
        """One line for stderr: which surface of revolution was built, and why, with the
        radii of the other choice (``--lambda design|compact``)."""
        mer, choice = self.meridian, self.choice
        n0 = mer.segments / mer.lam

        def size(lam: float) -> str:
            r = circumradius(mer.d, 2.0 * math.pi / (lam * n0))
            return f"r {r.min():.3g}–{r.max():.3g} {units}"

        built = f"λ = {mer.lam:.4g}, {size(mer.lam)}, {mer.h[-1] - mer.h[0]:.3g} {units} tall"
        design = choice.design if choice is not None else None
        turn = (f"the nets' rows turn {math.degrees(design[1]):.4g}°" if design is not None
                else "the rows' turn could not be measured")
        how = choice.how if choice is not None else "segments"
        if how == "design":
            text = (f"the design's own surface of revolution (--lambda design: {turn}): "
                    f"{built}; --lambda compact gives the full-turn surface isometric to it "
                    f"({size(1.0)}), a mold to turn on a lathe")
        elif how == "compact":
            other = (f"; --lambda design gives the design's own surface (λ = {design[0]:.4g}, "
                     f"{size(design[0])})" if design is not None else f" ({turn})")
            text = (f"the full-turn surface of revolution isometric to the nets (--lambda "
                    f"compact), a mold to turn on a lathe: {built}{other}")
        else:
            asked = "--segments" if how == "segments" else "--lambda"
            other = (f"; the design's own surface is λ = {design[0]:.4g}"
                     if design is not None else "")
            text = (f"the surface of revolution of {asked} (Minding's bending of the full turn, "
                    f"Prop. 4.3): {built}{other}")
        lowered = (" (λ lowered so that every x(u) is real)" if mer.lowered else "")
        return f"extract-mold: {text}{lowered}"

    def panel_records(self) -> list[dict]:
        """The panel-to-mold map: one JSON-able record per panel, nets in order, row-major."""
        prefix = len(self.nets) > 1
        width = max(2, len(str(max(max(len(self.rows), p.cols.shape[0]) for p in self.nets))))
        out = []
        for k, net in enumerate(self.nets):
            for i, (u0, u1) in enumerate(self.rows.tolist()):
                piece = self.piece_of_row[i]
                for j, (v0, v1) in enumerate(net.cols.tolist()):
                    flat = bool(net.flat[i, j])
                    curv = float(net.curvature[i, j])
                    out.append({
                        "id": panel_id(i, j, width, f"N{k + 1}-" if prefix else ""),
                        "net": k,
                        "rows": [u0, u1],
                        "cols": [v0, v1],
                        "piece": None if flat or piece < 0 else self.pieces[piece].id,
                        "angle_deg": net.angles[j].tolist(),
                        "isometry_error": float(net.error[i, j]),
                        "curvature_max": curv if math.isfinite(curv) else None,
                        "flat": flat,
                    })
        return out

    def metrics(self) -> dict:
        """Summary figures (SPEC §7) of the mold and its panels."""
        flat = sum(int(p.flat.sum()) for p in self.nets)
        total = sum(int(p.flat.size) for p in self.nets)
        mer = self.meridian
        return {
            "segments": mer.segments,
            "lambda": mer.lam,
            "lambda_lowered": mer.lowered,
            "radius_min": float(mer.r.min()),
            "radius_max": float(mer.r.max()),
            "height": float(mer.h[-1] - mer.h[0]),
            "profile_length": mer.length,
            "sector_angle_deg": math.degrees(self.sector_angle),
            "pieces": len(self.pieces),
            "panels": total,
            "panels_flat": flat,
            "panels_curved": total - flat,
            "isometry_error_max": max(float(p.error.max()) for p in self.nets),
            "revolution_residual_max": max(p.residual_max for p in self.nets),
        }


def extract_mold(nets: list[tuple[str, np.ndarray]], *, segments: float | None = None,
                 lam: float | str | None = None, panel_size: int = DEFAULT_PANEL_SIZE,
                 flat_tol: float = DEFAULT_FLAT_TOL, max_length: float | None = None,
                 tol: float = DEFAULT_TOL, max_strain: float = DEFAULT_MAX_STRAIN) -> Mold:
    """The mold of the nets ``[(name, f (m, n_k, 3)), …]`` (names are used in messages).

    ``segments`` (N) and ``lam`` (λ = N/(n−1), n of the first net; or ``design``, ``compact``:
    :func:`choose_lambda`) are exclusive; neither gives the design's own surface. Raises
    DgpcError naming the net (or option) at fault: (5) fails beyond ``tol``, a net differs
    from the first, a panel is further than ``max_strain`` from its mold patch, a panel row
    is longer than ``max_length``.
    """
    if segments is not None and lam is not None:
        raise ValueError("give segments or lam, not both")
    K = int(panel_size)
    widths = [net_widths(f) for _, f in nets]
    for (name, _), wd in zip(nets, widths, strict=True):
        check_revolution(wd, tol, name)
    ref_name, ref = nets[0][0], widths[0]
    for (name, _), wd in zip(nets[1:], widths[1:], strict=True):
        check_same_surface(ref, wd, tol, name, ref_name)
    factors = [column_factors(wd.w, ref.d) for wd in widths]
    choice = choose_lambda([f for _, f in nets], lam, segments)
    mer = meridian(ref.d, ref.l, nets[0][1].shape[1] - 1, segments=segments, lam=choice.lam,
                   c_max=max(float(c.max()) for c in factors))
    m = nets[0][1].shape[0]
    row_starts = block_starts(m - 1, K)
    rows = np.column_stack([row_starts, np.minimum(row_starts + K, m - 1)])

    per_net = []
    for (name, f), wd, c in zip(nets, widths, factors, strict=True):
        theta = mer.column_angles(c)
        phi = np.degrees(np.concatenate([[0.0], np.cumsum(theta)]))
        error = block_max(quad_isometry_error(f, mold_grid(mer, theta)), K)
        curvature = block_max(quad_curvature(f), K)
        col_starts = block_starts(f.shape[1] - 1, K)
        cols = np.column_stack([col_starts, np.minimum(col_starts + K, f.shape[1] - 1)])
        per_net.append(NetPanels(
            name=name, shape=(int(f.shape[0]), int(f.shape[1])), theta=theta,
            residual_max=float(np.nanmax(wd.residual)) if wd.residual.size else 0.0,
            error=error, curvature=curvature,
            flat=np.isfinite(curvature) & (curvature <= flat_tol),
            cols=cols, angles=np.column_stack([phi[cols[:, 0]], phi[cols[:, 1]]])))
        log.info("%s: %d×%d panels, isometry error ≤ %.3g, %d flat", name, *error.shape,
                 float(error.max()), int(per_net[-1].flat.sum()))

    _check_panels(per_net, row_starts, K, max_strain, prefix=len(nets) > 1)
    needs_mold = np.any(np.stack([~p.flat.all(axis=1) for p in per_net]), axis=0)
    pieces, piece_of_row = cut_pieces(rows, needs_mold, mer.l, max_length)
    sector = max(float(np.radians(np.diff(p.angles, axis=1)).max()) for p in per_net)
    return Mold(meridian=mer, nets=per_net, rows=rows, pieces=pieces,
                piece_of_row=piece_of_row, sector_angle=sector, panel_size=K, choice=choice)


def check_max_length(mold: Mold, max_length, units: str) -> None:
    """OptionSlip (a usage error) where ``--mold-max-length`` (a
    :class:`~dgpc_cli.io.length.Length` or None) breaks the rule of every length
    (:meth:`~dgpc_cli.io.length.Length.check`): a plain number is plausible up to the whole
    mold's length along its meridian."""
    if max_length is None:
        return
    length = float(np.sum(mold.meridian.l))
    max_length.check("--mold-max-length", units, Span(
        0.0, length * mm_per_unit(units), "mold piece", low_open=True,
        high_text=f"the whole mold ({length:.4g} {units} along the meridian)"), "the nets'")


def _check_panels(per_net: list[NetPanels], row_starts: np.ndarray, K: int, max_strain: float,
                  prefix: bool) -> None:
    """DgpcError naming the net and its worst panel when a panel is further than
    ``max_strain`` from its mold patch."""
    worst = max(range(len(per_net)), key=lambda k: float(per_net[k].error.max()))
    net = per_net[worst]
    err = float(net.error.max())
    if err <= max_strain:
        return
    i, j = np.unravel_index(int(np.argmax(net.error)), net.error.shape)
    width = max(2, len(str(max(len(row_starts), net.cols.shape[0]))))
    pid = panel_id(int(i), int(j), width, f"N{worst + 1}-" if prefix else "")
    bad = int((net.error > max_strain).sum())
    raise DgpcError(f"panel {pid} (rows {int(i) * K}-{min(int(i) * K + K, net.shape[0] - 1)}) "
                    f"is {err:.3g} off its mold patch (largest relative difference of its "
                    f"edges and diagonals), more than --max-strain {max_strain:g}; {bad} of "
                    f"{net.error.size} panels are: the net is not isometric to the surface of "
                    "revolution closely enough to be pressed on one mold", source=net.name)


def inspect_mold(mold) -> dict:
    """What ``dgpc inspect MOLD`` prints: the meridian profile (r, h), the number of mold pieces,
    the counts of curved and flat panels, and the artifact's metrics. ``mold`` is a
    :class:`~dgpc_cli.io.mold.MoldArtifact`."""
    panels = mold.data["panels"]
    flat = sum(1 for p in panels if p["flat"])
    return {
        **mold.metrics,
        "profile": {"r": mold.data["profile"]["r"], "h": mold.data["profile"]["h"],
                    "units": mold.data["units"]},
        "pieces": len(mold.data["pieces"]),
        "panels": len(panels),
        "panels_flat": flat,
        "panels_curved": len(panels) - flat,
    }
