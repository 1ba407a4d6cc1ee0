"""``dgpc init MESH --patches auto|K``: several nets where one is poor (SPEC §5).

A single net over a lobed roof needs strips whose width varies many times along them (the
geodesics fan out over every hill and crowd in every valley: paper §3.1, the Jacobi equation).
``--patches K`` cuts the reference into K patches (``surfaces.patches``: along the valleys and
necks between its lobes, the largest patch bisected until there are K) and makes one net on
each, by the same choice as a single net (``layout.choice``), the patch being its
reference: ``optimize --mode fit`` fits it to the patch and ``planarize-strips --trim`` clips
its strips to the patch's outline, cut curves included.

``--patches auto`` first makes the single net and measures its *width ratio*: per strip, the
widest over the narrowest of its rows on the reference, the worst strip's. At most
:data:`WIDTH_RATIO_LIMIT` the single net is kept; above, the patch whose net is worst is
bisected as long as its ratio is above the limit, the bisection lowers it (or leaves it within
:data:`RATIO_SLACK` while the halves' nets cover :data:`COVERAGE_GAIN` more of the patch), and
there are fewer than :data:`MAX_PATCHES` patches.

Every net records why (``data.patches``, carried on by ``optimize``): the single net's
candidate, coverage and width ratio, the limit, K, every cut (its curves, in the net's unit,
and figures) and every patch's area, coverage and width ratio.
"""

from __future__ import annotations

import dataclasses
import hashlib
import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.mesh import ReferenceMesh, clean_mesh, write_mesh_obj
from dgpc_cli.io.net import NetArtifact
from dgpc_cli.metrics.width_ratio import strip_width_ratios
from dgpc_cli.surfaces.patches import Patch, bisect, order_patches, split

log = logging.getLogger(__name__)

#: A single net whose worst strip varies in width by more than this is split (auto).
WIDTH_RATIO_LIMIT = 3.0
#: A cut whose patches' strips vary no more than this fraction beyond the patch's is kept
#: when their nets cover at least :data:`COVERAGE_GAIN` more of it (a net across the patch
#: folds or is shrunk where the two halves' nets clad it).
RATIO_SLACK, COVERAGE_GAIN = 0.1, 0.05
#: The most patches ``--patches auto`` makes.
MAX_PATCHES = 4
#: A net vertex lies on the reference when it is within this fraction of the net's mean edge of
#: it (a net traced beyond it with ``--extend`` runs off in the tangent planes).
ON_REFERENCE = 1e-3


def width_ratio(f: np.ndarray, mesh: ReferenceMesh) -> dict:
    """The width ratio of the net ``f (m, n, 3)`` on ``mesh`` (see the module): ``ratio`` (the
    worst strip's widest over narrowest row, counting rows whose two vertices lie on the mesh),
    that ``strip`` (``S-v07``) and every strip's ratio (``per_strip``, null for a strip with
    fewer than two such rows)."""
    from dgpc_cli.core.reference import ReferenceSurface

    f = np.asarray(f, float)
    m, n = f.shape[:2]
    surface = ReferenceSurface(mesh.vertices, mesh.faces)
    P = f.reshape(-1, 3)
    on, _ = surface.closest(P)
    edge = float(np.mean(np.linalg.norm(np.diff(f, axis=1), axis=-1)))
    near = (np.linalg.norm(P - on, axis=1) <= ON_REFERENCE * edge).reshape(m, n)
    ratios = strip_width_ratios(f, near[:, :-1] & near[:, 1:])
    per_strip = np.where(np.isfinite(ratios), ratios, np.nan)
    if not np.isfinite(per_strip).any():
        return {"ratio": None, "strip": None, "per_strip": [None] * (n - 1)}
    j = int(np.nanargmax(per_strip))
    return {"ratio": float(per_strip[j]), "strip": f"S-v{j:02d}",
            "per_strip": [None if not np.isfinite(x) else float(x) for x in per_strip]}


@dataclass
class PatchNet:
    """One patch, the mesh made of it (``mesh.path``: the OBJ it is to be written to) and its
    OBJ bytes, the net made on it, the choice's outcome and candidates, its width ratio, and
    how to make its net within the largest strip width (``layout.width``; None: it is)."""

    patch: Patch
    mesh: ReferenceMesh
    obj: bytes
    net: NetArtifact
    outcome: object
    tried: list
    width: dict
    label: str
    narrowed: Callable[[], tuple] | None = None


#: Makes a net on a mesh: ``(mesh) -> (grid, outcome, tried, narrowed)`` (``layout.choice.choose``
#: or the search with the command's options bound, the mesh continued as ``--extend`` says;
#: ``narrowed()``: the net within the largest strip width, ``(grid, outcome, tried)``, or None).
NetMaker = Callable[[ReferenceMesh], tuple]


def _patch_net(patch: Patch, path: Path, make: NetMaker, whole: ReferenceMesh) -> PatchNet:
    V, F = clean_mesh(patch.vertices, patch.faces)
    obj = write_mesh_obj(path, V, F)
    mesh = ReferenceMesh(V, F, Path(path), hashlib.sha256(obj).hexdigest())
    try:
        grid, outcome, tried, later = make(mesh)
    except DgpcError as err:
        raise DgpcError(f"patch {path.name}: {err.reason}", source=whole.path) from None
    return PatchNet(patch, mesh, obj, grid.net, outcome, tried,
                    width_ratio(grid.net.f, mesh), grid.label, later)


def narrowed(p: PatchNet) -> PatchNet:
    """The patch net ``p`` made within the largest strip width (the patches are decided by the
    nets as first made: a finer net's widths vary more along its strips at the fans)."""
    if p.narrowed is None:
        return p
    try:
        grid, outcome, tried = p.narrowed()
    except DgpcError as err:
        raise DgpcError(f"patch {p.mesh.path.name}: {err.reason}", source=p.mesh.path) from None
    return dataclasses.replace(p, net=grid.net, outcome=outcome, tried=tried,
                               width=width_ratio(grid.net.f, p.mesh), label=grid.label,
                               narrowed=None)


def _cut_record(cut: dict) -> dict:
    return {"curves": [np.asarray(c, float).tolist() for c in cut["curves"]],
            "cut_ratio": cut["cut_ratio"], "area_share": cut["area_share"]}


def plan(mesh: ReferenceMesh, count: int | None, stem: Path, single: np.ndarray,
         label: str, coverage: float, make: NetMaker) -> tuple[list[PatchNet], dict]:
    """The patches of ``mesh`` and their nets (``count`` of them, or as ``auto`` decides when
    ``count`` is None; see the module), their OBJs to be written at ``STEM.pK.patch.obj``, and
    the record every net keeps; no nets when one patch is kept. ``single``: the single net
    ``(m, n, 3)``, made by the candidate ``label``, covering ``coverage`` of the mesh."""
    first = width_ratio(single, mesh)
    record = {"requested": "auto" if count is None else count, "limit": WIDTH_RATIO_LIMIT,
              "single": {"candidate": label, "coverage": coverage,
                         "width_ratio": first["ratio"], "strip": first["strip"]}}
    ratio = first["ratio"]
    if count == 1 or (count is None and (ratio is None or ratio <= WIDTH_RATIO_LIMIT)):
        record.update(count=1, cuts=[], reason=(
            "--patches 1" if count == 1 else
            f"the single net's strips vary in width at most {ratio_text(ratio)} along them "
            f"(limit {WIDTH_RATIO_LIMIT:g}x): one patch"))
        return [], record

    def path(k: int) -> Path:
        return stem.parent / f"{stem.name}.p{k}.patch.obj"

    whole = Patch(mesh.vertices, mesh.faces)
    if count is not None:
        try:
            patches, cuts = split(mesh.vertices, mesh.faces, count)
        except ValueError as err:
            raise DgpcError(f"cannot cut the mesh into {count} patches: {err}",
                            source=mesh.path) from None
        nets = [_patch_net(p, path(k + 1), make, mesh) for k, p in enumerate(patches)]
        why = (f"--patches {count}; the single net's strips vary in width up to "
               f"{ratio_text(ratio)} along them (strip {first['strip']})")
    else:
        nets, cuts, stop = _auto(whole, ratio, coverage, path, make, mesh)
        if not nets:
            record.update(count=1, cuts=[], reason=(
                f"the single net's strips vary in width up to {ratio_text(ratio)} along them "
                f"(strip {first['strip']}), more than {WIDTH_RATIO_LIMIT:g}x, but {stop}: "
                "one patch"))
            return [], record
        why = (f"the single net's strips vary in width up to {ratio_text(ratio)} along them "
               f"(strip {first['strip']}), more than {WIDTH_RATIO_LIMIT:g}x: {len(nets)} patches; "
               + stop)
    ordered = order_patches([p.patch for p in nets], mesh.vertices)
    nets = [next(p for p in nets if p.patch is q) for q in ordered]
    # the OBJ names follow the final order
    nets = [_renamed(p, path(k + 1)) for k, p in enumerate(nets)]
    record.update(count=len(nets), reason=why, cuts=[_cut_record(c) for c in cuts],
                  patches=[{"name": f"p{k + 1}", "area": p.patch.area,
                            "coverage": p.outcome.coverage, "candidate": p.label,
                            "width_ratio": p.width["ratio"], "strip": p.width["strip"]}
                           for k, p in enumerate(nets)])
    return nets, record


def ratio_text(ratio) -> str:
    """``5.20x``, or ``?`` for no ratio."""
    return "?" if ratio is None else f"{ratio:.2f}x"


def _renamed(p: PatchNet, path: Path) -> PatchNet:
    if p.mesh.path == path:
        return p
    obj = write_mesh_obj(path, p.mesh.vertices, p.mesh.faces)
    mesh = ReferenceMesh(p.mesh.vertices, p.mesh.faces, path, hashlib.sha256(obj).hexdigest())
    return dataclasses.replace(p, mesh=mesh, obj=obj)


def _auto(whole: Patch, ratio: float, coverage: float, path, make: NetMaker,
          mesh: ReferenceMesh):
    """``--patches auto`` above the limit: bisect the worst patch while it helps (see the
    module); the patch nets, the cuts made and why the splitting stopped. ``coverage``: the
    single net's coverage of the mesh."""
    cuts: list[dict] = []
    current = [(whole, ratio, None, coverage)]
    serial = 0
    while True:
        k = max(range(len(current)), key=lambda i: (_key(current[i][1]), -i))
        patch, worst, _, covered = current[k]
        if worst is not None and worst <= WIDTH_RATIO_LIMIT:
            stop = f"every patch's strips vary at most {WIDTH_RATIO_LIMIT:g}x"
            break
        if len(current) >= MAX_PATCHES:
            stop = f"stopped at {MAX_PATCHES} patches"
            break
        try:
            a, b, curves, rec = bisect(patch)
        except ValueError as err:
            stop = f"the worst patch cannot be cut further ({err})"
            break
        serial += 2
        pa = _patch_net(a, path(serial - 1), make, mesh)
        pb = _patch_net(b, path(serial), make, mesh)
        new = max(_key(pa.width["ratio"]), _key(pb.width["ratio"]))
        both = ((a.area * pa.outcome.coverage + b.area * pb.outcome.coverage)
                / (a.area + b.area))
        gain = both - covered
        if new >= _key(worst) and not (gain >= COVERAGE_GAIN
                                       and new <= _key(worst) * (1 + RATIO_SLACK)):
            stop = (f"cutting the worst patch gives {ratio_text(new)}, no better than "
                    f"{ratio_text(worst)}"
                    + (f", and covers {100 * gain:.1f} % more of it" if gain > 0 else ""))
            break
        cuts.append({"curves": curves, **rec})
        current[k:k + 1] = [(a, pa.width["ratio"], pa, pa.outcome.coverage),
                            (b, pb.width["ratio"], pb, pb.outcome.coverage)]
    if len(current) == 1:
        return [], cuts, stop
    return [c[2] for c in current], cuts, stop


def _key(ratio) -> float:
    return np.inf if ratio is None else float(ratio)
