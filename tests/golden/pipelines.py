"""What the golden tests run and record: small versions of every pipeline (pipelines/*.mk).

``run(name, out)`` runs ``make pipeline-NAME OUT=out ROWS=.. COLS=..`` from the repository
root; ``collect(name, out)`` reads the artifacts into a reviewable, JSON-able dict:

- ``metrics``: key figures from ``dgpc inspect`` (SPEC §8);
- ``counts``: integers (parts, classes, sheets, mold pieces, laths), compared exactly;
- ``nets``: the final nets' coordinates;
- ``dxf``: DXF entity counts by layer and type (re-read with ezdxf), compared exactly.

The tolerance of every figure, and its reason, is in ``tolerances.py``: each comes from the
stopping rule of the stage that made it; ``compare`` applies them.
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
import numpy as np
from click.testing import CliRunner
from tolerances import FLOOR, tolerances

from dgpc_cli.cli.main import cli
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net, write_net
from dgpc_cli.metrics.hausdorff import hausdorff

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).resolve().parent
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
    "bowling-pin-clairaut": [],             # a family of fits: see tolerances.py
    "gridshell": ["a", "b"],
    "gallery": [f"{s}-net" for s in GALLERY],
}


#: pipeline -> the nets its first stage (init) makes, which every later stage starts from
INPUTS = {
    "gehry-facade": ["base"],
    "timber-cladding": ["base"],
    "felt-developable": ["init"],
    "bowling-pin-clairaut": ["init"],
    "gridshell": ["a0", "b0"],
    "gallery": [f"{s}-base" for s in GALLERY],
}


def _env(env: dict | None = None) -> dict:
    return {**os.environ, **(env or {}),
            "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}


def _make(targets: list[str], name: str, out: Path, env: dict | None) -> None:
    subprocess.run(["make", "-s", "-j2", "-o", ".venv/.installed", *targets,
                    *make_args(name, out)],
                   cwd=ROOT, check=True, env=_env(env), stdout=subprocess.DEVNULL)


def planned(name: str, out: Path) -> list[list[str]]:
    """The dgpc commands ``make -n pipeline-NAME`` would run now (what is out of date), each as
    its words from the subcommand on."""
    text = subprocess.run(["make", "-n", "-o", ".venv/.installed", f"pipeline-{name}",
                           *make_args(name, out)],
                          cwd=ROOT, check=True, env=_env(), capture_output=True,
                          text=True).stdout
    return [line.split()[2:] for line in text.splitlines() if "/dgpc -q " in line]


def _without_figures(name: str, out: Path) -> list[str]:
    """The make arguments that run pipeline ``name`` into ``out`` without its report pages
    (``dgpc report STEM... -o P`` writes ``P-index.html``): each page taken as made, the
    artifacts it would draw asked for by name."""
    args = []
    for words in planned(name, out):
        if words[0] == "report":
            at = words.index("-o")
            args += ["-o", f"{words[at + 1]}-index.html", *(f"{s}.json" for s in words[1:at])]
    return args


#: The pipelines whose golden runs draw their figures too (``make pipeline-NAME``): the demo's,
#: and the facade's (tests/test_pipeline_dxf.py reads its mold's page). The report stage has
#: tests of its own (tests/test_report_*.py); the figures of the other pipelines would cost a
#: third of their runs and are not compared.
FIGURES = {"timber-cladding", "gehry-facade"}


def run(name: str, out: Path, *, perturb: float = 0.0, env: dict | None = None,
        figures: bool | None = None) -> Path:
    """Run the small version of pipeline ``name`` into ``out``; returns ``out/NAME``.

    ``perturb``: every coordinate of the input nets (``INPUTS``, what init made) moves by up
    to this fraction of the net's bounding-box diagonal (uniform, seeded) before the later
    stages run. ``env``: extra environment of every stage. ``figures``: whether the report
    figures are drawn too (the golden record does not read them; default: ``FIGURES``)."""
    d = out / name
    if perturb:
        _make([str(d / f"{stem}.json") for stem in INPUTS[name]], name, out, env)
        rng = np.random.default_rng(12)
        for stem in INPUTS[name]:
            net = read_net(d / stem)
            diagonal = float(np.linalg.norm(np.ptp(net.f.reshape(-1, 3), axis=0)))
            net.f = net.f + perturb * diagonal * rng.uniform(-1.0, 1.0, net.f.shape)
            write_net(d / stem, net, force=True)
    draw = figures if figures is not None else name in FIGURES
    _make([f"pipeline-{name}", *([] if draw else _without_figures(name, out))], name, out, env)
    return d


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
    tol = tolerances(name, METRICS[name])
    return {
        "pipeline": name,
        "size": list(SIZES[name]),
        "tolerances": {"metrics": {k: [t.kind, t.value, t.why] for k, t in tol["metrics"].items()},
                       "coordinates": [tol["coordinates"].kind, tol["coordinates"].value,
                                       tol["coordinates"].why],
                       "floor": FLOOR, "counts": "exact", "dxf": "exact",
                       "reasons": "tests/golden/tolerances.py"},
        "metrics": {k: float(get(*v)) for k, v in METRICS[name].items()},
        "counts": {k: int(get(*v)) for k, v in COUNTS[name].items()},
        "nets": {stem: read_net(d / stem).f.tolist() for stem in NETS[name]},
        "dxf": dxf,
        "json": json_skeletons(d),
    }


def compare(name: str, got: dict, want: dict, *, drift: bool = False
            ) -> dict[str, tuple[float, float]]:
    """``{figure: (deviation, tolerance)}`` of the records ``got`` against ``want`` of pipeline
    ``name``, with the tolerances of ``tolerances.py`` (a net's deviation: its largest vertex
    distance over its bbox diagonal; an upper bound's: its value, or with ``drift`` its
    distance from ``want``'s). Figures at round-off (``FLOOR``) and those compared with kind
    ``none`` are left out."""
    tol = tolerances(name, METRICS[name])
    out = {}
    for key, w in want["metrics"].items():
        t, g = tol["metrics"][key], got["metrics"][key]
        if t.kind == "none" or max(abs(g), abs(w)) <= FLOOR:
            continue
        if t.kind == "max":
            out[key] = (abs(g - w) if drift else g, t.value)
        else:
            out[key] = (abs(g - w) / max(abs(g), abs(w)), t.value)
    t = tol["coordinates"]
    for stem, w in want["nets"].items():
        if t.kind == "none":
            continue
        w, g = np.asarray(w), np.asarray(got["nets"][stem])
        diagonal = np.linalg.norm(np.ptp(w.reshape(-1, 3), axis=0))
        out[f"net {stem}"] = (float(np.abs(g - w).max() / diagonal) if g.shape == w.shape
                              else np.inf, t.value)
    return out


_NUMERAL = re.compile(r"\d+(\.\d+)?([eE][-+]?\d+)?")
_SHA256 = re.compile(r"^[0-9a-f]{64}$")


def _skeleton(x):
    """``x`` with every number masked (they differ between CPUs in their last digits, and are
    compared above with their tolerances), lists of numbers and of such lists (points,
    outlines: how many points an outline has follows its numbers) masked whole, sha256 values
    and numerals in strings masked, a path
    out of the pipeline's folder reduced to its file name, and the items of a list of objects
    deduplicated (their number follows the numbers)."""
    if isinstance(x, dict):
        return {k: _skeleton(v) for k, v in sorted(x.items())}
    if isinstance(x, list):
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in x):
            return "<numbers>"
        items = [_skeleton(v) for v in x]
        if items and all(v in ("<numbers>", "<arrays>") for v in items):
            return "<arrays>"         # points, outlines: how many follows the numbers
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
