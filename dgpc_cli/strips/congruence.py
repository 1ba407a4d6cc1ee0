"""Congruence classes of developed strips (paper §6.2.4, Fig. 18 bottom-right; SPEC §6, §8).

Two developed strips are congruent when a rigid motion maps one onto the other within a
tolerance. Their rulings may differ (an isometric bending moves the rulings, Fig. 18), so the
strips are compared as outlines: both boundary geodesics resampled at equal arc-length fractions
give corresponding points, optimally aligned by the Kabsch/Procrustes method. The four ways of
pairing the boundaries (as is, u reversed, A and B swapped, both) are tried; reflections count
only when mirror images are allowed.

The tolerance is a length (the shop's: ``unfold --congruence-tol``, default 0.5 mm), and the
classes do not depend on the order of the parts: every two parts are compared and grouped by
complete linkage, so that every two members of a class (and so every member and the class's
representative, the template it is cut from) agree within the tolerance.
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

    @classmethod
    def identity(cls) -> Alignment:
        """A part's alignment onto itself (a class's representative, a part of its own)."""
        return cls(R=np.eye(2), t=np.zeros(2), relabel="identity", mirrored=False, error=0.0)

    def apply(self, X: np.ndarray) -> np.ndarray:
        return X @ self.R.T + self.t

    def record(self, length: float, mm: float = 1.0) -> dict:
        """The flat artifact's record, ``length`` the representative's and ``mm`` mm per
        unit of the points: ``deviation_mm`` is the error in mm."""
        return {"matrix": self.R, "translation": self.t, "relabel": self.relabel,
                "mirrored": self.mirrored, "error": self.error,
                "relative_error": self.error / length, "deviation_mm": self.error * mm}


def kabsch(X: np.ndarray, Y: np.ndarray, allow_reflection: bool) -> tuple[np.ndarray, np.ndarray]:
    """Rotation (or orthogonal map) R and translation t minimizing ``Σ‖R x_i + t − y_i‖²``
    for corresponding points ``X, Y (k, d)`` (d = 2 for developed parts, 3 in space)."""
    cx, cy = X.mean(axis=0), Y.mean(axis=0)
    H = (X - cx).T @ (Y - cy)
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(Vt.T @ U.T))
    if allow_reflection:
        d = 1.0
    D = np.diag([1.0] * (X.shape[1] - 1) + [d if d != 0 else 1.0])
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


def end_invariants(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Lengths ``(4,)`` a rigid motion keeps and every pairing of :data:`RELABELINGS` only
    permutes: the chords of the two geodesics and the two end rulings, each pair sorted.
    Two strips whose invariants differ by more than 2 e cannot align within e (the end
    points are corresponding points of :func:`outline_points`)."""
    chords = sorted((float(np.linalg.norm(A[-1] - A[0])), float(np.linalg.norm(B[-1] - B[0]))))
    ends = sorted((float(np.linalg.norm(B[0] - A[0])), float(np.linalg.norm(B[-1] - A[-1]))))
    return np.array(chords + ends)


def deviation_matrix(parts: list[tuple[np.ndarray, np.ndarray]], tol: float, *,
                     mirror_ok: bool = False) -> np.ndarray:
    """Symmetric ``(n, n)``: the best alignment's largest point distance between every two
    developed strips ``(A, B)`` (:func:`align` of the later onto the earlier), ``inf`` where
    :func:`end_invariants` already prove it above ``tol``."""
    n = len(parts)
    inv = np.array([end_invariants(A, B) for A, B in parts]).reshape(n, 4)
    D = np.full((n, n), np.inf)
    np.fill_diagonal(D, 0.0)
    near = np.max(np.abs(inv[:, None, :] - inv[None, :, :]), axis=-1) <= 2.0 * tol * (1 + 1e-9)
    for i, j in zip(*np.nonzero(np.triu(near, k=1)), strict=True):
        D[i, j] = D[j, i] = align(*parts[j], *parts[i], mirror_ok=mirror_ok).error
    return D


#: Representatives whose largest distances to the others differ by less than this fraction of
#: the tolerance are a tie.
TIE = 1e-6


@dataclass
class CongruenceClass:
    """Members (part indices, in the canonical order) of one class, its representative and
    every member's alignment onto the representative."""

    id: str
    representative: int
    members: list
    alignments: list


def complete_linkage(D: np.ndarray, tol: float) -> list[list[int]]:
    """Groups of ``range(n)`` within which every two are at most ``tol`` apart in ``D``:
    complete-linkage clustering cut at ``tol`` (scipy), each group in ascending order, the
    groups by their first index."""
    n = D.shape[0]
    if n == 1:
        return [[0]]
    from scipy.cluster.hierarchy import fcluster, linkage
    from scipy.spatial.distance import squareform

    finite = D[np.isfinite(D)]
    far = 2.0 * max(float(finite.max(initial=0.0)), tol) + 1.0
    Z = linkage(squareform(np.where(np.isfinite(D), D, far), checks=False), method="complete")
    labels = fcluster(Z, t=tol, criterion="distance")
    groups: dict[int, list[int]] = {}
    for i, label in enumerate(labels):
        groups.setdefault(int(label), []).append(i)
    return sorted(groups.values(), key=lambda g: g[0])


def congruence_classes(parts: list[tuple[np.ndarray, np.ndarray]], tol: float, keys: list, *,
                       mirror_ok: bool = False) -> list[CongruenceClass]:
    """Group developed strips ``(A, B)`` into congruence classes within ``tol`` (a length in
    the strips' unit: the best alignment's largest point distance).

    Independent of the order of ``parts``: they are taken in the order of their ``keys``
    (distinct, sortable: e.g. the part ids), every two compared (:func:`deviation_matrix`),
    and grouped by complete linkage (:func:`complete_linkage`): every two members of a class
    are within ``tol``. A class's representative is its member farthest from none (the least
    largest distance to the others; the first in key order on a tie, within :data:`TIE` of
    the tolerance, so that copies equal to round-off keep their first); ``C01``, ``C02``, ...
    number the classes in the key order of their first members.
    """
    order = sorted(range(len(parts)), key=lambda i: keys[i])
    canon = [parts[i] for i in order]
    D = deviation_matrix(canon, tol, mirror_ok=mirror_ok)
    out = []
    for k, group in enumerate(complete_linkage(D, tol)):
        farthest = D[np.ix_(group, group)].max(axis=1)
        rep = group[int(np.argmax(farthest <= farthest.min() + TIE * tol))]
        alignments = [Alignment.identity() if i == rep
                      else align(*canon[i], *canon[rep], mirror_ok=mirror_ok) for i in group]
        out.append(CongruenceClass(id=f"C{k + 1:02d}", representative=order[rep],
                                   members=[order[i] for i in group], alignments=alignments))
    return out
