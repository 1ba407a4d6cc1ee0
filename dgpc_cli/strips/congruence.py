"""Congruence classes of developed strips (paper §6.2.4, Fig. 18 bottom-right; SPEC §6, §8).

Two developed strips are congruent when a rigid motion maps one onto the other within a
tolerance. Their rulings may differ (an isometric bending moves the rulings, Fig. 18), so the
strips are compared as outlines: both boundary geodesics resampled at equal arc-length fractions
give corresponding points, optimally aligned by the Kabsch/Procrustes method. The four ways of
pairing the boundaries (as is, u reversed, A and B swapped, both) are tried; reflections count
only when mirror images are allowed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Pairings of the two boundary geodesics: (reverse u, swap A and B).
RELABELINGS = {"identity": (False, False), "reversed": (True, False),
               "swapped": (False, True), "rotated": (True, True)}


def resample(X: np.ndarray, k: int) -> np.ndarray:
    """``k`` points at equal arc-length fractions along the polyline ``X (m, 2)``."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=-1))])
    t = np.linspace(0.0, s[-1], k)
    return np.stack([np.interp(t, s, X[:, 0]), np.interp(t, s, X[:, 1])], axis=-1)


def outline_points(A: np.ndarray, B: np.ndarray, k: int, relabel: str = "identity"):
    """Corresponding points ``(2k, 2)`` of a developed strip: A then B resampled, after the
    relabeling (a name of :data:`RELABELINGS`)."""
    reverse, swap = RELABELINGS[relabel]
    if swap:
        A, B = B, A
    if reverse:
        A, B = A[::-1], B[::-1]
    return np.concatenate([resample(A, k), resample(B, k)])


@dataclass
class Alignment:
    """The rigid motion ``x ↦ R x + t`` taking a strip onto another, its relabeling, whether it
    is a reflection (det R = −1), and the largest point distance after it."""

    R: np.ndarray
    t: np.ndarray
    relabel: str
    mirrored: bool
    error: float

    def apply(self, X: np.ndarray) -> np.ndarray:
        return X @ self.R.T + self.t

    def record(self, length: float) -> dict:
        return {"matrix": self.R, "translation": self.t, "relabel": self.relabel,
                "mirrored": self.mirrored, "error": self.error,
                "relative_error": self.error / length}


def kabsch(X: np.ndarray, Y: np.ndarray, allow_reflection: bool) -> tuple[np.ndarray, np.ndarray]:
    """Rotation (or orthogonal map) R and translation t minimizing ``Σ‖R x_i + t − y_i‖²``
    for corresponding points ``X, Y (k, 2)``."""
    cx, cy = X.mean(axis=0), Y.mean(axis=0)
    H = (X - cx).T @ (Y - cy)
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(Vt.T @ U.T))
    if allow_reflection:
        d = 1.0
    D = np.diag([1.0, d if d != 0 else 1.0])
    R = Vt.T @ D @ U.T
    return R, cy - R @ cx


def align(A: np.ndarray, B: np.ndarray, A_ref: np.ndarray, B_ref: np.ndarray, *,
          mirror_ok: bool = False, samples: int | None = None) -> Alignment:
    """The best alignment of the developed strip ``A, B (m, 2)`` onto ``A_ref, B_ref``."""
    k = samples or 4 * max(A.shape[0], A_ref.shape[0])
    target = outline_points(A_ref, B_ref, k)
    best = None
    for relabel in RELABELINGS:
        X = outline_points(A, B, k, relabel)
        for reflect in ((False, True) if mirror_ok else (False,)):
            R, t = kabsch(X, target, reflect)
            err = float(np.max(np.linalg.norm(X @ R.T + t - target, axis=1)))
            if best is None or err < best.error - 1e-15:
                best = Alignment(R=R, t=t, relabel=relabel,
                                 mirrored=bool(np.linalg.det(R) < 0), error=err)
    return best


@dataclass
class CongruenceClass:
    """Members (part indices) of one class, its representative (the first member) and every
    member's alignment onto the representative."""

    id: str
    representative: int
    members: list
    alignments: list


def congruence_classes(parts: list[tuple[np.ndarray, np.ndarray, float]], tol: float, *,
                       mirror_ok: bool = False) -> list[CongruenceClass]:
    """Group developed strips ``(A, B, length)`` into congruence classes.

    In order, each strip joins the first existing class whose representative it matches within
    ``tol`` times the representative's length (the best alignment's largest point distance),
    else it founds a new class. Deterministic for a given order.
    """
    classes: list[CongruenceClass] = []
    for i, (A, B, _) in enumerate(parts):
        for cls in classes:
            Ar, Br, length = parts[cls.representative]
            al = align(A, B, Ar, Br, mirror_ok=mirror_ok)
            if al.error <= tol * length:
                cls.members.append(i)
                cls.alignments.append(al)
                break
        else:
            ident = Alignment(R=np.eye(2), t=np.zeros(2), relabel="identity", mirrored=False,
                              error=0.0)
            classes.append(CongruenceClass(id=f"C{len(classes) + 1:02d}", representative=i,
                                           members=[i], alignments=[ident]))
    return classes
