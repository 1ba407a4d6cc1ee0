"""Figures of a mold artifact: the meridian profile, the panels on the mold and on the design
(paper Fig. 16), and the mold pieces with the flat panels that need none (paper Fig. 17).

The mold is the surface of revolution ``(r(u) cos φ, r(u) sin φ, h(u))`` about the z axis. A
panel of the panel-to-mold map (``data.panels``: net, vertex ``rows`` and ``cols``, ``angle_deg``
on the mold, ``piece``, ``flat``) covers the quads ``rows × cols`` of its design net and the
region ``rows × angle_deg`` of the mold (every quad of the net is congruent to its quad there).

* :func:`pairing_figure` (Fig. 16): for one net, the mold region of each of its panels (left,
  the mold unrolled: along the parallel across, along the meridian up, so that no panel hides
  behind another) and the panel on the design (right), at one scale, one colour per panel on
  both sides, no two alike (:func:`panel_colours`), labelled with its id where the label fits
  without covering another; flat panels hatched.
* :func:`pieces_figure` (Fig. 17): the mold sector cut into its pieces (left, one colour per
  piece) and every design net with each panel in the colour of the piece it is pressed on; flat
  panels (K ≈ 0, no mold) white with a green outline.
"""

from __future__ import annotations

import colorsys
import math

import numpy as np

from .camera import model_frame, outward_front, outward_normals, same_scale, standard_views
from .render import figure
from .scene import Polygons, Segments, grid_quads, scene_points
from .views import LABEL_PT, TITLE_PT, one_scale, view_axes
from .words import counted

__all__ = ["PAIRING_SIZE", "PIECES_SIZE", "pairing_figure", "panel_colours", "pieces_figure",
           "profile_figure"]

#: Figure sizes (inches).
PAIRING_SIZE, PIECES_SIZE, PROFILE_SIZE = (11.0, 7.0), (11.0, 7.0), (5.0, 6.0)
#: Flat panels: outline colour (paper Fig. 17: green), hatch on the pairing figure.
FLAT_EDGE, FLAT_HATCH = (0.0, 0.6, 0.0, 1.0), "///"
WHITE = (1.0, 1.0, 1.0, 1.0)


def profile_figure(r: np.ndarray, h: np.ndarray, *, unit: str, title: str):
    """The mold's meridian ``(r, h)`` with its mirror image and the axis, equal scales, the
    axes labelled in ``unit``."""
    r, h = np.asarray(r, float), np.asarray(h, float)
    fig = figure(*PROFILE_SIZE)
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(r, h, lw=1.2, marker=".", ms=3, color="tab:blue", label="meridian")
    ax.plot(-r, h, lw=0.6, ls="--", color="0.6", label="mirror image")
    ax.axvline(0.0, lw=0.6, ls="-.", color="k", label="axis")
    ax.set_aspect("equal")
    ax.set_xlabel(f"r [{unit}]", fontsize=LABEL_PT)
    ax.set_ylabel(f"h [{unit}]", fontsize=LABEL_PT)
    ax.set_title(title, fontsize=TITLE_PT - 1)
    ax.legend(fontsize=LABEL_PT - 1, loc="best")
    ax.grid(True, lw=0.3)
    ax.tick_params(labelsize=LABEL_PT - 1)
    fig.tight_layout()
    return fig


def _blocks(panels: list[dict]) -> tuple[dict, dict]:
    """Row and column block index of every panel start, per net."""
    rows = sorted({p["rows"][0] for p in panels})
    cols: dict[int, list] = {}
    for p in panels:
        cols.setdefault(p["net"], set()).add(p["cols"][0])
    return ({r: i for i, r in enumerate(rows)},
            {k: {c: j for j, c in enumerate(sorted(v))} for k, v in cols.items()})


def panel_colours(panels: list[dict]) -> dict[str, tuple]:
    """One RGBA colour per panel id, no two panels of a net alike: the hue runs across the
    columns of its net, the value down its rows (light at the first row, darker at the last),
    and the saturation alternates like a chessboard, so that neighbouring panels differ."""
    row_of, col_of = _blocks(panels)
    rows = max(len(row_of), 1)
    out = {}
    for p in panels:
        i, j = row_of[p["rows"][0]], col_of[p["net"]][p["cols"][0]]
        count = max(len(col_of[p["net"]]), 1)
        hue = 0.85 * j / max(count - 1, 1)
        value = 0.98 - 0.4 * i / max(rows - 1, 1)
        r, g, b = colorsys.hsv_to_rgb(hue, 0.3 if (i + j) % 2 else 0.65, value)
        out[p["id"]] = (r, g, b, 1.0)
    return out


def mold_grid(r: np.ndarray, h: np.ndarray, rows, angles_deg, steps: int) -> np.ndarray:
    """The vertex grid ``(u1 − u0 + 1, steps + 1, 3)`` of the mold between the vertex rows
    ``rows = (u0, u1)`` and the angles ``angles_deg``."""
    u0, u1 = int(rows[0]), int(rows[1])
    phi = np.radians(np.linspace(float(angles_deg[0]), float(angles_deg[1]), steps + 1))
    rr, hh = np.asarray(r, float)[u0:u1 + 1], np.asarray(h, float)[u0:u1 + 1]
    return np.stack([rr[:, None] * np.cos(phi)[None, :], rr[:, None] * np.sin(phi)[None, :],
                     np.broadcast_to(hh[:, None], (rr.size, phi.size))], axis=-1)


def _outline(grid: np.ndarray) -> np.ndarray:
    """Boundary segments ``(k, 2, 3)`` of a vertex grid ``(a, b, 3)``."""
    ring = np.concatenate([grid[0, :], grid[1:, -1], grid[-1, -2::-1], grid[-2:0:-1, 0]])
    return np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)


def _panel_layers(grids: dict[str, np.ndarray], colours: dict, flat: set, gid: str) -> list:
    """Polygons of the panels (``grids``: id → vertex grid), curved ones then the flat ones
    hatched, and their outlines."""
    layers = []
    for name, chosen in ((gid, [k for k in grids if k not in flat]),
                         (f"{gid}-flat", [k for k in grids if k in flat])):
        if not chosen:
            continue
        quads = [grid_quads(grids[k]) for k in chosen]
        ids = [k for k, q in zip(chosen, quads, strict=True) for _ in range(len(q))]
        layers.append(Polygons(np.concatenate(quads), np.array([colours[k] for k in ids]),
                               name, edgecolor=(0.3, 0.3, 0.3, 0.25), linewidth=0.2, ids=ids,
                               hatch=FLAT_HATCH if name.endswith("-flat") else None))
    edges = np.concatenate([_outline(g) for g in grids.values()])
    layers.append(Segments(edges, (0.1, 0.1, 0.1, 1.0), f"{gid}-outlines", linewidth=0.7))
    return layers


def _short(pid: str) -> str:
    """The panel id without its net prefix and ``P-`` (``N2-P-u03-v07`` → ``u03-v07``)."""
    return pid.rsplit("P-", 1)[-1]


def _facing(view, grids: dict[str, np.ndarray]) -> dict[str, bool]:
    """Whether each panel (vertex grid) turns its outside (:func:`outward_normals` over all
    panels) to the viewer."""
    pids = list(grids)
    corners = np.stack([np.stack([g[0, 0], g[-1, 0], g[-1, -1], g[0, -1]]) for g in
                        grids.values()])
    toward = outward_normals(corners) @ view.rotation[2]
    return {pid: bool(t >= 0) for pid, t in zip(pids, toward, strict=True)}


#: Font size (points) of the panel labels; their box per character and height (points).
PANEL_PT = 6.5
LABEL_CHAR_PT, LABEL_HEIGHT_PT = 0.62 * PANEL_PT + 0.2, PANEL_PT + 2.5


def _labels(ax, view, grids: dict[str, np.ndarray], colours: dict, side: str,
            facing_only: bool = True) -> None:
    """The ids of the panels (those that face the viewer, with ``facing_only``), at their
    centres, on their colour: the largest panels first, each only where its box overlaps no
    label placed before and lies inside the axes (no label covers or cuts another)."""
    facing = _facing(view, grids) if facing_only else dict.fromkeys(grids, True)
    ax.apply_aspect()
    to_points = ax.transData + ax.get_figure().dpi_scale_trans.inverted()
    box_ax = ax.get_window_extent().transformed(ax.get_figure().dpi_scale_trans.inverted())
    placed: list[tuple[float, float, float, float]] = []
    order = sorted(grids, key=lambda pid: -float(np.ptp(view.project(grids[pid].reshape(-1, 3)),
                                                         axis=0).prod()))
    for pid in order:
        if not facing[pid]:
            continue
        x, y = view.project(grids[pid].reshape(-1, 3).mean(axis=0))
        cx, cy = to_points.transform((x, y))                # inches from the figure's corner
        text = _short(pid)
        hw = 0.5 * len(text) * LABEL_CHAR_PT / 72
        hh = 0.5 * LABEL_HEIGHT_PT / 72
        box = (cx - hw, cy - hh, cx + hw, cy + hh)
        inside = box_ax.x0 <= box[0] and box[2] <= box_ax.x1 and box_ax.y0 <= box[1] \
            and box[3] <= box_ax.y1
        if not inside or any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]
                             for b in placed):
            continue
        placed.append(box)
        ax.text(x, y, text, fontsize=PANEL_PT, ha="center", va="center", zorder=10,
                gid=f"label-{side}:{pid}",
                bbox={"boxstyle": "square,pad=0.15", "facecolor": colours[pid],
                      "edgecolor": "none", "alpha": 0.9})


def unrolled_grid(r: np.ndarray, h: np.ndarray, rows, angles_deg, steps: int,
                  middle_deg: float) -> np.ndarray:
    """The mold region of :func:`mold_grid` unrolled into the plane y = 0: x the arc along the
    parallel from the angle ``middle_deg`` (r(u)·Δφ), z the meridian's arc length s(u) from
    the mold's first row; every panel of the mold shows, none behind another."""
    r, h = np.asarray(r, float), np.asarray(h, float)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(r), np.diff(h)))])
    u0, u1 = int(rows[0]), int(rows[1])
    phi = np.radians(np.linspace(float(angles_deg[0]), float(angles_deg[1]), steps + 1)
                     - middle_deg)
    rr, ss = r[u0:u1 + 1], s[u0:u1 + 1]
    return np.stack([rr[:, None] * phi[None, :], np.zeros((rr.size, phi.size)),
                     np.broadcast_to(ss[:, None], (rr.size, phi.size))], axis=-1)


def pairing_figure(f: np.ndarray, panels: list[dict], r: np.ndarray, h: np.ndarray, *,
                   unit: str, title: str):
    """Paper Fig. 16 for one design net ``f (m, n, 3)`` and its ``panels`` (records of the
    panel-to-mold map): the mold regions left (axes gid ``view-mold``), the design right
    (``view-design``); panel polygons of gids ``panels``/``panels-flat`` carry the panel ids
    (urls), labels ``label-mold:<id>`` / ``label-design:<id>``."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    colours = panel_colours(panels)
    flat = {p["id"] for p in panels if p["flat"]}
    f = np.asarray(f, float)
    design = {p["id"]: f[p["rows"][0]:p["rows"][1] + 1, p["cols"][0]:p["cols"][1] + 1]
              for p in panels}
    angles = [a for p in panels for a in p["angle_deg"]]
    middle = 0.5 * (min(angles) + max(angles)) if angles else 0.0
    mold = {p["id"]: unrolled_grid(r, h, p["rows"], p["angle_deg"],
                                   max(p["cols"][1] - p["cols"][0], 1), middle)
            for p in panels}
    fig = figure(*PAIRING_SIZE)
    sides = []
    for side, grids in (("mold", mold), ("design", design)):
        layers = _panel_layers(grids, colours, flat, "panels")
        pts = scene_points(layers)
        if side == "mold":              # the unrolled mold (plane y = 0), seen square on
            side_front = np.array([0.0, -1.0, 0.0])
            view = standard_views(pts, front=side_front)[2]
        else:
            side_front = outward_front(np.concatenate([grid_quads(g) for g in grids.values()]))
            view = standard_views(pts, front=side_front)[0]
        sides.append((side, grids, layers, pts, side_front, view,
                      model_frame(view, pts, front=side_front)))
    frames = same_scale([s[-1] for s in sides])
    captions = {"mold": "on the mold, unrolled (along the parallel × along the meridian)",
                "design": "on the design"}
    for k, ((side, grids, layers, pts, side_front, view, _), frame) in enumerate(
            zip(sides, frames, strict=True)):
        ax = view_axes(fig, (0.01 + 0.5 * k, 0.12, 0.48, 0.76), view, layers, pts, unit=unit,
                       front=side_front, frame=frame)
        ax.set_gid(f"view-{side}")
        ax.set_title(captions[side], fontsize=LABEL_PT + 1, pad=4)
        _labels(ax, view, grids, colours, side, facing_only=side == "design")
    legend = [Patch(facecolor="0.85", edgecolor="0.3", label="one colour per panel, on both "
                                                                "sides"),
              Line2D([], [], color=(0.1, 0.1, 0.1), lw=0.7, label="panel outline")]
    if flat:
        legend.append(Patch(facecolor="white", edgecolor="0.3", hatch=FLAT_HATCH,
                            label=f"flat panel, no mold needed ({len(flat)})"))
    fig.legend(handles=legend, loc="lower center", bbox_to_anchor=(0.5, 0.005),
               ncol=len(legend), fontsize=LABEL_PT)
    fig.suptitle(title, fontsize=TITLE_PT, y=0.985)
    return fig


def _piece_colours(pieces: list[dict]) -> dict[str, tuple]:
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    return {p["id"]: tuple(cmap(k % 10)) for k, p in enumerate(pieces)}


def pieces_figure(nets: list[np.ndarray], panels: list[dict], pieces: list[dict],
                  r: np.ndarray, h: np.ndarray, sector_deg: float, *, unit: str, title: str,
                  names: list[str]):
    """Paper Fig. 17: the mold sector (``sector_deg`` wide) cut into its ``pieces`` (left, one
    colour each, gid ``pieces``), and each design net (right, ``names``) with its panels in the
    colour of their piece; flat panels white with a green outline (gid ``flat-outlines``)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    colours = _piece_colours(pieces)
    fig = figure(*PIECES_SIZE)
    steps = max(4, int(round(sector_deg / 5.0)))
    quads, cols, ids = [], [], []
    covered = np.zeros(len(r) - 1, bool)
    for p in pieces:
        q = grid_quads(mold_grid(r, h, p["rows"], (0.0, sector_deg), steps))
        quads.append(q)
        cols += [colours[p["id"]]] * len(q)
        ids += [p["id"]] * len(q)
        covered[p["rows"][0]:p["rows"][1]] = True
    for u in np.flatnonzero(~covered):
        q = grid_quads(mold_grid(r, h, (u, u + 1), (0.0, sector_deg), steps))
        quads.append(q)
        cols += [WHITE] * len(q)
        ids += [""] * len(q)
    layers = [Polygons(np.concatenate(quads), np.array(cols), "pieces",
                       edgecolor=(0.3, 0.3, 0.3, 0.2), linewidth=0.2, ids=ids)]
    pts = scene_points(layers)
    front = outward_front(layers[0].polys)
    view = standard_views(pts, front=front)[2]            # the elevation: the sector flat on
    cells = [((0.01, 0.12, 0.3, 0.76), view, layers, pts, front)]
    count = len(nets)
    ncol = 1 if count == 1 else 2
    nrow = math.ceil(count / ncol)
    width, height = 0.66 / ncol, 0.8 / nrow
    any_flat = False
    for k, f in enumerate(nets):
        f = np.asarray(f, float)
        mine = [p for p in panels if p["net"] == k]
        grids = {p["id"]: f[p["rows"][0]:p["rows"][1] + 1, p["cols"][0]:p["cols"][1] + 1]
                 for p in mine}
        quads = [grid_quads(grids[p["id"]]) for p in mine]
        face = [WHITE if p["flat"] or p["piece"] is None else colours[p["piece"]]
                for p in mine]
        layer = Polygons(np.concatenate(quads),
                         np.array([c for c, q in zip(face, quads, strict=True)
                                   for _ in range(len(q))]),
                         f"design-{k + 1}", edgecolor=(0.3, 0.3, 0.3, 0.3), linewidth=0.2,
                         ids=[p["id"] for p, q in zip(mine, quads, strict=True)
                              for _ in range(len(q))])
        flat = [g for p in mine if p["flat"] for g in [grids[p["id"]]]]
        design_layers = [layer]
        if flat:
            any_flat = True
            design_layers.append(Segments(np.concatenate([_outline(g) for g in flat]),
                                          FLAT_EDGE, "flat-outlines", linewidth=1.2))
        net_pts = f.reshape(-1, 3)
        net_front = outward_front(grid_quads(f))
        row, col = divmod(k, ncol)
        rect = (0.33 + col * width, 0.12 + (nrow - 1 - row) * height, width - 0.01,
                height - 0.01)
        cells.append((rect, standard_views(net_pts, front=net_front)[0], design_layers,
                      net_pts, net_front))
    # every view at one scale, one scale bar (under the sector) for all
    frames = one_scale(fig, [c[0] for c in cells],
                       [model_frame(v, p, front=fr) for _, v, _, p, fr in cells])
    for k, ((rect, v, lay, p, fr), frame) in enumerate(zip(cells, frames, strict=True)):
        ax = view_axes(fig, rect, v, lay, p, unit=unit, front=fr, frame=frame, bar=k == 0)
        if k == 0:
            ax.set_gid("view-pieces")
            ax.set_title(f"sector {sector_deg:.3g}°, {counted(len(pieces), 'piece')}",
                         fontsize=LABEL_PT + 1)
            for piece in pieces:
                mid = mold_grid(r, h, piece["rows"], (0.0, sector_deg),
                                2).reshape(-1, 3).mean(axis=0)
                x, y = v.project(mid)
                ax.text(x, y, piece["id"], ha="center", va="center", fontsize=LABEL_PT,
                        zorder=10, gid=f"piece-label:{piece['id']}")
            continue
        mine = [q for q in panels if q["net"] == k - 1]
        ax.set_gid(f"view-design-{k}")
        n_flat = sum(q["flat"] for q in mine)
        ax.set_title(f"{names[k - 1]}: {len(mine)} panels, {n_flat} flat", fontsize=LABEL_PT)
    legend = [Patch(facecolor=colours[p["id"]], edgecolor="0.3", label=f"piece {p['id']}")
              for p in pieces[:8]]
    if any_flat:                                          # only what is drawn
        legend.append(Line2D([], [], color=FLAT_EDGE, lw=1.5,
                             label="flat panel (K ≈ 0): no mold"))
    if not covered.all():
        legend.append(Patch(facecolor=WHITE, edgecolor="0.3", label="mold rows no panel needs"))
    fig.legend(handles=legend, loc="lower center", bbox_to_anchor=(0.5, 0.005),
               ncol=min(len(legend), 5), fontsize=LABEL_PT)
    title = f"{title} (every view at one scale)"
    fig.suptitle(title, fontsize=TITLE_PT, y=0.985)
    return fig
