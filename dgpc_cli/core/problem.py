"""Bind the constraint terms of SPEC §4 to one net's data, in units of its mean edge length.

The solver works on a net scaled to mean edge length 1 (so weights, ε and tolerances do not depend
on the model's units; the paper measures R after the same rescaling, §6.2.5). A ``Problem`` holds
that scale and the data of the data-bound terms (isometry lengths, handles, reference surface).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from dgpc_cli.core.constraints import TERMS
from dgpc_cli.core.constraints.isometry import isometry_data
from dgpc_cli.core.constraints.rim import rim_directions
from dgpc_cli.core.layout import NetLayout
from dgpc_cli.core.solver import Schedule, Term

#: Terms that pull and may be left with a residual; the tolerance applies to all others (the
#: geometry asked for). Fairness is always soft; a mode may add approximation (a reference the
#: net cannot lie on exactly, e.g. a nearly developable fit, paper Fig. 8).
SOFT_TERMS = ("fairness",)
#: Terms bound to the net a drag starts from (``Problem.f_start``).
START_TERMS = ("displacement_fairness", "displacement_smoothness", "closeness", "crease_guard")
#: Terms that only shape the solution (smoothness, staying put): in no residual norm and not
#: in R.
REGULARIZERS = ("fairness", "displacement_fairness", "displacement_smoothness", "closeness",
                "equal_u_edges", "crease_guard")


def mean_edge_length(f: np.ndarray) -> float:
    """Mean length of all edges of a grid ``(m, n, 3)``."""
    f = np.asarray(f, dtype=float)
    du = np.linalg.norm(f[1:] - f[:-1], axis=-1)
    dv = np.linalg.norm(f[:, 1:] - f[:, :-1], axis=-1)
    return float((du.sum() + dv.sum()) / (du.size + dv.size))


@dataclass
class Problem:
    """The terms of one optimization on an ``m × n`` net, in scaled units.

    Attributes
    ----------
    layout : NetLayout
    scale : float
        Length unit of the scaled problem (the mean edge length of the input net).
    weights : dict[str, Schedule]
        Weight schedule per term name; terms with weight 0 throughout are left out.
    f0 : (m, n, 3) array, optional
        The reference net for ``isometry`` (model units): its edge lengths and boundary angles.
    handle_ids, handle_targets : arrays, optional
        Handle vertex ids ``(l,)`` and targets ``(l, 3)`` (model units).
    reference : object with ``closest(points) -> (p, n)`` and ``scaled(s)``, optional
    boundary_ids : array, optional
        Net vertices kept on the reference's boundary by the ``boundary`` term.
    f_start : (m, n, 3) array, optional
        The net a drag starts from (model units), for ``displacement_fairness`` and
        ``closeness``, and the start of the ``rim`` term.
    rim_slack : (m·n,) array, optional
        How far the ``rim`` term lets each vertex of ``f_start`` come in (model units; default
        0): the distance it lies beyond the reference's edge (a net traced past it).
    """

    layout: NetLayout
    scale: float
    weights: dict
    f0: np.ndarray | None = None
    handle_ids: np.ndarray | None = None
    handle_targets: np.ndarray | None = None
    reference: object | None = None
    soft: tuple[str, ...] = SOFT_TERMS
    boundary_ids: np.ndarray | None = None
    f_start: np.ndarray | None = None
    rim_slack: np.ndarray | None = None
    _scaled_reference: object | None = field(default=None, init=False, repr=False)

    def active(self) -> list[str]:
        """Names of the terms in play, in the canonical order of ``TERMS``."""
        names = []
        for name in TERMS:
            sched = self.weights.get(name)
            if sched is None or (sched.start == 0 and sched.end == 0):
                continue
            if name == "approximation" and self.reference is None:
                continue
            if name == "boundary" and (self.reference is None or self.boundary_ids is None
                                       or len(self.boundary_ids) == 0):
                continue
            if name == "handles" and self.handle_ids is None:
                continue
            if name == "isometry" and self.f0 is None:
                continue
            if name in START_TERMS and self.f_start is None:
                continue
            if name == "rim" and (self.f_start is None or self.reference is None):
                continue
            names.append(name)
        return names

    def _bind(self, name: str, targets=None):
        lay, s = self.layout, self.scale
        fn = TERMS[name]
        if name == "isometry":
            w0, cos0 = isometry_data(lay, self.f0 / s)
            return lambda x: fn(x, lay, w0, cos0)
        if name in START_TERMS:
            start = np.asarray(self.f_start, dtype=float).reshape(-1, 3) / s
            return lambda x: fn(x, lay, start)
        if name == "rim":
            start = np.asarray(self.f_start, dtype=float).reshape(-1, 3) / s
            ids, outward = rim_directions(lay, start)
            slack = (np.zeros(len(ids)) if self.rim_slack is None
                     else np.asarray(self.rim_slack, dtype=float).ravel()[ids] / s)
            return lambda x: fn(x, lay, ids, start[ids], outward, slack)
        if name == "handles":
            ids = self.handle_ids
            p = (self.handle_targets if targets is None else targets) / s
            return lambda x: fn(x, lay, ids, p)
        if name in ("approximation", "boundary"):
            if self._scaled_reference is None:
                self._scaled_reference = self.reference.scaled(1.0 / s)
            ref = self._scaled_reference
            if name == "boundary":
                ids = self.boundary_ids
                return lambda x: fn(x, lay, ref, ids)
            return lambda x: fn(x, lay, ref)
        return lambda x: fn(x, lay)

    def terms(self, handle_targets=None) -> list[Term]:
        """Bound terms for the solver; ``handle_targets`` overrides the targets (handle steps)."""
        return [self.term(name, handle_targets) for name in self.active()]

    def term(self, name: str, handle_targets=None) -> Term:
        """The bound term ``name`` (a drag rebinds only ``handles`` to new targets)."""
        return Term(name, self._bind(name, handle_targets), self.weights[name],
                    hard=name not in self.soft and name not in REGULARIZERS,
                    regularizer=name in REGULARIZERS)

    def x_from_vertices(self, f: np.ndarray) -> np.ndarray:
        """Scaled variable vector with e, w derived from the vertex positions."""
        return self.layout.pack(np.asarray(f, dtype=float) / self.scale)

    def vertices(self, x: np.ndarray) -> np.ndarray:
        """Vertex grid ``(m, n, 3)`` in model units."""
        return self.layout.vertices(x) * self.scale

    def residual_norms(self, f: np.ndarray) -> dict[str, float]:
        """Unweighted residual norm of every active term at the vertex positions f.

        The net is rescaled to its own mean edge length 1 first, as the paper does for R.
        """
        own = mean_edge_length(f)
        rescaled = replace(self, scale=own)
        x = rescaled.x_from_vertices(f)
        return {t.name: float(np.linalg.norm(t.func(x)[0])) for t in rescaled.terms()}


def constraint_error(norms: dict[str, float], weights: dict, soft=()) -> float:
    """The paper's R = (Σ φ_i²)^½ (§6.2.5) over the hard terms with a positive final weight.

    Soft terms (``soft``: closeness to a reference the net need not lie on exactly) and the
    regularizers (fairness, a drag's smoothness) are left out; their norms are listed apart.
    """
    sq = sum(v * v for k, v in norms.items()
             if k not in REGULARIZERS and k not in soft
             and weights.get(k, Schedule.constant(0)).end > 0)
    return float(np.sqrt(sq))
