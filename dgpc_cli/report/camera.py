"""The cameras of the 3-D figures: standard orthographic views framed on the model.

A :class:`View` is an orthographic camera: the rows of its ``rotation`` are the screen's
right, the screen's up and the direction towards the viewer, so a point p is drawn at
``(right·p, up·p)`` at depth ``toward·p`` (larger is nearer). Orthographic views keep one scale
over the whole picture, so a scale bar holds everywhere in it.

:func:`standard_views` gives the three views of a model, around its ``up`` direction (the axis of
a surface of revolution, else +z) and its ``front`` (horizontal, the direction a viewer of its
elevation stands in: away from the axis for a surface of revolution, else across the model's
longest horizontal extent):

Nets are seen from their outside (:func:`outward_front`).

* ``axonometric`` — from the front, :data:`AZIMUTH` to the right and :data:`ELEVATION` above;
* ``plan`` — along the up direction, from above (along the axis for a surface of revolution);
* ``elevation`` — from the front, horizontally.

:meth:`View.frame` fits the view to the model's bounding box in the (front, side, up) frame:
the box's eight corners projected, plus a fixed :data:`MARGIN` of the larger side on every side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["AZIMUTH", "ELEVATION", "MARGIN", "View", "box_corners", "model_frame",
           "outward_front", "outward_normals", "same_scale", "standard_views"]

#: The axonometric view: degrees to the right of the front and above the horizon.
AZIMUTH, ELEVATION = 35.0, 25.0
#: Margin of a frame on every side, as a fraction of the frame's larger side.
MARGIN = 0.04


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    n = float(np.linalg.norm(v))
    if not n > 0:
        raise ValueError("zero vector")
    return v / n


@dataclass(frozen=True)
class View:
    """An orthographic camera ``rotation (3, 3)``: rows right, up, towards the viewer."""

    name: str
    title: str
    rotation: np.ndarray

    def project(self, points) -> np.ndarray:
        """Screen coordinates ``(..., 2)`` of ``points (..., 3)``."""
        return np.asarray(points, float) @ self.rotation[:2].T

    def depth(self, points) -> np.ndarray:
        """Depth ``(...)`` of ``points (..., 3)`` towards the viewer (larger is nearer)."""
        return np.asarray(points, float) @ self.rotation[2]

    def frame(self, corners: np.ndarray) -> tuple[float, float, float, float]:
        """``(x0, x1, y0, y1)``: the projected ``corners (k, 3)`` of a bounding box with
        :data:`MARGIN` of the larger side around them."""
        xy = self.project(corners)
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        pad = MARGIN * float(max(hi - lo)) or 1.0
        return (float(lo[0] - pad), float(hi[0] + pad), float(lo[1] - pad), float(hi[1] + pad))


def _look(name: str, title: str, toward: np.ndarray, up: np.ndarray, right_hint: np.ndarray
          ) -> View:
    toward = _unit(toward)
    right = np.cross(up, toward)
    if np.linalg.norm(right) < 1e-9:          # looking along up: the hint is right
        right = right_hint - np.dot(right_hint, toward) * toward
    right = _unit(right)
    screen_up = np.cross(toward, right)
    return View(name, title, np.stack([right, screen_up, toward]))


def _horizontal_frame(points: np.ndarray, up: np.ndarray, front) -> tuple[np.ndarray,
                                                                          np.ndarray]:
    """``(front, side)``: unit horizontal directions, side = up × front."""
    helper = np.eye(3)[int(np.argmin(np.abs(up)))]
    e1 = _unit(helper - np.dot(helper, up) * up)
    e2 = np.cross(up, e1)
    if front is not None:
        fr = np.asarray(front, float) - np.dot(front, up) * up
        if np.linalg.norm(fr) > 1e-9 * max(1.0, float(np.linalg.norm(front))):
            fr = _unit(fr)
            return fr, np.cross(up, fr)
    q = points - points.mean(axis=0)
    a, b = q @ e1, q @ e2
    cov = np.array([[a @ a, a @ b], [a @ b, b @ b]])
    w, vecs = np.linalg.eigh(cov)
    small = vecs[:, 0]                         # across the longest horizontal extent
    fr = small[0] * e1 + small[1] * e2
    k = int(np.argmax(np.abs(fr)))
    fr = _unit(fr if fr[k] >= 0 else -fr)
    return fr, np.cross(up, fr)


def box_corners(points, up=(0.0, 0.0, 1.0), front=None) -> np.ndarray:
    """The 8 corners ``(8, 3)`` of the bounding box of ``points (k, 3)`` in the model's
    (front, side, up) frame (see :func:`standard_views`)."""
    p = np.asarray(points, float).reshape(-1, 3)
    up = _unit(up)
    fr, side = _horizontal_frame(p, up, front)
    basis = np.stack([fr, side, up])
    q = p @ basis.T
    lo, hi = q.min(axis=0), q.max(axis=0)
    corners = np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return corners @ basis


def standard_views(points, up=(0.0, 0.0, 1.0), front=None, *, plan_title: str = "plan"
                   ) -> list[View]:
    """The axonometric, plan and elevation views of the model ``points (k, 3)`` (see the
    module); ``up`` and ``front`` directions, ``front`` None for the default."""
    p = np.asarray(points, float).reshape(-1, 3)
    up = _unit(up)
    fr, side = _horizontal_frame(p, up, front)
    az, el = np.radians(AZIMUTH), np.radians(ELEVATION)
    axo = np.cos(el) * (np.cos(az) * fr + np.sin(az) * side) + np.sin(el) * up
    return [_look("axonometric", "axonometric", axo, up, side),
            _look("plan", plan_title, up, up, side),
            _look("elevation", "elevation", fr, up, side)]


def model_frame(view: View, points, up=(0.0, 0.0, 1.0), front=None
                ) -> tuple[float, float, float, float]:
    """The frame of ``view`` on the model ``points`` (:meth:`View.frame` of its box)."""
    return view.frame(box_corners(points, up, front))


def same_scale(frames: list[tuple[float, float, float, float]]
               ) -> list[tuple[float, float, float, float]]:
    """The ``frames`` widened about their centres to the largest width and height among them,
    so that views drawn into equally large axes share one scale."""
    width = max(f[1] - f[0] for f in frames)
    height = max(f[3] - f[2] for f in frames)
    out = []
    for x0, x1, y0, y1 in frames:
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        out.append((cx - 0.5 * width, cx + 0.5 * width, cy - 0.5 * height, cy + 0.5 * height))
    return out


def outward_normals(quads) -> np.ndarray:
    """Normals ``(k, 3)`` (cross product of the diagonals, not unit) of ``quads (k, 4, 3)``,
    all turned to the side away from the quads' centroid (the outside of a convex or wrapped
    surface, the bulging side of a curved facade)."""
    q = np.asarray(quads, float)
    n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    centres = q.mean(axis=1)
    sign = float(np.einsum("ij,ij->", n, centres - centres.mean(axis=0)))
    return -n if sign < 0 else n


def outward_front(quads, up=(0.0, 0.0, 1.0)) -> np.ndarray | None:
    """The horizontal part of the mean outward normal of ``quads (k, 4, 3)``
    (:func:`outward_normals`): where the viewer of the model's outside stands; None when it
    is nearly vertical (a roof seen from above needs no front)."""
    n = outward_normals(quads).sum(axis=0)
    up = _unit(up)
    horizontal = n - np.dot(n, up) * up
    length = float(np.linalg.norm(n))
    if not length > 0 or np.linalg.norm(horizontal) < 0.2 * length:
        return None
    return horizontal / np.linalg.norm(horizontal)
