"""The length option type: units, plain numbers, ranges, and usage errors (exit 2)."""

import click
import pytest
from click.testing import CliRunner

from dgpc_cli.cli.length import Length, LengthParam, length_help


@click.command()
@click.option("--gap", type=LengthParam(min=0, min_open=True), default="0.5mm")
@click.option("--sheet-margin", type=LengthParam(plain="mm", min=0), default=10.0)
def _cmd(gap, sheet_margin):
    click.echo(f"{gap.to_mm('m')!r} {sheet_margin.to_mm('m')!r} {gap.text()}")


@pytest.mark.parametrize("text, mm", [("2.5m", 2500.0), ("2500mm", 2500.0), ("0.5 mm", 0.5),
                                      ("1in", 25.4), ("3", 3000.0), (".5cm", 5.0),
                                      ("1e3mm", 1000.0)])
def test_units_convert(text, mm):
    out = CliRunner().invoke(_cmd, ["--gap", text])
    assert out.exit_code == 0, out.output
    assert float(out.output.split()[0]) == pytest.approx(mm, rel=1e-15)


def test_plain_number_takes_the_options_own_unit():
    out = CliRunner().invoke(_cmd, ["--sheet-margin", "7"])
    assert out.exit_code == 0
    assert out.output.split()[1] == "7.0"          # mm, not the artifact's metres
    assert out.output.split()[0] == "0.5"           # the default gap, 0.5mm


@pytest.mark.parametrize("text", ["nan", "inf", "-1mm", "0", "2.5 meters", "2.5mx", "", "1,5m"])
def test_bad_lengths_are_usage_errors(text):
    out = CliRunner().invoke(_cmd, ["--gap", text])
    assert out.exit_code == 2
    assert "--gap" in out.output


def test_conversions_and_text():
    length = Length(2500.0, "mm")
    assert length.in_units("m") == 2.5
    assert Length(3.0).in_units("mm", artifact_units="m") == 3000.0
    assert length.text() == "2500mm" and Length(3.0).text() == "3"
    with pytest.raises(ValueError):
        Length(3.0).to_mm()
    assert "data.units" in length_help("Gap.") and "in mm" in length_help("Gap.", plain="mm")


@pytest.mark.parametrize("text, size", [("2500x1250", (2500.0, 1250.0)),
                                        ("6.1mx2.5m", (6100.0, 2500.0)),
                                        ("6100x2500mm", (6100.0, 2500.0)),
                                        ("6.1x2.5m", (6100.0, 2500.0)),
                                        ("250cm × 125cm", (2500.0, 1250.0))])
def test_sheet_sizes_take_units(text, size):
    from dgpc_cli.stages.nest import parse_sheet

    assert parse_sheet(text) == pytest.approx(size, rel=1e-15)


@pytest.mark.parametrize("text", ["1x2yd", "0x1", "2500", "2500x1250x3", "nanx1"])
def test_bad_sheet_sizes(text):
    from dgpc_cli.stages.nest import parse_sheet

    with pytest.raises(ValueError):
        parse_sheet(text)
