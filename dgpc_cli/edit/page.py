"""The page of ``dgpc edit``: a viser scene of the net, its handles as gizmos, and the status.

The page only shows frames and forwards the designer's gestures to ``actions`` (an object with
``drag(u, v, target, end)``, ``pin(u, v)``, ``release(u, v)``, ``undo()``, ``redo()``,
``save()`` and ``fabrication(on)``); the solving happens elsewhere, off the page's threads.
A frame (see ``dgpc_cli.edit.session.Frame``) carries the net in its unit, a colour field per
vertex, the pleated and creased vertices, the handles and the status line.
"""

from __future__ import annotations

import logging
import threading

import numpy as np
import viser

from dgpc_cli.edit.colours import field_colours, legend
from dgpc_cli.edit.page_input import (
    BadInput,
    direction,
    guarded,
    number,
    vector,
    within_reach,
)
from dgpc_cli.edit.viser_logs import route_viser_output
from dgpc_cli.report.camera import outward_front, standard_views
from dgpc_cli.report.scene import grid_quads

log = logging.getLogger(__name__)

#: Colours of the page (RGB 0–255): the net's surface, its geodesics, flagged vertices.
SURFACE, GEODESICS, FLAGGED, SELECTED = (205, 205, 200), (200, 40, 40), (255, 0, 170), \
    (30, 120, 255)


#: The initial camera's distance from the net's centre, in diagonals of its bounding box.
CAMERA_DISTANCE = 1.1
#: Size of a handle's gizmo, in edge lengths of the net.
GIZMO_SIZE = 3.0
#: Width of its lines, in pixels (wider lines are easier to grab).
GIZMO_LINE = 6.0
#: The push slider: a handle moved along the net's normal, ± this many edge lengths.
PUSH_RANGE = 3.0
#: Seconds without a slider move after which the push counts as released (the net settles).
PUSH_SETTLE = 0.4


def quad_faces(m: int, n: int) -> np.ndarray:
    """Two triangles per quad of an m×n grid, row-major vertex ids ``u*n+v``."""
    vid = np.arange(m * n).reshape(m, n)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    return np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                           np.stack([a, c, d], -1).reshape(-1, 3)])


def vertex_normal(f: np.ndarray, u: int, v: int) -> np.ndarray:
    """Unit normal of the net ``f (m, n, 3)`` at vertex ``(u, v)`` (cross product of the
    central, at the rim one-sided, differences along u and v)."""
    m, n = f.shape[:2]
    du = f[min(u + 1, m - 1), v] - f[max(u - 1, 0), v]
    dv = f[u, min(v + 1, n - 1)] - f[u, max(v - 1, 0)]
    normal = np.cross(du, dv)
    return normal / (np.linalg.norm(normal) or 1.0)


def geodesic_segments(f: np.ndarray) -> np.ndarray:
    """Segments ``(k, 2, 3)`` of the u-lines (the geodesics) of the net ``f (m, n, 3)``."""
    return np.stack([f[:-1], f[1:]], axis=2).reshape(-1, 2, 3)


def initial_camera(f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The initial camera (look-at point, position; up +z): the report's axonometric view of
    the net (:func:`~dgpc_cli.report.camera.standard_views`, seen from its outside: column 0
    on the left, as in the report's elevation), from ``CAMERA_DISTANCE`` diagonals of its
    bounding box."""
    pts = f.reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = 0.5 * (lo + hi)
    up = (0.0, 0.0, 1.0)
    axonometric = standard_views(pts, up, outward_front(grid_quads(f), up))[0]
    toward = axonometric.rotation[2]
    return centre, centre + CAMERA_DISTANCE * float(np.linalg.norm(hi - lo)) * toward


class EditPage:
    """A viser server on ``host:port`` (port 0: a free one) showing the frames of a session."""

    def __init__(self, first, actions, *, host: str, port: int, title: str,
                 reference: tuple[np.ndarray, np.ndarray] | None = None,
                 max_strain: float = 3e-4):
        self.actions = actions
        self.limit = max_strain
        route_viser_output()            # viser's prints and errors: one stderr line each
        self.server = viser.ViserServer(host=host, port=port, label=title, verbose=False)
        # no public share link: the page stays where --host puts it
        self.server.request_share_url = self._no_share
        self.server.gui.configure_theme(control_width="large", show_logo=False,
                                        show_share_button=False)
        self.server.scene.set_up_direction("+z")
        self.server.scene.configure_fog(1e9, 2e9, enabled=False)   # a far net stays vivid
        self.shape = first.f.shape[:2]
        m, n = self.shape
        pts0 = first.f.reshape(-1, 3)
        self.box = (pts0.min(axis=0), pts0.max(axis=0))    # the reach of a handle's target
        self._accepted: dict[tuple[int, int], tuple[float, float, float]] = {}
        self._targets: dict[tuple[int, int], tuple[float, float, float]] = {}
        self._saved_handles: list | None = None
        self._lock = threading.RLock()
        self._gizmos: dict[tuple[int, int], object] = {}
        self._dragging: set[tuple[int, int]] = set()
        self.selected: tuple[int, int] | None = None
        self._push_base: tuple[np.ndarray, np.ndarray] | None = None   # (target, normal)
        self._push_timer: threading.Timer | None = None
        self._resetting = False
        self._figures_of = None                 # the field whose colours the page shows
        f = first.f.reshape(-1, 3)
        self.scale = float(np.median(np.linalg.norm(first.f[1:] - first.f[:-1], axis=-1)))
        if reference is not None:
            self.server.scene.add_mesh_simple("/reference", reference[0], reference[1],
                                              color=(150, 170, 200), opacity=0.35,
                                              side="double", cast_shadow=False,
                                              receive_shadow=False)
        self.mesh = self.server.scene.add_mesh_simple("/net", f, quad_faces(m, n),
                                                      color=SURFACE, side="double",
                                                      cast_shadow=False, receive_shadow=False)
        self.mesh.on_click(self._clicked)
        # the lines and points are no children of the clickable net: the page's hit test takes
        # a point within a world unit of the ray, and a click handler above the points would
        # take the press meant for a gizmo's arrow in front of them
        self.lines = self.server.scene.add_line_segments(
            "/geodesics", geodesic_segments(first.f), colors=GEODESICS, thickness=2.0,
            thickness_units="screen")
        self.points = self.server.scene.add_point_cloud(
            "/field", f, colors=field_colours(first.field, max_strain),
            point_size=0.2 * self.scale, point_shape="circle")
        self.flags = self.server.scene.add_point_cloud(
            "/flags", np.zeros((1, 3)), colors=FLAGGED, point_size=0.8 * self.scale,
            point_shape="diamond", visible=False)
        self.marker = self.server.scene.add_icosphere(
            "/selected", radius=0.3 * self.scale, color=SELECTED, visible=False)
        self._gui(first)
        self._view(first.f)
        self.show(first)

    # -- layout --------------------------------------------------------------------------
    def _gui(self, first) -> None:
        gui = self.server.gui
        self.status = gui.add_markdown(_status_markdown(first))
        self.figures = gui.add_markdown(_field_markdown(first, self.limit))
        with gui.add_folder("Handles"):
            self.selection = gui.add_markdown("Click a vertex of the net to add a handle.")
            self.push = gui.add_slider("Push selected (edges)", -PUSH_RANGE, PUSH_RANGE, 0.05,
                                       0.0, hint="Drag to move the selected handle along the "
                                                 "net's normal; let go and the net settles.")
            release = gui.add_button("Release selected handle")
            pin = gui.add_button("Pin selected vertex")
            undo = gui.add_button("Undo")
            redo = gui.add_button("Redo")
        with gui.add_folder("Save"):
            save = gui.add_button("Save artifact")
            self.saved = gui.add_markdown("")
        with gui.add_folder("Fabrication"):
            self.fab_on = gui.add_checkbox("Fabrication figures", False)
            self.fabrication = gui.add_markdown("")

        release.on_click(guarded("release")(
            lambda _: self.selected and self.actions.release(*self.selected)))
        pin.on_click(guarded("pin")(lambda _: self.selected and self.actions.pin(*self.selected)))
        undo.on_click(guarded("undo")(lambda _: self.actions.undo()))
        redo.on_click(guarded("redo")(lambda _: self.actions.redo()))
        save.on_click(guarded("save")(lambda _: self._save()))
        self.fab_on.on_update(guarded("fabrication switch")(lambda _: self._fabrication()))
        self.push.on_update(guarded("push")(lambda _: self._pushed()))

    def _view(self, f: np.ndarray) -> None:
        look_at, position = initial_camera(f)
        cam = self.server.initial_camera
        cam.look_at = tuple(look_at)
        cam.position = tuple(position)
        cam.up = (0.0, 0.0, 1.0)

    @property
    def url(self) -> str:
        return f"http://{_url_host(self.server.get_host())}:{self.server.get_port()}/"

    # -- gestures ------------------------------------------------------------------------
    def _no_share(self, *args, **kwargs) -> None:
        log.warning("edit: the page asked for a public share link; refused (the page listens "
                    "where --host says only)")

    def _fabrication(self) -> None:
        on = self.fab_on.value
        if not isinstance(on, bool):
            raise BadInput(f"fabrication switch: {on!r} is not true or false")
        self.actions.fabrication(on)

    @guarded("click")
    def _clicked(self, event) -> None:
        """Select the vertex nearest to the clicked ray; a vertex that is no handle becomes
        one, held where it is."""
        f = self._f.reshape(-1, 3)
        o = vector(event.ray_origin, "click: ray origin")
        d = direction(event.ray_direction, "click: ray direction")
        rel = f - o
        along = rel @ d
        off = np.linalg.norm(rel - along[:, None] * d, axis=1)
        if not (along > 0).any():
            raise BadInput("click: the ray passes no vertex of the net")
        vid = int(np.argmin(np.where(along > 0, off, np.inf)))
        u, v = divmod(vid, self.shape[1])
        self.select((u, v))
        if (u, v) not in self._gizmos:
            self.actions.pin(u, v)

    def select(self, index: tuple[int, int] | None) -> None:
        if index != self.selected:
            self._push_base = None
            self._resetting = True
            self.push.value = 0.0
            self._resetting = False
        self.selected = index
        if index is None:
            self.marker.visible = False
            self.selection.content = "Click a vertex of the net to add a handle."
            return
        self.marker.position = tuple(self._f[index])
        self.marker.visible = True
        held = "a handle" if index in self._gizmos else "not a handle"
        self.selection.content = f"Selected vertex **({index[0]}, {index[1]})**: {held}."

    def _pushed(self) -> None:
        """The push slider moved: drag the selected handle along the normal; the drag ends
        ``PUSH_SETTLE`` seconds after the last move."""
        if self._resetting:
            return
        push = number(self.push.value, -PUSH_RANGE, PUSH_RANGE, "push")
        index = self.selected
        if index is None:
            return
        if self._push_base is None:
            self._push_base = (self._f[index].copy(), vertex_normal(self._f, *index))
        base, normal = self._push_base
        target = tuple(float(c) for c in base + push * self.scale * normal)
        self.actions.drag(index[0], index[1], target, False)
        if self._push_timer is not None:
            self._push_timer.cancel()
        self._push_timer = threading.Timer(
            PUSH_SETTLE, lambda: self.actions.drag(index[0], index[1], target, True))
        self._push_timer.daemon = True
        self._push_timer.start()

    def _save(self) -> None:
        self.saved.content = "saving…"
        self.actions.save()

    @guarded("gizmo move")
    def _gizmo_moved(self, index: tuple[int, int], handle, event) -> None:
        """A gizmo's drag: its start selects the handle; each move drags it to the gizmo's
        position (checked: finite, within reach of the net); the end ends the drag (at the
        last position accepted, where the end's own is refused)."""
        phase = getattr(event, "phase", "update")
        if phase == "start":
            self._dragging.add(index)
            self.select(index)
            return
        end = phase == "end"
        if end:
            self._dragging.discard(index)
        try:
            target = vector(handle.position, f"gizmo ({index[0]}, {index[1]})")
            within_reach(target, self.box, f"gizmo ({index[0]}, {index[1]})")
        except BadInput:
            self._restore_gizmo(index)
            if end and index in self._accepted:
                self.actions.drag(index[0], index[1], self._accepted[index], True)
            raise
        self._accepted[index] = tuple(float(c) for c in target)
        self.actions.drag(index[0], index[1], self._accepted[index], end)

    # -- frames --------------------------------------------------------------------------
    def show(self, frame) -> None:
        """Show a frame (any thread). Only what changed is sent: the vertex positions of the
        scene's objects always (no object is made anew), the colours, flags and texts when
        the frame's figures are new (a drag event's quick frame keeps the last ones)."""
        with self._lock:
            self._f = frame.f
            pts = frame.f.reshape(-1, 3).astype(np.float32)
            figures = frame.field is not self._figures_of
            self._figures_of = frame.field
            with self.server.atomic():
                self.mesh.vertices = pts
                self.lines.points = geodesic_segments(frame.f).astype(np.float32)
                self.points.points = pts
                flagged = (frame.pleated | frame.creased).reshape(-1)
                if figures:
                    self.points.colors = field_colours(frame.field, self.limit)
                if flagged.any():
                    self.flags.points = pts[flagged]
                if figures:
                    self.flags.visible = bool(flagged.any())
                    self.figures.content = _field_markdown(frame, self.limit)
                self._sync_gizmos(frame)
                status = _status_markdown(frame)
                if status != self.status.content:
                    self.status.content = status
                if frame.fabrication is not None:
                    self.fabrication.content = _fabrication_markdown(frame.fabrication)
                elif not self.fab_on.value and self.fabrication.content:
                    self.fabrication.content = ""
                self._unsaved(frame)
            if self.selected is not None:
                self.select(self.selected)

    def _sync_gizmos(self, frame) -> None:
        wanted = {(u, v): target for u, v, target in frame.handles}
        self._targets = wanted
        for index in list(self._gizmos):
            if index not in wanted:
                self._gizmos.pop(index).remove()
        for index, target in wanted.items():
            gizmo = self._gizmos.get(index)
            if gizmo is None:
                self._new_gizmo(index, target)
            elif index not in self._dragging and frame.settled:
                gizmo.position = target

    def _new_gizmo(self, index: tuple[int, int], target) -> None:
        """A gizmo for the handle ``index`` at ``target`` (one there before is replaced)."""
        old = self._gizmos.pop(index, None)
        if old is not None:
            old.remove()
        gizmo = self.server.scene.add_transform_controls(
            f"/handles/h{index[0]}_{index[1]}", scale=GIZMO_SIZE * self.scale,
            line_width=GIZMO_LINE, disable_rotations=True, depth_test=False,
            position=target)
        gizmo.on_update(lambda event, i=index, g=gizmo: self._gizmo_moved(i, g, event))
        self._gizmos[index] = gizmo

    def _restore_gizmo(self, index: tuple[int, int]) -> None:
        """Put the gizmo of ``index`` back where the handle is, after a refused position
        (viser keeps what it was sent, of any shape: the gizmo is made anew)."""
        with self._lock:
            target = self._accepted.get(index, self._targets.get(index))
            if target is not None and index in self._gizmos:
                self._new_gizmo(index, target)

    def saved_to(self, text: str, saved: bool = False) -> None:
        """Say what the last save did (``saved``: it wrote the artifact of the handles on
        screen; the line then changes once they change: :meth:`_unsaved`)."""
        with self._lock:
            self.saved.content = text
            self._saved_handles = sorted(self._targets.items()) if saved else None

    def _unsaved(self, frame) -> None:
        """After a save, the first frame whose handles differ says the design changed since."""
        if self._saved_handles is None:
            return
        if sorted((u, v, t) for u, v, t in frame.handles) != [
                (*i, t) for i, t in self._saved_handles]:
            self.saved.content = "Changed since the last save: **not saved**"
            self._saved_handles = None

    def stop(self) -> None:
        self.server.stop()


def _url_host(host: str) -> str:
    return f"[{host}]" if ":" in host else host


def _status_markdown(frame) -> str:
    """The status line: the state in words (no emoji: a browser without an emoji font shows
    an empty box), the run's iterations and time where the net on screen is that run's."""
    line = f"**{frame.state.replace('_', ' ')}**: {frame.message}"
    if frame.iterations:
        line += f"  \n_{frame.iterations} iterations, {1000 * frame.seconds:.0f} ms_"
    return line


def _field_markdown(frame, limit: float) -> str:
    values = frame.field[np.isfinite(frame.field)]
    worst = float(values.max()) if values.size else float("nan")
    flags = []
    if frame.pleated.any():
        flags.append(f"pleated at {int(frame.pleated.sum())} vertices")
    if frame.creased.any():
        flags.append(f"creased at {int(frame.creased.sum())} vertices")
    text = f"Colour: {frame.field_name}, largest **{worst:.3g}** ({legend(limit)})"
    if flags:
        text += "  \n**Flagged**: " + "; ".join(flags) + " (magenta)"
    return text


def _percent(value) -> str:
    return "n/a" if value is None or value != value else f"{100 * value:.2f} %"


def _strips_markdown(strips: dict | None) -> str:
    """The strips' figures (:mod:`dgpc_cli.edit.fabrication`), saying where they come from."""
    if strips is None:
        return ("**Strips**: the figures of planarize-strips and unfold follow when the net "
                "settles")
    if "error" in strips:
        return f"**Strips**: {strips['error']}"
    k = strips["templates"]
    quantities = strips["quantities"]
    templates = (f"one template ({quantities[0]} copies)" if k == 1 else
                 f"{k} templates ({' + '.join(map(str, quantities))})")
    how = ("bent from one template" if strips["method"] == "template"
           else "each on its own (no shared template)")
    refine = f", {strips['refine']} rulings per net row" if strips["refine"] > 1 else ""
    if strips["source"] == "live":
        source = ("_live estimate while the net moves: the last strips bent onto it; "
                  "planarize-strips and unfold give theirs when it settles_")
    else:
        source = "_as planarize-strips and unfold make them (their defaults)_"
    missed = f"; **misses** {', '.join(strips['missed'])}" if strips["missed"] else ""
    return (f"**Strips**: {strips['strips']} strips, {how}{refine}: **{templates}**; "
            f"deviation from the net {_percent(strips['deviation'])} of the width, seam step "
            f"{_percent(strips['seam_step'])} (targets 1.5 %, 1 %){missed}  \n{source}")


def _fabrication_markdown(fab: dict) -> str:
    pending = fab.get("pending")
    lines = [] if pending and fab.get("strips") is None else [_strips_markdown(fab.get("strips"))]
    if pending:
        lines.append("**Strips**: planarize-strips and unfold are at work on the settled net")
    mold = fab.get("mold")
    if mold is None:
        lines.append("**Mold**: when the net settles")
    elif "error" in mold:
        lines.append(f"**Mold**: {mold['error']}")
    else:
        pieces = ", ".join(f"{p['id']} ({p['length']:.3g})" for p in mold["pieces"]) or "none"
        lines.append(f"**Mold**: one surface of revolution, radius {mold['radius'][0]:.3g}–"
                     f"{mold['radius'][1]:.3g}; pieces {pieces}; largest strain against it "
                     f"**{mold['strain_max']:.3g}**")
    return "  \n".join(lines)
