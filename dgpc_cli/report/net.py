"""Figures of nets in the three standard views (:mod:`.views`): quads coloured by a field, the
reference mesh under the net, the strain glyphs of paper Fig. 13, and the laths of a gridshell.

Fields per quad:

* strip width (§3.1): the mean of the quad's two v-edge lengths (viridis);
* discrete Gaussian curvature K (Jacobi equation (1), :func:`gaussian_curvature`): the mean of
  the finite K at the quad's two v-edges, red positive, blue negative, white ≈ 0 (``bwr`` on a
  range symmetric about 0, as the paper's Fig. 17).

Quads without a value (NaN) are light grey. The reference mesh, when at hand, is drawn under
the net, translucent grey where the net covers it and orange where it does not
(:func:`~dgpc_cli.metrics.coverage.covered_faces`), so that uncovered area shows.

The strain figure (:func:`strain_figure`) colours the area around every vertex (its quarter of
each adjacent quad) with the vertex's ``|λ1| + |λ2|`` and draws at every interior vertex the
principal directions of the strain tensor D (§6.1) as a cross: one arm along each eigenvector,
as long as its eigenvalue's magnitude, on a scale that makes the 75th percentile of the
vertices' larger magnitudes 0.9 mean edges long (a few spikes at the corners do not shrink the
rest to dots; longer arms are capped at 1.2 mean edges), black for stretch (λ > 0) and blue
for compression (λ < 0). Boundary vertices have one-sided tensors and no glyph. The handles of
the optimization are marked (magenta crosses), and the plan's cell shows the start shape (the
input net, grey) with each handle's move from its start to its target, through the same camera.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dgpc_cli.metrics.curvature import gaussian_curvature, strip_widths
from dgpc_cli.metrics.strain import mean_available

from .scene import Polygons, Segments, grid_quads
from .views import ColourBar, views_figure

__all__ = ["Reference", "curvature_per_quad", "field_figure", "laths_figure",
           "strain_figure", "strain_scale_top", "vertex_to_quad", "width_per_quad"]

#: Colour of quads without a value.
MISSING = (0.85, 0.85, 0.85, 1.0)
#: Reference faces: covered by the net (translucent grey), not covered (orange).
COVERED, UNCOVERED = (0.55, 0.55, 0.55, 0.25), (1.0, 0.5, 0.05, 0.75)
#: Strain glyphs: stretch, compression.
STRETCH, COMPRESSION = (0.0, 0.0, 0.0, 1.0), (0.0, 0.25, 0.95, 1.0)
#: Smallest span of a colour bar of a one-signed field, relative to its middle value: a field
#: constant to within it (a developable's strip width) is one colour, its ticks plain numbers.
MIN_SPAN = 1e-3
#: Length of a glyph arm at the :data:`GLYPH_PERCENTILE` of the magnitudes, and the cap of
#: every arm, in mean edge lengths.
GLYPH_ARM, GLYPH_CAP, GLYPH_PERCENTILE = 0.9, 1.2, 75
#: Colour of the handles' marks and moves; of the start shape's edges.
HANDLE, START = (0.85, 0.0, 0.75, 1.0), (0.35, 0.35, 0.35, 0.8)


@dataclass
class Reference:
    """A reference mesh ``vertices (k, 3)``, ``faces (t, 3)`` and the fraction ``(t,)`` of
    each face the net covers; ``recorded`` the covered share of the artifact's metrics
    (``coverage.area_fraction``), which the legend shows when given."""

    vertices: np.ndarray
    faces: np.ndarray
    covered: np.ndarray
    recorded: float | None = None

    @property
    def share(self) -> float:
        """The covered share the figure states: the recorded one, else :attr:`area_fraction`."""
        return self.area_fraction if self.recorded is None else float(self.recorded)

    @property
    def area_fraction(self) -> float:
        from trimesh.triangles import area as triangle_areas

        area = triangle_areas(self.vertices[self.faces])
        return float((area * self.covered).sum() / area.sum()) if area.sum() > 0 else 0.0


def width_per_quad(f: np.ndarray) -> np.ndarray:
    """Strip width per quad ``(m − 1, n − 1)`` of a net ``f (m, n, 3)``."""
    w = strip_widths(f)
    return 0.5 * (w[:-1] + w[1:])


def curvature_per_quad(f: np.ndarray) -> np.ndarray:
    """Discrete Gaussian curvature per quad ``(m − 1, n − 1)`` (NaN where none is defined)."""
    K = gaussian_curvature(f)
    return mean_available(K[:-1], K[1:])


def vertex_to_quad(values: np.ndarray) -> np.ndarray:
    """Per-vertex values ``(m, n)`` averaged to the quads ``(m − 1, n − 1)``, NaN-aware."""
    v = np.asarray(values, float)
    return mean_available(v[:-1, :-1], v[1:, :-1], v[1:, 1:], v[:-1, 1:])


def _norm(values: np.ndarray, diverging: bool):
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    finite = values[np.isfinite(values)]
    if diverging:
        a = float(np.abs(finite).max()) if finite.size else 0.0
        return Normalize(-(a or 1.0), a or 1.0), colormaps["bwr"]
    lo = float(finite.min()) if finite.size else 0.0
    hi = float(finite.max()) if finite.size else 1.0
    mid = 0.5 * (lo + hi)
    if hi - lo < MIN_SPAN * (abs(mid) or 1.0):     # a constant field reads as one colour
        pad = 0.5 * MIN_SPAN * (abs(mid) or 1.0)
        lo, hi = mid - pad, mid + pad
    return Normalize(lo, hi), colormaps["viridis"]


def _colours(values: np.ndarray, norm, cmap) -> np.ndarray:
    v = np.asarray(values, float).ravel()
    out = np.array(cmap(norm(np.where(np.isfinite(v), v, 0.0))), float).reshape(-1, 4)
    out[~np.isfinite(v)] = MISSING
    return out


def reference_layer(ref: Reference) -> Polygons:
    """The reference's faces, covered ones grey and uncovered ones orange (gid ``reference``)."""
    colours = np.where((np.asarray(ref.covered) >= 0.5)[:, None], COVERED, UNCOVERED)
    return Polygons(np.asarray(ref.vertices, float)[np.asarray(ref.faces)], colours,
                    "reference", edgecolor=(0, 0, 0, 0), linewidth=0.0)


def reference_legend(ref: Reference) -> list:
    from matplotlib.patches import Patch

    share = ref.share
    return [Patch(facecolor=COVERED, edgecolor="0.5",
                  label=f"reference, covered ({100 * share:.1f} %)"),
            Patch(facecolor=UNCOVERED, edgecolor="0.5",
                  label=f"reference, not covered ({100 * (1 - share):.1f} %)")]


def field_figure(grids: list[np.ndarray], values: list[np.ndarray], *, title: str,
                 label: str, unit: str, diverging: bool = False,
                 reference: Reference | None = None, up=(0.0, 0.0, 1.0), front=None):
    """The quad grids ``grids[i] (m_i, n_i, 3)`` in the standard views, quads coloured by
    ``values[i] (m_i − 1, n_i − 1)`` with a colour bar labelled ``label``; ``diverging``: red
    positive, blue negative, white 0 on a range symmetric about 0. Gid of the quads: ``net``."""
    flat = np.concatenate([np.asarray(v, float).ravel() for v in values])
    norm, cmap = _norm(flat, diverging)
    quads = np.concatenate([grid_quads(f) for f in grids])
    layers = [Polygons(quads, _colours(flat, norm, cmap), "net")]
    legend = None
    if reference is not None:
        layers.insert(0, reference_layer(reference))
        legend = reference_legend(reference)
    return views_figure(layers, title=title, unit=unit, up=up, front=front,
                        colour_bar=ColourBar(norm, cmap, label), legend=legend)


def vertex_cells(f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every quad's four corner quarters (corner, edge midpoints, centre): polygons
    ``(4(m − 1)(n − 1), 4, 3)`` and the flat index ``u·n + v`` of the vertex each belongs to."""
    f = np.asarray(f, float)
    m, n = f.shape[:2]
    q = grid_quads(f)                                           # corners 00, 10, 11, 01
    centre = q.mean(axis=1)
    u, v = np.meshgrid(np.arange(m - 1), np.arange(n - 1), indexing="ij")
    corner_ids = np.stack([u * n + v, (u + 1) * n + v, (u + 1) * n + v + 1, u * n + v + 1],
                          axis=-1).reshape(-1, 4)
    cells, ids = [], []
    for c in range(4):
        prev_mid = 0.5 * (q[:, c] + q[:, (c - 1) % 4])
        next_mid = 0.5 * (q[:, c] + q[:, (c + 1) % 4])
        cells.append(np.stack([q[:, c], next_mid, centre, prev_mid], axis=1))
        ids.append(corner_ids[:, c])
    return np.concatenate(cells), np.concatenate(ids)


def strain_glyphs(f: np.ndarray, D: np.ndarray) -> tuple[Segments, Segments]:
    """The two arms of the strain crosses at the interior vertices of ``f (m, n, 3)``
    (``D (m, n, 2, 2)`` the strain tensors): along the λ1 and the λ2 eigenvector, each
    ``((m − 2)(n − 2), 2, 3)`` centred on its vertex (gids ``strain-glyphs-1``, ``-2``)."""
    from dgpc_cli.metrics.frames import tangent_frames
    from dgpc_cli.metrics.strain import principal_strains

    f = np.asarray(f, float)
    lam1, lam2, theta = principal_strains(D)
    Tu, Tv, _ = tangent_frames(f)
    inner = (slice(1, -1), slice(1, -1))
    c, s = np.cos(theta[inner])[..., None], np.sin(theta[inner])[..., None]
    e1 = c * Tu[inner] + s * Tv[inner]
    e2 = -s * Tu[inner] + c * Tv[inner]
    l1, l2 = lam1[inner], lam2[inner]
    mags = np.fmax(np.abs(l1), np.abs(l2)).ravel()          # each vertex's longer arm
    mags = mags[np.isfinite(mags) & (mags > 0)]
    big = float(np.percentile(mags, GLYPH_PERCENTILE)) if mags.size else 0.0
    edge = _mean_edge(f)
    scale = 0.5 * GLYPH_ARM * edge / big if big > 0 else 0.0
    centre = f[inner]
    arms = []
    for k, (lam, e) in enumerate(((l1, e1), (l2, e2)), start=1):
        length = np.minimum(np.nan_to_num(scale * np.abs(lam)), 0.5 * GLYPH_CAP * edge)
        half = length[..., None] * np.nan_to_num(e)
        segs = np.stack([centre - half, centre + half], axis=-2).reshape(-1, 2, 3)
        colours = np.where((np.nan_to_num(lam) >= 0).ravel()[:, None], STRETCH, COMPRESSION)
        arms.append(Segments(segs, colours, f"strain-glyphs-{k}", linewidth=1.5))
    return arms[0], arms[1]


def _mean_edge(f: np.ndarray) -> float:
    edges = np.concatenate([np.linalg.norm(np.diff(f, axis=0), axis=-1).ravel(),
                            np.linalg.norm(np.diff(f, axis=1), axis=-1).ravel()])
    return float(edges.mean())


def _grid_edges(f: np.ndarray) -> np.ndarray:
    """Every edge ``(k, 2, 3)`` of the grid ``f (m, n, 3)``."""
    u = np.stack([f[:-1], f[1:]], axis=2).reshape(-1, 2, 3)
    v = np.stack([f[:, :-1], f[:, 1:]], axis=2).reshape(-1, 2, 3)
    return np.concatenate([u, v])


def handle_marks(points: np.ndarray, size: float) -> Segments:
    """A three-armed cross ``size`` long at each of ``points (k, 3)`` (gid ``handles``)."""
    p = np.asarray(points, float).reshape(-1, 3)
    axes = 0.5 * size * np.eye(3)
    segs = np.stack([p[:, None] - axes, p[:, None] + axes], axis=2).reshape(-1, 2, 3)
    return Segments(segs, HANDLE, "handles", linewidth=2.2)


def strain_scale_top(amount: np.ndarray, tolerance: float | None) -> float:
    """The top of a strain figure's colour scale: the largest finite strain in ``amount``,
    at least ``tolerance`` (a strain within the tolerance is never the scale's red; round-off
    of an unmoved net stays at its pale bottom), 1 where there is neither."""
    finite = np.asarray(amount, float)[np.isfinite(amount)]
    top = float(finite.max()) if finite.size and finite.max() > 0 else 0.0
    return max(top, tolerance or 0.0) or 1.0


def strain_figure(f: np.ndarray, f0: np.ndarray, *, title: str, unit: str,
                  up=(0.0, 0.0, 1.0), front=None, handles: dict | None = None,
                  tolerance: float | None = None):
    """Paper Fig. 13: the strain of the net ``f`` against ``f0`` (both ``(m, n, 3)``), the area
    around each vertex coloured by ``|λ1| + |λ2|`` (gid ``strain``) under the principal
    directions at the interior vertices (:func:`strain_glyphs`); ``handles`` (the net's
    ``data.handles``: flat vertex ``ids``) marked on the net and, in the start shape's view
    (``view-second``), on ``f0`` with their moves to where they are on ``f`` (gid
    ``handle-moves``). The colour scale runs from 0 to the largest strain, and at least to
    ``tolerance`` (the net's ``--max-strain``): a strain within it, round-off above all, is
    never drawn in the scale's red."""
    from matplotlib import colormaps
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D

    from dgpc_cli.metrics.strain import principal_strains, strain_tensor

    D = strain_tensor(f, f0)
    lam1, lam2, _ = principal_strains(D)
    amount = (np.abs(lam1) + np.abs(lam2)).ravel()
    norm, cmap = Normalize(0.0, strain_scale_top(amount, tolerance)), colormaps["YlOrRd"]
    cells, ids = vertex_cells(f)
    arm1, arm2 = strain_glyphs(f, D)
    layers = [Polygons(cells, _colours(amount[ids], norm, cmap), "strain",
                       edgecolor=(0, 0, 0, 0), linewidth=0.0),
              Polygons(grid_quads(f), np.zeros((len(grid_quads(f)), 4)), "net-edges",
                       edgecolor=(0.3, 0.3, 0.3, 0.5), linewidth=0.25),
              arm1, arm2]
    start = [Segments(_grid_edges(np.asarray(f0, float)), START, "start-net", linewidth=0.5)]
    legend = [Line2D([], [], color=STRETCH, lw=1.5, label="principal direction, stretch"),
              Line2D([], [], color=COMPRESSION, lw=1.5,
                     label="principal direction, compression")]
    ids_h = [int(i) for i in (handles or {}).get("ids", [])]
    if ids_h:
        size = 0.8 * _mean_edge(f)
        now, then = f.reshape(-1, 3)[ids_h], np.asarray(f0, float).reshape(-1, 3)[ids_h]
        layers.append(handle_marks(now, size))
        start += [Segments(np.stack([then, now], axis=1), HANDLE, "handle-moves",
                           linewidth=1.5), handle_marks(now, size)]
        moved = float(np.linalg.norm(now - then, axis=1).max())
        legend.append(Line2D([], [], color=HANDLE, lw=2.2,
                             label=f"handles ({len(ids_h)}): a cross where each is; on the "
                                   "start shape a line from where it started (moves up to "
                                   f"{moved:.3g} {unit})"))
    points = np.concatenate([f.reshape(-1, 3), np.asarray(f0, float).reshape(-1, 3)])
    return views_figure(layers, title=title, unit=unit, up=up, front=front,
                        colour_bar=ColourBar(norm, cmap, "strain |λ1| + |λ2| (dimensionless)"
                                             + (f"; --max-strain {tolerance:g}" if tolerance
                                                else "")),
                        legend=legend, points=points,
                        instead_of_plan=("start shape (input net)", start))


def laths_figure(families: list[list[np.ndarray]], names: list[str], *, title: str,
                 unit: str, up=(0.0, 0.0, 1.0)):
    """3-D polylines (``(k, 3)`` each) in the standard views, one colour per family (gids
    ``laths-<i>``), with a legend of ``names`` (the two lath families of a gridshell, Fig. 14)."""
    from matplotlib.lines import Line2D

    colours = [(0.12, 0.47, 0.71, 1.0), (0.84, 0.15, 0.16, 1.0), (0.17, 0.63, 0.17, 1.0)]
    layers, legend = [], []
    for k, (lines, name) in enumerate(zip(families, names, strict=True)):
        segs = [np.stack([p[:-1], p[1:]], axis=1) for p in (np.asarray(x, float)
                                                              for x in lines) if len(p) > 1]
        colour = colours[k % len(colours)]
        layers.append(Segments(np.concatenate(segs) if segs else np.zeros((0, 2, 3)), colour,
                               f"laths-{k}", linewidth=0.8))
        legend.append(Line2D([], [], color=colour, lw=1.5, label=name))
    return views_figure(layers, title=title, unit=unit, up=up, legend=legend)
