"""The README stays true: its "Design your own" commands run as typed (a fresh shell with the
`dgpc` command on PATH, in a folder beside the checkout's samples), and every figure it quotes
of them and of the demo is what a run gives, within the precision quoted. The demo is run once
per test run (the ``demo_run`` fixture of conftest.py, shared with the end-mark tests)."""

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.io.net import read_net

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def section(heading: str) -> str:
    """The README's text under ``## heading``, to the next heading of that level."""
    start = README.index(f"\n## {heading}\n")
    end = README.find("\n## ", start + 1)
    return README[start:end if end > 0 else None]


def sh_blocks(text: str) -> list[str]:
    return re.findall(r"```sh\n(.*?)```", text, flags=re.S)


def quoted(pattern: str, text: str = README) -> tuple[str, ...]:
    """The figures the README quotes where ``pattern`` (a regex with one group per figure,
    spaces matching any run of white space) matches, exactly once."""
    regex = re.compile(pattern.replace(" ", r"\s+"))
    found = regex.findall(text)
    assert len(found) == 1, f"{pattern!r} matches {len(found)} times in the README"
    return found[0] if isinstance(found[0], tuple) else (found[0],)


def agrees(text: str, value: float) -> bool:
    """``value`` rounded to the significant digits of the quoted ``text`` is ``text``:
    ``1.24e-4`` holds 1.2403e-4, ``84`` holds 84.15, ``0.57`` holds 0.567. A value on the
    rounding edge may sit a thousandth of itself past it (``4.0e-6`` holds 4.0502e-6), the
    drift another machine's arithmetic may give a figure (the golden tolerances allow more)."""
    mantissa = re.sub(r"[eE].*$", "", text).replace("-", "").replace(".", "").lstrip("0")
    digits = max(len(mantissa), 1)
    quoted_value = float(text)
    half_unit = 0.5 * 10.0 ** (math.floor(math.log10(abs(quoted_value))) - digits + 1) \
        if quoted_value else 0.5 * 10.0 ** -digits
    return (f"{value:.{digits - 1}e}" == f"{quoted_value:.{digits - 1}e}"
            or abs(value - quoted_value) <= half_unit + 1e-3 * abs(value))


def check(kind: str, text: str, value: float, what: str) -> None:
    """One quoted figure against the run: ``eq`` within its precision, ``le``/``lt`` a
    bound."""
    ok = {"eq": lambda: agrees(text, value), "le": lambda: value <= float(text),
          "lt": lambda: value < float(text)}[kind]()
    assert ok, f"the README quotes {what} as {text}; the run gives {value:.6g}"


def inspect(stem, *extra) -> dict:
    return json.loads(dgpc("inspect", stem, *extra).stdout)


# -- Design your own ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def designed(tmp_path_factory):
    """The "Design your own" blocks run as typed by bash, with `dgpc` on PATH (as `make
    install` or the activated .venv give it), in a folder holding the checkout's samples."""
    d = tmp_path_factory.mktemp("design")
    (d / "samples").symlink_to(ROOT / "samples")
    script = "\n".join(sh_blocks(section("Design your own")))
    assert "dgpc init" in script and "dgpc nest" in script
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    run = subprocess.run(["bash", "-e", "-c", script], cwd=d, env=env, capture_output=True,
                         text=True, check=False)
    assert run.returncode == 0, run.stderr
    return d


def test_design_your_own_runs_as_typed(designed):
    d = designed
    for name in ("base.json", "wall.json", "strips.json", "flat.json", "sheets.json",
                 "sheets.sheet01.dxf", "flat-report-index.html"):
        assert (d / name).is_file(), name
    base, wall = read_net(d / "base"), read_net(d / "wall")
    rows, cols = (int(x) for x in quoted(r"`base` is a net of (\d+) × (\d+) vertices"))
    assert base.shape == (rows, cols) and wall.units == "m"
    # the handles as the README explains them: [20, 0] pinned, [0, 12] pulled in by 35 cm
    assert np.allclose(wall.f[20, 0], base.f[20, 0], atol=1e-6)
    pulled = float(quoted(r"pull the bottom-right one in by (\d+) cm")[0]) / 100
    assert np.allclose(wall.f[0, 12] - base.f[0, 12], [-pulled, 0, 0], atol=1e-6)
    assert wall.status["state"] == "converged"


def test_the_exit_3_example_gives_the_figures_quoted(designed, tmp_path):
    """"Pinning the other three corners, with the same drag": exit 3, and the strain and gpc
    angle defect the README quotes."""
    handles = json.loads((designed / "handles.json").read_text())["handles"]
    held = {tuple(h["index"]) for h in handles}
    corners = [[20, 0], [20, 12], [0, 0], [0, 12]]
    handles += [{"index": c, "offset": [0, 0, 0]} for c in corners if tuple(c) not in held]
    assert len(handles) == 4
    (tmp_path / "h.json").write_text(json.dumps({"handles": handles}))
    r = dgpc("optimize", designed / "base", "--mode", "isometric", "--handles",
             tmp_path / "h.json", "--steps", 5, "-o", tmp_path / "wall", expect=3)
    assert "missed tolerance: strain" in r.stderr and "> --max-strain" in r.stderr
    strain, defect = quoted(r"with the same drag, does that \(strain (\S+) > 3e-4, and a gpc "
                            r"angle defect of (\S+) rad > 1e-4\)")
    m = inspect(tmp_path / "wall", "--against", designed / "base")
    check("eq", strain, m["strain"]["max"], "the strain of the exit-3 example")
    check("eq", defect, m["gpc_angle_defect_max"], "its gpc angle defect")


def test_the_cone_example_gives_one_template(tmp_path):
    """"A net isometric to a surface of revolution gives one class": the README's cone block,
    run as typed, its strips on one template."""
    block, = [b for b in sh_blocks(README) if "--profile cone" in b]
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    run = subprocess.run(["bash", "-e", "-c", block], cwd=tmp_path, env=env,
                         capture_output=True, text=True, check=False)
    assert run.returncode == 0 and "warning" not in run.stderr, run.stderr
    strips, = quoted(r"cone-fig-overlay\.png: the (\d+) strips on one template")
    metrics = inspect(tmp_path / "cone-flat")
    assert metrics["n_classes"] == 1 and metrics["n_parts"] == int(strips)
    assert (tmp_path / "cone-fig-overlay.png").is_file()


# -- the demo -------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def demo(demo_run):
    d = demo_run
    return {"dir": d, "wall": inspect(d / "wall", "--against", d / "base"),
            "strips": inspect(d / "strips"), "flat": inspect(d / "flat"),
            "sheets": inspect(d / "sheets"),
            "flat_doc": json.loads((d / "flat.json").read_text())}


def test_what_the_demo_builds(demo):
    d, flat = demo["dir"], demo["flat"]
    intro = section("Quick start")
    tall = quoted(r"a timber wall (\d+) m tall", intro)[0]
    z = read_net(d / "wall").f[..., 2]
    check("eq", tall, float(np.ptp(z)), "the wall's height (m)")
    strips, = quoted(r"clad with (\d+) geodesic strips cut from one template", intro)
    within, = quoted(r"developed outlines agree within (\S+) mm\)", intro)
    assert flat["n_parts"] == int(strips) and flat["n_classes"] == 1
    check("le", within, flat["max_congruence_deviation_mm"], "the outlines' agreement (mm)")
    w, h = quoted(r"cut from (\S+) × (\S+) m LVL panels", intro)
    sheet = json.loads((d / "sheets.json").read_text())["parameters"]["sheet"]
    assert sheet == f"{float(w) * 1000:g}x{float(h) * 1000:g}"
    copies, = quoted(r"one template of (\d+) copies", intro)
    classes = demo["flat_doc"]["data"]["classes"]
    assert [c["quantity"] for c in classes] == [int(copies)]
    first, last = quoted(r"`(flat\.C01\.S-v\d+\.dxf)` … `(flat\.C01\.S-v\d+\.dxf)`", intro)
    assert (d / first).is_file() and (d / last).is_file()
    assert sorted(p.name for p in d.glob("flat.C01.S-v*.dxf"))[-1] == last
    for name in ("sheets.sheet01.dxf", "sheets.sheet02.dxf", "sheets.parts.csv",
                 "flat.parts.csv", "report-index.html", "wall.obj"):
        assert (d / name).is_file(), name


def test_the_demo_row_of_the_pipelines_table(demo):
    wall, strips, flat, sheets = demo["wall"], demo["strips"], demo["flat"], demo["sheets"]
    fab = strips["fabrication"]
    R, strain, off = quoted(r"\| `timber-cladding` \(21×13\) \| R; max strain \| [^|]+\| "
                            r"≤ (\S+); (\S+) \(rows (\S+) % off circles\) \|")
    check("le", R, wall["R"], "R")
    check("eq", strain, wall["strain"]["max"], "the demo's max strain")
    check("eq", off, 100 * wall["parallel_departure"]["relative"], "rows off circles (%)")
    n_cls, n_parts, within, dev_mm, dev_pct, seam_mm, seam_pct, gaps, area = quoted(
        r"one template: (\d+) class of (\d+), outlines within (\S+) mm; deviation from the "
        r"net (\S+) mm \((\S+) % of the width\), seam step (\S+) mm \((\S+) %\), end gaps "
        r"< (\S+) mm, parts' area = the net's × \(1 \+ (\S+)\) \|")
    assert flat["n_classes"] == int(n_cls) and flat["n_parts"] == int(n_parts)
    check("le", within, flat["max_congruence_deviation_mm"], "the outlines' agreement")
    check("eq", dev_mm, fab["max_deviation_mm"], "the deviation (mm)")
    check("eq", dev_pct, 100 * fab["max_deviation_relative"], "the deviation (%)")
    check("eq", seam_mm, fab["max_seam_step_mm"], "the seam step (mm)")
    check("eq", seam_pct, 100 * fab["max_seam_step_relative"], "the seam step (%)")
    check("lt", gaps, fab["max_end_gap_mm"], "the end gaps (mm)")
    check("eq", area, fab["area_ratio"] - 1, "the parts' area over the net's, less 1")
    count, use = quoted(r"\| cut sheets \(6\.1 × 2\.5 m\) \| — \| (\d+) sheets, utilization "
                        r"(\d+) % \|")
    assert sheets["sheet_count"] == int(count)
    check("eq", use, 100 * sheets["utilization"], "the utilization (%)")


def test_the_demo_wall_in_the_strips_tables(demo):
    fab = demo["strips"]["fabrication"]
    dev, seam = quoted(r"\| demo wall \| \*\*0\.02 \(default\)\*\* \| \*\*0\.01\*\* \| "
                       r"\*\*(\S+) %\*\* \| \*\*(\S+) %\*\* \|")
    check("eq", dev, 100 * fab["max_deviation_relative"], "the default's deviation (%)")
    check("eq", seam, 100 * fab["max_seam_step_relative"], "the default's seam step (%)")
    dev, quads, seam, ratio = quoted(r"\| demo wall \| 1 \| (\S+) % \| (\S+) % \| (\S+) % \| "
                                     r"(\S+) \|")
    check("eq", dev, 100 * fab["max_deviation_relative"], "K = 1 deviation (%)")
    check("eq", quads, 100 * fab.get("net_quads_max_deviation_relative",
                                     fab["max_deviation_relative"]), "against the net's quads")
    check("eq", seam, 100 * fab["max_seam_step_relative"], "K = 1 seam step (%)")
    check("eq", ratio, fab["max_side_ratio"], "the largest side ratio")
    dev, seam = quoted(r"keeps K = 1 for the demo wall \((\S+) % / (\S+) %\)")
    check("eq", dev, 100 * fab["max_deviation_relative"], "--refine auto's deviation (%)")
    check("eq", seam, 100 * fab["max_seam_step_relative"], "--refine auto's seam step (%)")
    assert json.loads((demo["dir"] / "strips.json").read_text())["parameters"].get(
        "refine", 1) == 1


def test_the_demo_wall_in_the_unfold_text(demo):
    classes = demo["flat_doc"]["data"]["classes"]
    far, = quoted(r"on the demo wall a copy's rulings lie up to (\d+) mm from the template's")
    check("eq", far, max(c["score_deviation_mm"] for c in classes), "score_deviation_mm")
    below, = quoted(r"round-off \(below (\S+) mm on the demo wall and Gehry facade 1\)")
    check("lt", below, demo["flat"]["max_congruence_deviation_mm"], "the copies' agreement")


@pytest.mark.parametrize("text, value, ok", [("1.24e-4", 1.2403e-4, True),
                                             ("1.4e-4", 1.2403e-4, False),
                                             ("84", 84.153, True), ("0.57", 0.567, True),
                                             ("0.76", 0.567, False), ("306", 305.945, True),
                                             ("4.0e-6", 4.0038e-6, True),
                                             ("3.5e-6", 4.0038e-6, False)])
def test_the_precision_rule(text, value, ok):
    assert agrees(text, value) == ok


def test_make_demo_ends_with_how_dgpc_is_reached(demo_run):
    lines = (demo_run.parent / "make-demo.log").read_text().strip().splitlines()
    assert lines[-1].startswith("dgpc: ")
    assert ("source" in lines[-1] and "make install" in lines[-1]) or "on your PATH" in lines[-1]
