"""What the golden tests run and record: small versions of every pipeline (pipelines/*.mk).

``run(name, out)`` runs ``make pipeline-NAME OUT=out ROWS=.. COLS=..`` from the repository
root; ``collect(name, out)`` reads the artifacts into a reviewable, JSON-able dict:

- ``metrics``: key figures from ``dgpc inspect`` (SPEC §8), compared with relative tolerance
  ``rel_tol(name, key)`` — or both at most ``FLOOR`` (residual-type numbers at solver noise
  level);
- ``counts``: integers (parts, classes, sheets, mold pieces, laths), compared exactly;
- ``nets``: the final nets' coordinates, compared within ``coord_tol(name)`` × bbox diagonal;
- ``dxf``: DXF entity counts by layer and type (re-read with ezdxf), compared exactly.

Tolerances follow how well each figure is determined by the pipeline's inputs. A net that
meets hard constraints only (isometric deformations, the fits whose approximation term is
hard) is fixed to rounding: ``REL`` and ``COORD_REL``. A fit whose vertices may slide along
the reference (the gridshell's gpc fit beyond its reference) or whose figure mixes in a soft
term (the felt's nearly developable fit) stops where its soft terms stop falling; that point
moves with the last bits of the arithmetic, which differ between CPUs (OpenBLAS, bundled in
numpy's and scipy's wheels, picks its kernels by CPU: another kernel sums in another order).
``spread.py`` measures it by running every pipeline with another OpenBLAS kernel; the
tolerances below are ten times or more what it measured (figures in the comments).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

import ezdxf
from click.testing import CliRunner

from dgpc_cli.cli.main import cli
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net
from dgpc_cli.metrics.hausdorff import hausdorff

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).resolve().parent
REL, FLOOR, COORD_REL = 1e-6, 1e-8, 1e-9

#: Relative tolerances of the figures of soft fits (measured with another OpenBLAS kernel:
#: felt R 2.6e-7, congruence 7.1e-5; gridshell Hausdorff 1.7e-2 and 4.5e-4, coverage 1.7e-4).
SOFT_REL = {
    "felt-developable": {"R": 1e-4, "congruence_error": 1e-2},
    "gridshell": {"hausdorff_over_diagonal_a": 0.2, "hausdorff_over_diagonal_b": 0.2,
                  "coverage_a": 5e-3, "coverage_b": 5e-3},
}
#: Coordinate tolerances (× bbox diagonal) of soft fits (measured: felt 1.2e-9, gridshell
#: 5.6e-4: its vertices slide along the reference, the surface they span stays put).
SOFT_COORD = {"felt-developable": 1e-7, "gridshell": 1e-2}


#: Upper bounds of the figures of a fit whose solution is a family rather than one net: the
#: twisted net on the bowling pin may turn about the pin's axis and slide along its geodesics
#: while staying a gpc net on it, and the last bits of its start pick the member (1e-15
#: perturbations of the 21×11 start moved the fitted vertices by 3–8 % of the diagonal, the
#: largest relative Clairaut MAD 2.4e-3–4.8e-3, Hausdorff 0.8e-3–2.1e-3 of the diagonal, R
#: 4e-13–2.6e-9). What the pipeline verifies is bounded instead: R within its --tol, Clairaut's
#: r cos α constant within 1 %, the net on the pin; its coordinates are not compared.
BOUNDS = {
    "bowling-pin-clairaut": {"R": 1e-8, "clairaut_max_relative_mad": 1e-2,
                             "hausdorff_over_diagonal": 5e-3},
}


def rel_tol(name: str, key: str) -> float:
    """Relative tolerance of metric ``key`` of pipeline ``name``."""
    return SOFT_REL.get(name, {}).get(key, REL)


def coord_tol(name: str) -> float:
    """Tolerance of the final nets' coordinates of pipeline ``name``, × bbox diagonal."""
    return SOFT_COORD.get(name, COORD_REL)

#: pipeline -> (ROWS, COLS) of its small version; the handle files of these sizes are in samples/.
SIZES = {
    "gehry-facade": (9, 7),
    "timber-cladding": (9, 7),
    "felt-developable": (9, 7),
    "bowling-pin-clairaut": (21, 11),
    "gridshell": (15, 11),
    "gallery": (9, 7),
}
#: Make variables of the small versions: a 9×7 net is far stiffer than a 21×13 one, so the
#: designers' drags reach strains up to 1.1e-3 and gpc defects up to 3.4e-4 rad there (at the
#: default sizes: 2.2e-4 and 8.3e-5, within the defaults 3e-4 and 1e-4).
SMALL_VARS = {name: {"MAX_STRAIN": "2e-3", "GPC_TOL": "5e-4"}
              for name in ("gehry-facade", "timber-cladding", "gallery")}


def make_args(name: str, out: Path) -> list[str]:
    """The make variables of the small version of pipeline ``name`` writing into ``out``."""
    rows, cols = SIZES[name]
    extra = [f"{k}={v}" for k, v in SMALL_VARS.get(name, {}).items()]
    return [f"OUT={out}", f"ROWS={rows}", f"COLS={cols}", f"BIN={Path(sys.executable).parent}",
            *extra]

#: The gallery's shapes (pipelines/gallery.mk).
GALLERY = ("sphere-zone", "cylinder", "catenoid", "sphere", "bowling-pin", "wall")

#: pipeline -> {metric name: (artifact stem, key path in `dgpc inspect` JSON)}
METRICS = {
    "gehry-facade": {
        **{f"R_facade_{k}": (f"facade-{k}", "R") for k in range(1, 5)},
        **{f"max_strain_facade_{k}": (f"facade-{k}", "strain.max") for k in range(1, 5)},
        **{f"pleat_facade_{k}": (f"facade-{k}", "pleat_max") for k in range(1, 5)},
        **{f"departure_facade_{k}": (f"facade-{k}", "parallel_departure.relative")
           for k in range(1, 5)},
        "mold_isometry_error_max": ("mold", "isometry_error_max"),
        "mold_radius_max": ("mold", "radius_max"),
        "mold_height": ("mold", "height"),
        "utilization": ("sheets", "utilization"),
    },
    "timber-cladding": {
        "R": ("wall", "R"),
        "max_strain": ("wall", "strain.max"),
        "congruence_error": ("flat", "max_congruence_error"),
        "flat_max_strain": ("flat", "max_strain"),
        "utilization": ("sheets", "utilization"),
    },
    "felt-developable": {
        "R": ("felt", "R"),
        "jacobi_residual_max": ("felt", "jacobi_residual_max"),
        # developable mode keeps no reference: measured against the sample mesh here
        "hausdorff_over_diagonal": ("felt", "@samples/meshes/felt.obj"),
        "congruence_error": ("flat", "max_congruence_error"),
        "flat_max_strain": ("flat", "max_strain"),
    },
    "bowling-pin-clairaut": {
        "R": ("pin", "R"),
        "clairaut_max_relative_mad": ("pin", "clairaut.max_relative_mad"),
        "hausdorff_over_diagonal": ("pin", "hausdorff.net_to_reference_max/hausdorff.diagonal"),
    },
    "gallery": {
        **{f"max_strain_{s}": (f"{s}-net", "strain.max") for s in GALLERY},
        **{f"departure_{s}": (f"{s}-net", "parallel_departure.relative") for s in GALLERY},
        **{f"mold_error_{s}": (f"{s}-mold", "isometry_error_max") for s in GALLERY},
    },
    "gridshell": {
        "R_a": ("a", "R"),
        "R_b": ("b", "R"),
        # the nets run beyond the reference (--extend): it is covered, measured from it
        "hausdorff_over_diagonal_a": ("a", "hausdorff.reference_to_net_max/hausdorff.diagonal"),
        "hausdorff_over_diagonal_b": ("b", "hausdorff.reference_to_net_max/hausdorff.diagonal"),
        "coverage_a": ("a", "coverage.area_fraction"),
        "coverage_b": ("b", "coverage.area_fraction"),
    },
}

#: pipeline -> {count name: (artifact stem, key path)}
COUNTS = {
    "gehry-facade": {"mold_pieces": ("mold", "pieces"), "mold_panels": ("mold", "panels"),
                     "panels_flat": ("mold", "panels_flat"), "parts": ("sheets", "n_parts"),
                     "sheets": ("sheets", "sheet_count")},
    "timber-cladding": {"classes": ("flat", "n_classes"), "parts": ("sheets", "n_parts"),
                        "sheets": ("sheets", "sheet_count")},
    "felt-developable": {"classes": ("flat", "n_classes"), "parts": ("flat", "n_parts")},
    "bowling-pin-clairaut": {},
    "gridshell": {},
    "gallery": {f"classes_{s}": (f"{s}-flat", "n_classes") for s in GALLERY},
}

#: pipeline -> final nets (their coordinates are recorded)
NETS = {
    "gehry-facade": [f"facade-{k}" for k in range(1, 5)],
    "timber-cladding": ["wall"],
    "felt-developable": ["felt"],
    "bowling-pin-clairaut": [],             # a family of fits: see BOUNDS
    "gridshell": ["a", "b"],
    "gallery": [f"{s}-net" for s in GALLERY],
}


def run(name: str, out: Path) -> Path:
    """Run the small version of pipeline ``name`` into ``out``; returns ``out/NAME``."""
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    subprocess.run(["make", "-s", "-j2", "-o", ".venv/.installed", f"pipeline-{name}",
                    *make_args(name, out)],
                   cwd=ROOT, check=True, env=env, stdout=subprocess.DEVNULL)
    return out / name


def inspect(stem: Path) -> dict:
    result = CliRunner().invoke(cli, ["inspect", str(stem)], catch_exceptions=False)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


def lookup(doc: dict, path: str):
    if "/" in path:
        a, b = path.split("/")
        return lookup(doc, a) / lookup(doc, b)
    for key in path.split("."):
        doc = doc[key]
    return doc


def _inspect_stem(stem: Path) -> dict:
    """`dgpc inspect`, with --against the pipeline's initial net for the strain of a deformation."""
    base = stem.parent / "base.json"
    if stem.name.endswith("-net"):                  # the gallery's shapes
        base = stem.parent / f"{stem.name[:-4]}-base.json"
    args = ["inspect", str(stem)]
    if stem.name.startswith(("facade-", "wall")) or stem.name.endswith("-net"):
        if base.exists():
            args += ["--against", str(base.with_suffix(""))]
    result = CliRunner().invoke(cli, args, catch_exceptions=False)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


def collect(name: str, d: Path) -> dict:
    """The golden record of pipeline ``name`` whose artifacts are in ``d``."""
    docs: dict[str, dict] = {}

    def get(stem, path):
        if path.startswith("@"):
            mesh = load_mesh(ROOT / path[1:])
            h = hausdorff(read_net(d / stem).f, mesh.vertices, mesh.faces)
            return h["net_to_reference_max"] / h["diagonal"]
        if stem not in docs:
            docs[stem] = _inspect_stem(d / stem)
        return lookup(docs[stem], path)

    dxf = {}
    for path in sorted(d.glob("*.dxf")):
        counter = Counter(f"{e.dxf.layer}:{e.dxftype()}" for e in ezdxf.readfile(path).modelspace())
        dxf[path.name] = dict(sorted(counter.items()))
    return {
        "pipeline": name,
        "size": list(SIZES[name]),
        "tolerances": {"metrics_rel": {k: rel_tol(name, k) for k in METRICS[name]
                                       if k not in BOUNDS.get(name, {})},
                       "metrics_upper_bound": BOUNDS.get(name, {}),
                       "metrics_floor": FLOOR,
                       "coordinates_rel_to_bbox_diagonal": coord_tol(name), "counts": "exact",
                       "dxf": "exact"},
        "metrics": {k: float(get(*v)) for k, v in METRICS[name].items()},
        "counts": {k: int(get(*v)) for k, v in COUNTS[name].items()},
        "nets": {stem: read_net(d / stem).f.tolist() for stem in NETS[name]},
        "dxf": dxf,
        "json": json_skeletons(d),
    }


_NUMERAL = re.compile(r"\d+(\.\d+)?([eE][-+]?\d+)?")
_SHA256 = re.compile(r"^[0-9a-f]{64}$")


def _skeleton(x):
    """``x`` with every number masked (they differ between CPUs in their last digits, and are
    compared above with their tolerances), sha256 values and numerals in strings masked, a path
    out of the pipeline's folder reduced to its file name, and the items of a list of objects
    deduplicated (their number follows the numbers)."""
    if isinstance(x, dict):
        return {k: _skeleton(v) for k, v in sorted(x.items())}
    if isinstance(x, list):
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in x):
            return "<numbers>"
        items = [_skeleton(v) for v in x]
        if all(isinstance(v, dict) for v in x):
            unique = {json.dumps(v, sort_keys=True): v for v in items}
            return [unique[k] for k in sorted(unique)]
        return items
    if isinstance(x, bool) or x is None:
        return x
    if isinstance(x, (int, float)):
        return "<number>"
    if _SHA256.match(x) or x == "<sha256>":
        return "<sha256>"
    if x.startswith(("../", "/")):   # a file outside the pipeline's folder (samples/, the
        x = "<outside>/" + x.rsplit("/", 1)[-1]   # checkout): where it lies is the machine's
    return _NUMERAL.sub("#", x)


def json_skeleton(path: Path) -> dict:
    """What the golden records of an artifact JSON besides its numbers: its kind, version,
    inputs (paths relative to the artifact's folder), parameters, data and the names of its
    metrics, and its state; a path stored as typed, or a key lost, changes it."""
    doc = json.loads(path.read_text())
    status = doc.get("status", {})
    return _skeleton({**{k: doc[k] for k in ("kind", "schema_version", "created_by", "inputs",
                                             "parameters", "data")},
                      "metrics": sorted(doc.get("metrics", {})),
                      "status": {"state": status.get("state")}})


def json_skeletons(d: Path) -> dict:
    """:func:`json_skeleton` of every artifact JSON of a pipeline's folder ``d``."""
    out = {}
    for path in sorted(d.glob("*.json")):
        doc = json.loads(path.read_text())
        if isinstance(doc, dict) and "schema_version" in doc and "kind" in doc:
            out[path.name] = json_skeleton(path)
    return out


def dumps(doc: dict) -> str:
    return json.dumps(doc, indent=1, sort_keys=True) + "\n"
