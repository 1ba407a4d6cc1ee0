"""One rule for every length option (dgpc_cli.io.length): a plain number keeps its documented
meaning, one that lies outside its option's plausible span is a usage error (exit 2) naming
both readings and nothing is written; a length with its unit is taken as given; every length,
with or without a unit, is at most 1000 km once converted. The three traps a new user fell
into (a 0.006 mm router bit, a 0.02 mm margin, a 0.5 m congruence tolerance), the sheet sizes
of ``nest --sheet``, and init's strip width that cannot be met."""

import json

import pytest
from cli_helpers import dgpc

from dgpc_cli.io.length import MAX_LENGTH_MM, Length, Span
from dgpc_cli.io.units import mm_per_unit
from dgpc_cli.nesting.tools import BIT_SPAN, MARGIN_SPAN
from dgpc_cli.stages.nest import parse_sheet

WALL = "samples/profiles/wall.csv"


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """The demo's wall at 9 × 7, in metres: its strips ``s`` and flat parts ``f``."""
    d = tmp_path_factory.mktemp("wall")
    dgpc("init", "--surface", "revolution", "--profile", WALL, "--rows", 9, "--cols", 7,
         "--span", 60, "--units", "m", "-o", d / "net")
    dgpc("planarize-strips", d / "net", "-o", d / "s")
    dgpc("unfold", d / "s", "-o", d / "f")
    return d


def _files(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def _refused(folder, *args, code=2):
    """Run ``dgpc ARGS`` expecting one error line and exit ``code``, nothing written to
    ``folder``; the line."""
    before = _files(folder)
    r = dgpc(*args, expect=code)
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("Error: "), r.stderr
    assert "Traceback" not in r.stderr
    assert _files(folder) == before
    return lines[0]


def test_a_plain_router_bit_of_0_006_is_refused_naming_both_readings(wall, tmp_path):
    line = _refused(tmp_path, "nest", wall / "f", "--sheet", "6100x2500", "--tool", "router",
                    "--tool-diameter", "0.006", "-o", tmp_path / "sheets")
    assert "--tool-diameter 0.006 read as mm is a 0.006 mm router bit, outside the " \
           "plausible 0.5–50 mm; did you mean 6mm?" in line
    assert "give its unit: 0.006mm" in line


def test_a_plain_margin_of_0_02_is_refused_naming_both_readings(wall, tmp_path):
    line = _refused(tmp_path, "nest", wall / "f", "--sheet", "6100x2500", "--margin", "0.02",
                    "-o", tmp_path / "sheets")
    assert "--margin 0.02 read as mm is a 0.02 mm margin, below 1 mm; did you mean 20mm?" \
        in line


def test_a_plain_congruence_tolerance_in_metres_is_refused(wall, tmp_path):
    """0.5 on strips in metres is 0.5 m, which merges parts that differ by centimetres: more
    than 1 % of the parts' mean width, so refused; did you mean 0.5mm?"""
    line = _refused(tmp_path, "unfold", wall / "s", "--congruence-tol", "0.5",
                    "-o", tmp_path / "flat")
    assert "--congruence-tol 0.5 read as m (the strips' unit) is a 0.5 m congruence " \
           "tolerance, above 1 % of the parts' mean width (" in line
    assert "did you mean 0.5mm?" in line
    # the same tolerance meant: in mm, or as a plain number in metres
    for tol in ("0.5mm", "0.0005"):
        dgpc("unfold", wall / "s", "--congruence-tol", tol, "-o", tmp_path / "flat",
             "--force")
        doc = json.loads((tmp_path / "flat.json").read_text())
        assert doc["parameters"]["congruence_tol_mm"] == pytest.approx(0.5)


def test_lengths_with_their_units_are_taken_as_given():
    """The span judges plain numbers only; with a unit the user said what they meant."""
    assert Length(0.006, "mm", "mm").check("--tool-diameter", span=BIT_SPAN) == 0.006
    assert Length(0.0, None, "mm").check("--margin", span=MARGIN_SPAN) == 0.0   # 0: any unit
    with pytest.raises(Exception, match="did you mean 20mm"):
        Length(0.02, None, "mm").check("--margin", span=MARGIN_SPAN)


@pytest.mark.parametrize("args, option", [
    (["unfold", "{d}/s", "--stock-length", "1e308m"], "--stock-length"),
    (["unfold", "{d}/s", "--congruence-tol", "2000km"], None),          # unknown unit
    (["unfold", "{d}/s", "--stock-length", 1e300], "--stock-length"),   # plain, in m
    (["nest", "{d}/f", "--sheet", "6100x2500", "--kerf", "1e10mm"], "--kerf"),
    (["nest", "{d}/f", "--sheet", "1e7mx1m"], "--sheet"),
    (["init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
      "--edge-length", "1e12m"], "--edge-length"),
])
def test_one_limit_for_every_length(wall, tmp_path, args, option):
    """Beyond 1000 km once converted, with or without a unit: a usage error naming the
    option, nothing written."""
    args = [a.format(d=wall) if isinstance(a, str) else a for a in args]
    line = _refused(tmp_path, *args, "-o", tmp_path / "out")
    if option is None:
        assert "unknown unit 'km'" in line
    else:
        assert option in line and "beyond 1000 km" in line


def test_the_limit_is_the_same_in_every_unit():
    for unit in ("mm", "cm", "m", "in", "ft"):
        at = MAX_LENGTH_MM / mm_per_unit(unit) * (1 - 1e-12)
        assert Length(at, unit).check("--x") == pytest.approx(MAX_LENGTH_MM)
        with pytest.raises(Exception, match="beyond 1000 km"):
            Length(at * 1.001, unit).check("--x")
        with pytest.raises(Exception, match="beyond 1000 km"):
            Length(at * 1.001).check("--x", unit)       # a plain number in that unit


def test_spans_in_words():
    assert BIT_SPAN.words() == "0.5–50 mm"
    assert Span(1.0, None).words() == ">= 1 mm"
    assert Span(0.0, 3.5, low_open=True, high_text="1 % of the width").words() == \
        "from 0 mm to 1 % of the width"


@pytest.mark.parametrize("command, option, words", [
    ("nest", "--tool-diameter", "0.5–50 mm"),
    ("nest", "--margin", "0, or at least 1 mm"),
    ("nest", "--kerf", "0.02–10 mm"),
    ("unfold", "--congruence-tol", "up to 1 % of the parts' mean width"),
    ("unfold", "--stock-length", "longer than the widest part"),
    ("unfold", "--stagger", "up to the stock length"),
    ("laths", "--gap", "up to the nets' mean edge"),
    ("extract-mold", "--mold-max-length", "up to the whole mold's length"),
    ("optimize", "--coverage-tol", "up to 10 % of the reference's diagonal"),
])
def test_every_help_states_its_plausible_span(command, option, words):
    text = " ".join(dgpc(command, "--help").stdout.split())
    start = text.index(option + " ")
    assert f"Plausible: {words}" in text[start:start + 900]


# -- nest --sheet --------------------------------------------------------------------------------

def test_a_plain_sheet_in_metres_asks_for_the_unit(wall, tmp_path):
    line = _refused(tmp_path, "nest", wall / "f", "--sheet", "6.1x2.5", "-o", tmp_path / "sh")
    assert "6.1x2.5 read as mm is a 6.1 x 2.5 mm sheet" in line
    assert "did you mean 6.1m x 2.5m?" in line
    assert parse_sheet("6.1x2.5m") == pytest.approx((6100.0, 2500.0))


def test_a_sheet_given_height_first_gets_the_hint_to_turn_it(wall, tmp_path):
    """The wall's parts (6.06 m long) do not fit across a 2500 mm wide sheet, but along its
    6100 mm height they would: exit 1 naming the turned size."""
    line = _refused(tmp_path, "nest", wall / "f", "--sheet", "2500x6100", "-o", tmp_path / "sh",
                    code=1)
    assert "does not fit on the 2500 x 6100 mm sheet" in line
    assert "the sheet turned fits them: give --sheet 6100x2500 (width first)" in line
    # a sheet too small either way: the old advice
    line = _refused(tmp_path, "nest", wall / "f", "--sheet", "3000x3000", "-o", tmp_path / "sh",
                    code=1)
    assert "turned" not in line and "--stock-length" in line


def test_a_sheet_in_inches_does_not_ask_to_remake_a_net_in_metres(wall, tmp_path):
    """6100x2500in is 155 x 63.5 m: the parts (in metres) fill a fraction of a per cent of
    it. The warning points at the sheet, not at `init --units m`."""
    r = dgpc("nest", wall / "f", "--sheet", "6100x2500in", "--no-preview",
             "-o", tmp_path / "sh")
    lines = [line for line in r.stderr.splitlines() if "implausible" in line]
    assert len(lines) == 1
    assert "check --sheet (it is 154.9 x 63.5 m)" in lines[0] and "--units" not in lines[0]


def test_a_sheet_beyond_the_limit_is_a_usage_error():
    with pytest.raises(ValueError, match="beyond 1000 km"):
        parse_sheet("1e308x1e308")


def test_board_errors_give_the_stock_length_as_typed(wall, tmp_path):
    """An error of the boards names the stock length with the unit the user typed (and the
    lengths it computed with their unit, mm), not a bare number."""
    line = _refused(tmp_path, "unfold", wall / "s", "--stock-length", "30cm",
                    "-o", tmp_path / "f", code=1)
    assert line.startswith("Error: --stock-length 30cm: 300 mm is shorter than the strips")
