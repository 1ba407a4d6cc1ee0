"""Units and options without traps: the unit init assumes is said, every length option takes a
unit and every help line shows its unit and range, usage errors exit 2, one meaning per option
name, extract-mold says which surface of revolution it builds, errors name the next step."""

import json
import re

import click
import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.cli.length import LengthParam
from dgpc_cli.cli.main import COMMANDS, cli
from dgpc_cli.io.net import read_net

#: Options that are lengths (or files of lengths) wherever they appear, whatever their type.
LENGTH_OPTIONS = {"--spacing", "--gap", "--margin", "--stock-length", "--stagger",
                  "--mold-max-length", "--sheet", "--kerf", "--tool-diameter", "--handles"}
#: Options that are angles: their help names degrees or radians.
ANGLE_OPTIONS = {"--angle", "--span", "--twist", "--flat-angle", "--rotations"}
UNIT = re.compile(r"\b(mm|cm|m|in|ft)\b|unit")


def _help_records(name):
    ctx = click.Context(cli, info_name="dgpc")
    command = cli.get_command(ctx, name)
    sub = click.Context(command, info_name=name, parent=ctx)
    for param in command.params:
        if isinstance(param, click.Option) and not param.hidden:
            record = param.get_help_record(sub)
            if record is not None:
                yield param, record[0], " ".join(record[1].split())


def help_faults(name) -> list[str]:
    """What a user reading ``dgpc NAME --help`` would miss: a length without its unit, an angle
    without degrees or radians, a number without its range, a range with None in it."""
    faults = []
    for param, opts, text in _help_records(name):
        names = set(param.opts) | set(param.secondary_opts)
        if "None" in text:
            faults.append(f"{opts}: 'None' in {text!r}")
        if (isinstance(param.type, LengthParam) or names & LENGTH_OPTIONS) \
                and not UNIT.search(text):
            faults.append(f"{opts}: a length without its unit: {text!r}")
        if names & ANGLE_OPTIONS and not re.search(r"deg|radian", text, re.IGNORECASE):
            faults.append(f"{opts}: an angle without degrees or radians: {text!r}")
        if isinstance(param.type, (click.types.FloatParamType, click.types.IntParamType)):
            bounded = isinstance(param.type, click.types._NumberRangeBase) and (
                param.type.min is not None or param.type.max is not None)
            if not bounded:
                faults.append(f"{opts}: a number without its range: {text!r}")
    return faults


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_help_line_shows_its_unit_and_range(name):
    assert help_faults(name) == []


def test_the_help_says_what_a_user_must_know():
    text = " ".join(dgpc("init", "--help").stdout.split())
    assert "None" not in text
    assert "required with --surface" in text and "5 mm by default" in text
    assert "net's unit" in " ".join(dgpc("optimize", "--help").stdout.split())
    mold = " ".join(dgpc("extract-mold", "--help").stdout.split())
    assert "--revolution-tol" in mold and "--expect-units" in mold and "lathe" in mold
    assert "--tol " not in mold and "--units " not in mold           # the old names: hidden


def test_init_without_units_says_the_unit_and_size(tmp_path):
    r = dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 5, "--cols",
             5, "--span", 90, "-o", tmp_path / "a")
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and "no --units given" in lines[0] and "in mm" in lines[0]
    f = read_net(tmp_path / "a").f
    height = np.ptp(f[..., 2])
    assert f"× {height:.3g} mm" in lines[0] and "--units m" in lines[0]
    r = dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 5, "--cols",
             5, "--units", "m", "-o", tmp_path / "b")
    assert r.stderr == ""
    # a mesh too
    mesh = tmp_path / "m.obj"
    mesh.write_text("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    r = dgpc("init", mesh, "--method", "project", "--direction", "0,0,1", "--rows", 4,
             "--cols", 4, "-o", tmp_path / "c")
    assert "no --units given: the net is in mm, 2 × 1 × 0 mm" in r.stderr


@pytest.mark.parametrize("option, value, words", [
    ("--span", 400, ["'--span'", "0<x<=360"]),
    ("--span", 0, ["'--span'", "0<x<=360"]),
    ("--angle", 400, ["'--angle'", "-360<=x<=360"]),
    ("--twist", 2000, ["'--twist'", "-1000.0<=x<=1000.0"]),
])
def test_an_option_out_of_its_range_is_a_usage_error(tmp_path, option, value, words):
    args = (["--surface", "revolution", "--profile", "catenoid", "--rows", 5, "--cols", 5]
            if option != "--angle" else [tmp_path / "m.obj", "--method", "project"])
    r = dgpc("init", *args, option, value, "-o", tmp_path / "n", expect=2)
    assert len(r.stderr.splitlines()) == 1 and all(w in r.stderr for w in words), r.stderr
    assert not list(tmp_path.iterdir())


def test_usage_errors_exit_2(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 5, "--cols", 5,
         "--units", "m", "-o", tmp_path / "n")
    r = dgpc("optimize", tmp_path / "n", "--mode", "isometric", "-o", tmp_path / "o", expect=2)
    assert "needs --handles" in r.stderr
    dgpc("init", tmp_path / "x.obj", "--method", "project", "--direction", "1,a,0",
         "-o", tmp_path / "p", expect=2)


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """The catenoid wall of the trap: a quarter turn, r 1.5-3.04 m, 4 m tall."""
    d = tmp_path_factory.mktemp("wall")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 90, "--units", "m", "-o", d / "wall")
    return d


def _radii(stem):
    doc = json.loads(stem.with_suffix(".json").read_text())
    return np.array(doc["data"]["profile"]["r"]), doc


def test_extract_mold_builds_the_designs_own_surface_by_default(wall):
    design = dgpc("extract-mold", wall / "wall", "-o", wall / "design")
    r, doc = _radii(wall / "design")
    f = read_net(wall / "wall").f
    r_net = np.hypot(f[:, 0, 0], f[:, 0, 1])                   # the wall's own radii
    assert np.allclose(r, r_net, rtol=1e-9) and 1.49 < r.min() < 1.51 and r.max() > 3.0
    assert doc["data"]["lambda"] == 4.0 and doc["parameters"]["lambda"] == "design"
    assert abs(doc["metrics"]["height"] - 4.0) < 1e-9
    line = design.stderr.strip()
    assert len(line.splitlines()) == 1 and "design's own surface" in line and "90°" in line
    assert "r 1.5–3.04 m" in line and "--lambda compact" in line and "lathe" in line
    # asked for: the compact full-turn mold, a quarter of the radii, and it says so
    assert dgpc("extract-mold", wall / "wall", "--lambda", "design", "-o", wall / "d2").stderr \
        == design.stderr
    compact = dgpc("extract-mold", wall / "wall", "--lambda", "compact", "-o", wall / "compact")
    r1, doc1 = _radii(wall / "compact")
    assert doc1["data"]["lambda"] == 1.0 and r1.max() < 0.8 and doc1["metrics"]["height"] > 5
    assert "full-turn surface" in compact.stderr and "λ = 4" in compact.stderr
    value = dgpc("extract-mold", wall / "wall", "--lambda", 2, "-o", wall / "two")
    assert _radii(wall / "two")[1]["data"]["lambda"] == 2.0 and "--lambda" in value.stderr
    r = dgpc("extract-mold", wall / "wall", "--lambda", "huge", "-o", wall / "x", expect=2)
    assert "not a finite number > 0, nor design or compact" in r.stderr


def test_lengths_take_units_and_are_recorded_in_the_artifacts_unit(wall):
    dgpc("extract-mold", wall / "wall", "--panel-size", 2, "--mold-max-length", "2500mm",
         "-o", wall / "pieces")
    doc = json.loads((wall / "pieces.json").read_text())
    assert doc["parameters"]["mold_max_length"] == 2.5
    assert max(p["meridian_length"] for p in doc["data"]["pieces"]) <= 2.5


def test_a_plain_mold_max_length_meant_in_millimetres_is_a_usage_error(wall, tmp_path):
    """``--mold-max-length 2500`` on a net in metres is 2500 m, longer than the whole mold,
    where 2500 mm would cut it: exit 2, one line naming both readings, nothing written."""
    r = dgpc("extract-mold", wall / "wall", "--panel-size", 2, "--mold-max-length", 2500,
             "-o", tmp_path / "m", expect=2)
    err = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(err) == 1 and err[0].startswith(
        "Error: --mold-max-length 2500 read as m (the nets' unit) is a 2500 m mold piece, above "
        "the whole mold (")
    assert "did you mean 2500mm? (to mean it as typed, give its unit: 2500m)" in err[0]
    assert list(tmp_path.iterdir()) == []


def test_old_option_names_still_work_and_warn(wall):
    r = dgpc("extract-mold", wall / "wall", "--tol", 1e-3, "--units", "m", "-o", wall / "old")
    assert "--tol is deprecated, it is now --revolution-tol" in r.stderr
    assert "--units is deprecated, it is now --expect-units" in r.stderr
    assert json.loads((wall / "old.json").read_text())["parameters"]["revolution_tol"] == 1e-3
    dgpc("extract-mold", wall / "wall", "--units", "mm", "-o", wall / "old2", expect=2)


def test_a_wrong_kind_names_the_stage_that_makes_the_right_one(wall):
    r = dgpc("unfold", wall / "wall", "-o", wall / "flat", expect=1)
    assert "expected 'strips'" in r.stderr and "dgpc planarize-strips NET" in r.stderr
    r = dgpc("nest", wall / "wall", "--sheet", "2500x1250", "-o", wall / "sheets", expect=1)
    assert "expected 'flat'" in r.stderr and "dgpc unfold STRIPS" in r.stderr


def test_a_part_too_long_for_the_sheet_suggests_stock_length(wall):
    dgpc("planarize-strips", wall / "wall", "-o", wall / "strips")
    dgpc("unfold", wall / "strips", "-o", wall / "flat")
    r = dgpc("nest", wall / "flat", "--sheet", "2500x1250", "-o", wall / "sheets", expect=1)
    assert "does not fit" in r.stderr and "--stock-length" in r.stderr


def test_init_edge_length_takes_a_unit_and_its_old_name_warns(tmp_path):
    mesh = tmp_path / "m.obj"
    mesh.write_text("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    base = ["init", mesh, "--method", "project", "--direction", "0,0,1", "--units", "m"]
    dgpc(*base, "--edge-length", "250mm", "-o", tmp_path / "a")
    dv = np.linalg.norm(np.diff(read_net(tmp_path / "a").f, axis=1), axis=-1)
    assert np.allclose(dv, 0.25, rtol=1e-9)
    doc = json.loads((tmp_path / "a.json").read_text())
    assert doc["parameters"]["spacing"] == 0.25                  # in the net's unit, m
    r = dgpc(*base, "--spacing", 0.25, "-o", tmp_path / "b")
    assert "--spacing is deprecated, it is now --edge-length" in r.stderr
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()


def test_design_lambda_is_the_turn_of_the_rows():
    """λ = 360°/span for a net on a surface of revolution (twisted too: its rows are still
    parallels); a Minding bending by λ of a full ring is measured as λ."""
    from dgpc_cli.mold.profile import design_lambda, row_turning
    from dgpc_cli.surfaces.minding import minding_bend
    from dgpc_cli.surfaces.profiles import profile_from_spec
    from dgpc_cli.surfaces.revolution import revolution_net

    prof = profile_from_spec("catenoid")
    f = revolution_net(prof, 9, 7, span_deg=75.0, twist=0.4)
    assert np.allclose(np.degrees(row_turning(f)), 75.0, rtol=1e-12)
    assert design_lambda([f])[0] == pytest.approx(360 / 75, rel=1e-9)
    ring = revolution_net(prof, 9, 13, span_deg=360.0)
    assert design_lambda([ring])[0] == 1.0                      # 10 digits: exactly one turn
    assert design_lambda([minding_bend(ring, 0.7)])[0] == pytest.approx(0.7, rel=1e-9)
    flat = np.stack([*np.meshgrid(np.arange(4.0), np.arange(5.0), indexing="ij"),
                     np.zeros((4, 5))], axis=-1)
    assert design_lambda([flat]) is None and design_lambda([flat[:, :2]]) is None
