"""``dgpc edit``: a design session on one net, independent of any page (SPEC §4; paper §5.2).

The session holds the handles (grid vertices and their targets, in the net's unit), the net on
screen and an undo history. A drag runs a few iterations of guided projection on the problem
``optimize`` solves for the same handles, warm-started from the net on screen
(:meth:`EditSession.drag`); when the drag ends the net settles: ``optimize``'s own run from the
input net (:meth:`EditSession.settle`), so that what is saved is the artifact ``optimize``
writes for the saved handles file, byte for byte.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from dgpc_cli.core.solver import guided_projection, predictor_step
from dgpc_cli.edit.page_input import vector, within_reach
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.modes import SOFT
from dgpc_cli.fitting.optimize import OptimizeOutcome, judge, net_problem
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.handles import handles_bytes
from dgpc_cli.io.net import net_files
from dgpc_cli.metrics.crease import creased_vertices
from dgpc_cli.metrics.residuals import pleat
from dgpc_cli.metrics.strain import strain
from dgpc_cli.mold.isometry import panel_errors
from dgpc_cli.stages.optimize_artifact import (
    PreparedNet,
    optimize_prepared,
    optimized_artifact,
)
from dgpc_cli.tolerances import tol as TOL

log = logging.getLogger(__name__)

#: Guided-projection iterations per drag event (paper §5.2: iterations run while the mouse
#: moves): enough for the net to follow the handle, few enough to answer the next event.
LIVE_ITER = 1
#: A drag event runs a guided-projection iteration (a new factorization of the normal matrix)
#: every REFACTOR events, and whenever a predictor step is not taken; the events in between
#: re-solve the last factorized iteration for the handle's new target (one back-substitution,
#: :func:`~dgpc_cli.core.solver.predictor_step`). At 41×41 the factorization is ~85 % of an
#: iteration; after 3 predictor steps of the demo wall's drag the net residual is ~0.02 (mean
#: edges), and the next iteration brings it back to ~0.001.
REFACTOR = 4


class Superseded(Exception):
    """Raised from a solver callback when a newer request makes the running one moot."""


@dataclass
class Frame:
    """What the page shows: the net (net units), the colour field per vertex, the flagged
    vertices, the handles and the status line."""

    f: np.ndarray                       # (m, n, 3) net units
    field: np.ndarray                   # (m, n) strain or panel error (nan: undefined)
    field_name: str
    pleated: np.ndarray                 # (m, n) bool
    creased: np.ndarray                 # (m, n) bool
    handles: list[tuple[int, int, tuple[float, float, float]]]
    state: str                          # optimize's state, or "dragging"
    message: str
    settled: bool
    iterations: int = 0
    seconds: float = 0.0
    fabrication: dict | None = None
    #: Numeric factorizations of the normal matrix the last drag event made (0: a predictor
    #: step with the last one).
    factorizations: int = 0

    @property
    def status_line(self) -> str:
        return f"{self.state.replace('_', ' ')}: {self.message}"


@dataclass
class _Snapshot:
    handles: dict
    f_mm: np.ndarray
    outcome: OptimizeOutcome | None


@dataclass
class _Live:
    """The drag problem of one set of handle vertices, its iterate and solver workspace."""

    key: tuple[int, ...]
    problem: object
    x: np.ndarray
    workspace: object = None
    terms: list = field(default_factory=list)     # bound once; a drag rebinds the handles
    since: int = 0                                # predictor steps since the factorization
    linearized: bool = False                      # the workspace's factorization is of terms


@dataclass
class EditSession:
    """A design session on the prepared net (see :func:`~dgpc_cli.stages.optimize_artifact.
    prepare_optimize`); ``handles`` maps vertex id ``u*n+v`` to its target (net units)."""

    prepared: PreparedNet
    handles: dict[int, tuple[float, float, float]] = field(default_factory=dict)
    live_iter: int = LIVE_ITER
    #: Where the pipeline's figures of a settled net are asked for (None: worked out at once).
    fabricate: object = None

    def __post_init__(self):
        self.f_mm = np.array(self.prepared.net.f_mm, dtype=float)
        self.outcome: OptimizeOutcome | None = None
        self._undo: list[_Snapshot] = []
        self._redo: list[_Snapshot] = []
        self._live: _Live | None = None
        self._iterations = 0
        self._factorizations = 0
        self._seconds = 0.0
        self._shown: Frame | None = None
        self._strips = None             # the strips the live fabrication figures bend
        self._fab_of: tuple | None = None       # (net, figures) of the last settled figures

    # -- what is shown -------------------------------------------------------------------
    @property
    def mode(self) -> str:
        return self.prepared.settings.mode

    @property
    def shape(self) -> tuple[int, int]:
        return self.prepared.net.shape

    @property
    def settled(self) -> bool:
        return self.outcome is not None or not self.handles

    def handle_arrays(self) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Handle ids and targets in mm (as ``read_handles`` reads the saved file), or Nones."""
        if not self.handles:
            return None, None
        ids = np.fromiter(self.handles, dtype=np.int64, count=len(self.handles))
        targets = np.asarray(list(self.handles.values()), dtype=np.float64) * self.prepared.mm
        return ids, targets

    def quick_frame(self) -> Frame:
        """The net on screen with the colours, flags and status of the last full
        :meth:`frame` (what a drag event shows at once; the full frame follows when the solver
        is idle)."""
        last = self._shown
        if last is None or self.settled:
            return self.frame()
        n = self.shape[1]
        return replace(last, f=self.f_mm / self.prepared.mm,
                       handles=[(vid // n, vid % n, t) for vid, t in self.handles.items()],
                       state="dragging" if last.settled else last.state, settled=False,
                       iterations=self._iterations, seconds=self._seconds, fabrication=None,
                       factorizations=self._factorizations)

    def frame(self, fabrication: bool = False) -> Frame:
        """The net on screen, coloured by strain against the input (isometric) or by the panel
        error against its own surface of revolution (revolution), pleats and creases flagged,
        with the status ``optimize`` would report: its own when settled, else the figures of
        the net as it stands; with ``fabrication``, the fabrication figures
        (:meth:`fabrication`: the pipeline's when settled, else the live estimate)."""
        f_mm, f_in = self.f_mm, self.prepared.net.f_mm
        m, n = self.shape
        if self.mode == "isometric":
            values, name = strain(f_mm, f_in)[0], "strain"
        else:
            err = panel_errors(f_mm)
            values = np.full((m, n), np.nan) if err is None else _per_vertex(err, m, n)
            name = "panel error"
        pleated = np.zeros((m, n), dtype=bool)
        corrugation = pleat(f_mm)
        if corrugation.size:
            bad = corrugation > TOL.pleat
            pleated[:, 2:-3] |= bad
            pleated[:, 3:-2] |= bad
        if self.outcome is not None:
            state, message = self.outcome.status, self.outcome.message
        elif not self.handles:
            state, message = "input", "the input net; click a vertex to add a handle"
        else:
            state, message = self._judged()
        mm = self.prepared.mm
        handles = [(vid // n, vid % n, target) for vid, target in self.handles.items()]
        self._shown = Frame(f=f_mm / mm, field=np.asarray(values, dtype=float), field_name=name,
                     pleated=pleated, creased=creased_vertices(f_mm, start=f_in), handles=handles,
                     state=state if self.outcome is not None or not self.handles
                     else f"dragging ({state.replace('_', ' ')})",
                     message=message, settled=self.settled, iterations=self._iterations,
                     seconds=self._seconds, factorizations=self._factorizations,
                     fabrication=self.fabrication() if fabrication else None)
        return self._shown

    def _judged(self) -> tuple[str, str]:
        """What ``optimize`` would report if its solver stopped at the net on screen."""
        s = self.prepared.settings
        probe = OptimizeOutcome(f=self.f_mm, status="converged", message="", steps=[],
                                residuals={}, R=0.0)
        return judge(probe, self.prepared.net.f_mm, mode=s.mode, max_strain=s.max_strain,
                     gpc_tol=s.gpc_tol)

    # -- handles -------------------------------------------------------------------------
    def vertex_id(self, u: int, v: int) -> int:
        m, n = self.shape
        if not (0 <= u < m and 0 <= v < n):
            raise DgpcError(f"({u}, {v}) is outside the {m} x {n} grid", source="handle")
        return u * n + v

    def position(self, u: int, v: int) -> tuple[float, float, float]:
        """The vertex ``(u, v)`` of the net on screen, in net units."""
        p = self.f_mm.reshape(-1, 3)[self.vertex_id(u, v)] / self.prepared.mm
        return tuple(float(c) for c in p)

    def pin(self, u: int, v: int) -> None:
        """Make the vertex a handle held where it is on screen (a no-op for a handle)."""
        vid = self.vertex_id(u, v)
        if vid in self.handles:
            return
        self._remember()
        self.handles[vid] = self.position(u, v)
        self._changed()

    def release(self, u: int, v: int) -> None:
        """Let the handle at ``(u, v)`` go (a no-op for a vertex that is no handle)."""
        vid = self.vertex_id(u, v)
        if vid not in self.handles:
            return
        self._remember()
        del self.handles[vid]
        self._changed()

    def _changed(self) -> None:
        """The handles changed without a run: the net is not settled, and the figures of
        the last run (iterations, time) are not its own."""
        self.outcome = None
        self._iterations = self._factorizations = 0
        self._seconds = 0.0

    def drag(self, u: int, v: int, target) -> None:
        """Move the handle ``(u, v)`` (made one if it is not) to ``target`` (net units) and run
        ``live_iter`` iterations of guided projection from the net on screen, or, for up to
        ``REFACTOR − 1`` events after one, the predictor step of its last factorization."""
        vid = self.vertex_id(u, v)
        point = vector(target, f"handle ({u}, {v}): target")
        f_in = self.prepared.net.f_mm.reshape(-1, 3) / self.prepared.mm
        within_reach(point, (f_in.min(axis=0), f_in.max(axis=0)), f"handle ({u}, {v}): target")
        if self.outcome is not None or vid not in self.handles:
            self._remember()         # one undo step per drag, taken at its first event
        self.handles[vid] = tuple(float(c) for c in point)
        self.outcome = None
        ids, targets = self.handle_arrays()
        live = self._live_problem(ids, targets)
        t0 = time.perf_counter()
        terms = [live.problem.term("handles", targets) if t.name == "handles" else t
                 for t in live.terms]
        retract = live.problem.layout.orient_edges
        if live.linearized and live.since < REFACTOR - 1:
            step = predictor_step(terms, live.workspace, retract=retract)
            if step is not None and step.accepted:
                live.since += 1
                live.x = step.x
                self.f_mm = live.problem.vertices(live.x)
                self._iterations, self._factorizations = 0, 0
                self._seconds = time.perf_counter() - t0
                return
        result = guided_projection(live.x, terms, max_iter=self.live_iter,
                                   tol=self.prepared.settings.tol,
                                   backend=self.prepared.settings.backend,
                                   workspace=live.workspace, retract=retract)
        live.x, live.workspace = result.x, result.workspace
        live.linearized = result.workspace is not None and \
            result.workspace.linearization is not None
        live.since = 0
        self.f_mm = live.problem.vertices(live.x)
        self._iterations = self._factorizations = result.iterations
        self._seconds = time.perf_counter() - t0

    def _live_problem(self, ids: np.ndarray, targets: np.ndarray) -> _Live:
        key = tuple(int(i) for i in ids)
        if self._live is None or self._live.key != key:
            p = self.prepared
            problem = net_problem(p.net.f_mm, p.settings.schedules, reference=p.surface,
                                  handle_ids=ids, handle_targets=None, soft=SOFT[self.mode],
                                  boundary_ids=p.rim, rim_slack=p.rim_slack)
            workspace = self._live.workspace if self._live is not None else None
            self._live = _Live(key, problem, problem.x_from_vertices(self.f_mm), workspace,
                               problem.terms(targets))
        return self._live

    def settle(self, progress=None) -> OptimizeOutcome | None:
        """``optimize``'s run from the input net towards the handles (what is saved); None
        without handles. ``progress(k, record)`` is called every iteration (it may raise
        :class:`Superseded` to abandon the run; the session is then unchanged)."""
        if self.outcome is not None:
            return self.outcome
        ids, targets = self.handle_arrays()
        if ids is None:
            return None
        t0 = time.perf_counter()
        outcome = optimize_prepared(self.prepared, ids, targets, progress=progress)
        self.outcome, self.f_mm = outcome, outcome.f
        # the next drag starts from the settled net, with the factorization of the run's
        # first step (the same terms, so the same pattern)
        live = self._live = None
        live = self._live_problem(ids, targets)
        live.workspace = outcome.steps[0].workspace if outcome.steps else None
        self._iterations = self._factorizations = outcome.iterations
        self._seconds = time.perf_counter() - t0
        log.info("settled: %s (%s), %d iterations, %.2f s", outcome.status, outcome.message,
                 outcome.iterations, self._seconds)
        return outcome

    # -- undo ----------------------------------------------------------------------------
    def _snapshot(self) -> _Snapshot:
        return _Snapshot(dict(self.handles), self.f_mm.copy(), self.outcome)

    def _remember(self) -> None:
        self._undo.append(self._snapshot())
        self._redo.clear()

    def _restore(self, snap: _Snapshot) -> None:
        self.handles, self.f_mm, self.outcome = dict(snap.handles), snap.f_mm, snap.outcome
        self._live = None
        # the figures of the last run are not the restored net's
        self._iterations = self._factorizations = 0
        self._seconds = 0.0

    def undo(self) -> bool:
        if not self._undo:
            return False
        self._redo.append(self._snapshot())
        self._restore(self._undo.pop())
        return True

    def redo(self) -> bool:
        if not self._redo:
            return False
        self._undo.append(self._snapshot())
        self._restore(self._redo.pop())
        return True

    # -- artifacts -----------------------------------------------------------------------
    def save(self, output: Path, handles_path: Path | None = None) -> OptimizeOutcome:
        """Settle, then write the handles file (``handles_path``, default ``STEM-handles.json``
        beside the artifact) and the net artifact ``optimize`` writes for it to ``output``
        (both overwritten: the session's own files). Returns the outcome (its ``converged``
        decides the exit code, as in ``optimize``)."""
        out_json, _ = artifact_paths(output)
        ids, targets = self.handle_arrays()
        if targets is not None and not np.isfinite(targets).all():
            raise DgpcError("a handle's target is not finite: not saved", source=out_json)
        outcome = self.settle()
        if outcome is None:
            raise DgpcError(f"--mode {self.mode} needs handles: pin or drag a vertex first",
                            source="handles")
        if not np.isfinite(outcome.f).all():
            raise DgpcError("the settled net is not finite: not saved", source=out_json)
        handles_path = Path(handles_path or handles_file(output))
        n = self.shape[1]
        write_files({handles_path: handles_bytes(ids, n, targets / self.prepared.mm)},
                    force=True)
        result = optimized_artifact(self.prepared, outcome, output, handles_path, ids, targets)
        write_files(net_files(output, result), force=True)
        log.info("%s: %s; handles in %s", out_json, outcome.status, handles_path)
        return outcome

    # -- fabrication ---------------------------------------------------------------------
    def fabrication(self) -> dict:
        """The fabrication figures of the net on screen: settled, the pipeline's own
        (:func:`~dgpc_cli.edit.fabrication.fabrication_figures`, kept while the net stays);
        else the live estimate bent from the last strips
        (:func:`~dgpc_cli.edit.fabrication.live_figures`; ``{"strips": None}`` before any).
        With a ``fabricate`` callback (the page's :class:`~dgpc_cli.edit.fabrication_worker.
        FabricationWorker`), the pipeline's figures of a settled net are asked of it and
        the live estimate is shown, ``pending``, until :meth:`fabricated` brings them."""
        from dgpc_cli.edit.fabrication import fabrication_figures, live_figures

        if self.settled:
            cached = self._fab_of
            if cached is not None and np.array_equal(cached[0], self.f_mm):
                return cached[1]
            if self.fabricate is None:
                self.fabricated(self.f_mm, fabrication_figures(self.f_mm,
                                                               self.prepared.net.units))
                return self._fab_of[1]
            self.fabricate(self.f_mm.copy())
        strips = self._strips
        live = None if strips is None else live_figures(strips, self.f_mm)[0]
        return {"strips": live, "mold": None, **({"pending": True} if self.settled else {})}

    def fabricated(self, f_mm: np.ndarray, result: tuple) -> bool:
        """Keep the pipeline's figures ``result`` (figures, strips) of the net ``f_mm``
        where it is still the net on screen; whether it is."""
        if not np.array_equal(f_mm, self.f_mm):
            return False
        figures, self._strips = result
        self._fab_of = (np.array(f_mm, dtype=float), figures)
        return True


def handles_file(output: Path) -> Path:
    """Where ``dgpc edit -o STEM`` saves its handles: ``STEM-handles.json``."""
    out_json, _ = artifact_paths(output)
    return out_json.with_name(out_json.stem + "-handles.json")


def _per_vertex(quads: np.ndarray, m: int, n: int) -> np.ndarray:
    """A per-quad field ``(m−1, n−1)`` at the vertices: the largest of the quads around each."""
    q = np.where(np.isfinite(quads), quads, -np.inf)
    out = np.full((m, n), -np.inf)
    for du in (0, 1):
        for dv in (0, 1):
            out[du:m - 1 + du, dv:n - 1 + dv] = np.maximum(out[du:m - 1 + du, dv:n - 1 + dv], q)
    return np.where(np.isfinite(out), out, np.nan)
