"""Issue 14 item 1: a length unit on every artifact, carried from `init --units` to the cut
sheets; stages compute in mm, so a design in m and the same design in mm give the same bytes."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc
from mold_samples import gehry_nets, write

from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.laths import read_laths
from dgpc_cli.io.mold import read_mold
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.sheets import read_sheets
from dgpc_cli.io.strips import read_strips
from dgpc_cli.io.units import UNIT_MM, exact_mm, from_mm, to_mm
from dgpc_cli.surfaces.minding import minding_bend

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("units", list(UNIT_MM))
def test_stored_values_give_the_mm_back_exactly(units):
    """What a stage stores in a unit reads back as the millimetres it computed, bit for bit,
    and the stored mm do not depend on the unit (within a few ulps of the computed ones)."""
    rng = np.random.default_rng(7)
    y = rng.uniform(-1, 1, 200_000) * 10.0 ** rng.integers(-3, 7, 200_000)
    back = to_mm(from_mm(y, units), units)
    assert np.array_equal(back, exact_mm(y))
    assert np.array_equal(exact_mm(y), to_mm(from_mm(y, "mm"), "mm"))
    assert np.all(np.abs(exact_mm(y) - y) <= 64 * np.spacing(np.abs(y)))
    assert np.allclose(from_mm(y, units), y / UNIT_MM[units], rtol=1e-14, atol=0)


def test_init_records_the_unit_and_every_stage_carries_it(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 6,
         "--span", 360, "-o", tmp_path / "mm")
    assert read_net(tmp_path / "mm").units == "mm"              # the default
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 6,
         "--span", 360, "--units", "in", "-o", tmp_path / "cat")
    net = read_net(tmp_path / "cat")
    assert net.units == "in" and net.parameters["units"] == "in"
    # the same numbers in another unit: the profile's numbers are inches now
    assert np.allclose(net.f, read_net(tmp_path / "mm").f, rtol=1e-14, atol=1e-14)
    write_net(tmp_path / "iso", NetArtifact(f=minding_bend(net.f, 0.7), units="in"))
    dgpc("optimize", tmp_path / "cat", "--mode", "revolution", "-o", tmp_path / "opt")
    opt = read_net(tmp_path / "opt")
    assert opt.units == "in" and np.abs(opt.f - net.f).max() < 1e-6
    dgpc("planarize-strips", tmp_path / "iso", "-o", tmp_path / "s")
    assert read_strips(tmp_path / "s").units == "in"
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    assert read_flat(tmp_path / "f").units == "in"
    dgpc("extract-mold", tmp_path / "iso", "-o", tmp_path / "m")
    assert read_mold(tmp_path / "m").units == "in"
    dgpc("nest", tmp_path / "f", "--mold", tmp_path / "m", "--sheet", "2000x1000", "-o",
         tmp_path / "sh")
    sheets = read_sheets(tmp_path / "sh")
    assert sheets.data["units"] == "mm" and sheets.data["sheet"]["part_units"] == "in"
    assert sheets.data["sheet"]["mm_per_unit"] == 25.4
    # laths of the two families of a flat grid (the transpose of a catenoid net, its u-lines
    # the parallels, is no gpc net, and laths refuses it)
    u, v = np.meshgrid(np.linspace(0.0, 40.0, 6), np.linspace(0.0, 40.0, 6), indexing="ij")
    grid = np.stack([u, v, np.zeros_like(u)], axis=-1)
    write_net(tmp_path / "along", NetArtifact(f=grid, units="in"))
    write_net(tmp_path / "across", NetArtifact(f=np.transpose(grid, (1, 0, 2)), units="in"))
    dgpc("laths", tmp_path / "along", tmp_path / "across", "-o", tmp_path / "l")
    assert read_laths(tmp_path / "l").data["units"] == "in"
    for stem in ("cat", "iso", "s", "f", "m", "sh"):
        assert json.loads((tmp_path / f"{stem}.json").read_text())["schema_version"] == 2


def test_a_plain_lath_gap_meant_in_millimetres_is_a_usage_error(tmp_path):
    """``laths --gap 5`` on nets in metres (edges of 0.1 m) is a 5 m gap, where 5 mm was
    likely meant: exit 2, one line, nothing written; ``5mm`` and a plain 0.01 are fine."""
    u, v = np.meshgrid(np.linspace(0.0, 0.5, 6), np.linspace(0.0, 0.5, 6), indexing="ij")
    grid = np.stack([u, v, np.zeros_like(u)], axis=-1)
    write_net(tmp_path / "along", NetArtifact(f=grid, units="m"))
    write_net(tmp_path / "across", NetArtifact(f=np.transpose(grid, (1, 0, 2)), units="m"))
    before = sorted(p.name for p in tmp_path.iterdir())
    res = dgpc("laths", tmp_path / "along", tmp_path / "across", "--gap", 5, "-o",
               tmp_path / "l", expect=2)
    err = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(err) == 1 and "--gap 5 read as m (the nets' unit) is a 5 m gap, above the " \
        "nets' mean edge (0.1 m); did you mean 5mm?" in err[0]
    assert _no_output(tmp_path, before)
    for gap in ("5mm", 0.01):
        dgpc("laths", tmp_path / "along", tmp_path / "across", "--gap", gap, "-o",
             tmp_path / "l", "--force")
        doc = json.loads((tmp_path / "l.json").read_text())
        assert doc["parameters"]["gap"] == pytest.approx(0.005 if gap == "5mm" else 0.01)


def _no_output(folder, before):
    return sorted(p.name for p in folder.iterdir()) == before


@pytest.mark.parametrize("command", ["extract-mold", "nest"])
def test_a_units_option_is_a_check_naming_both(tmp_path, command):
    stem = write(tmp_path / "g", gehry_nets(9, 7)[0], units="m")
    args = {"extract-mold": ["extract-mold", stem],
            "nest": None}[command]
    if command == "nest":
        dgpc("planarize-strips", stem, "-o", tmp_path / "s")
        dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
        args = ["nest", tmp_path / "f", "--sheet", "6000x2000"]
    before = sorted(p.name for p in tmp_path.iterdir())
    res = dgpc(*args, "--expect-units", "mm", "-o", tmp_path / "out", expect=2)
    err = res.stderr.strip().splitlines()[-1]
    assert err.startswith("Error") and "--expect-units" in err and "mm given" in err
    assert "is in m" in err
    assert _no_output(tmp_path, before)
    # the former name still checks, and says it is now --expect-units
    res = dgpc(*args, "--units", "mm", "-o", tmp_path / "out", expect=2)
    assert "--units is deprecated, it is now --expect-units" in res.stderr
    dgpc(*args, "--expect-units", "m", "-o", tmp_path / "out")        # agreeing: fine


def test_an_unknown_unit_is_a_usage_error(tmp_path):
    res = dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols",
               4, "--units", "furlong", "-o", tmp_path / "n", expect=2)
    assert "--units" in res.stderr and "furlong" in res.stderr
    assert list(tmp_path.iterdir()) == []


def test_inputs_in_different_units_are_refused(tmp_path):
    nets = gehry_nets(9, 7)
    a = write(tmp_path / "a", nets[0], units="m")
    b = write(tmp_path / "b", nets[1], units="mm")
    before = sorted(p.name for p in tmp_path.iterdir())
    for args in (["extract-mold", a, b], ["laths", a, b]):
        res = dgpc(*args, "-o", tmp_path / "out", expect=1)
        (line,) = [x for x in res.stderr.splitlines() if x.strip()]
        assert line.startswith("Error") and "different units" in line
        assert "b.json is in mm" in line and "a.json is in m" in line
        assert _no_output(tmp_path, before)
    # a flat in m with a mold in mm
    dgpc("extract-mold", b, "-o", tmp_path / "mold")
    dgpc("planarize-strips", a, "-o", tmp_path / "s")
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    before = sorted(p.name for p in tmp_path.iterdir())
    res = dgpc("nest", tmp_path / "f", "--mold", tmp_path / "mold", "--sheet", "6000x2000",
               "-o", tmp_path / "out", expect=1)
    assert "different units" in res.stderr and _no_output(tmp_path, before)


def _scaled_inputs(folder, rows, cols):
    """The timber wall's profile and handles × 1000 (m → mm), written as the CSV and JSON
    a user in mm would have."""
    lines = (ROOT / "samples/profiles/wall.csv").read_text().split()
    rows_mm = [",".join(repr(float(x) * 1000.0) for x in line.split(",")) for line in lines[1:]]
    (folder / "wall.csv").write_text("\n".join([lines[0], *rows_mm]) + "\n")
    doc = json.loads((ROOT / f"samples/handles/wall-{rows}x{cols}.json").read_text())
    for h in doc["handles"]:
        for key in ("target", "offset"):
            if key in h:
                h[key] = [x * 1000.0 for x in h[key]]
    (folder / "handles.json").write_text(json.dumps(doc))


def _timber(folder, profile, handles, units, rows=9, cols=7):
    """The timber-cladding pipeline's commands (pipelines/timber-cladding.mk), unit declared
    once at init; nest gets no unit. A 9×7 net is stiff: the drag's tolerances of the
    pipeline's small version (tests/golden/pipelines.py)."""
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", rows, "--cols", cols,
         "--span", 60, "--units", units, "-o", folder / "base")
    dgpc("optimize", folder / "base", "--mode", "isometric", "--handles", handles, "--steps", 5,
         "--max-strain", 2e-3, "--gpc-tol", 5e-4, "-o", folder / "wall")
    dgpc("planarize-strips", folder / "wall", "-o", folder / "strips")
    dgpc("unfold", folder / "strips", "-o", folder / "flat")
    dgpc("nest", folder / "flat", "--sheet", "6100x2500", "-o", folder / "sheets")
    return read_sheets(folder / "sheets")


def test_timber_wall_in_m_and_in_mm_gives_the_same_cut_sheets(tmp_path):
    (tmp_path / "m").mkdir()
    (tmp_path / "mm").mkdir()
    _scaled_inputs(tmp_path / "mm", 9, 7)
    in_m = _timber(tmp_path / "m", ROOT / "samples/profiles/wall.csv",
                   ROOT / "samples/handles/wall-9x7.json", "m")
    in_mm = _timber(tmp_path / "mm", tmp_path / "mm/wall.csv", tmp_path / "mm/handles.json",
                    "mm")
    assert read_net(tmp_path / "m/wall").units == "m"
    assert in_m.data["sheet_count"] == in_mm.data["sheet_count"] >= 2
    for sheet in in_m.data["sheets"]:
        a = in_m.file(sheet["dxf"]).read_bytes()
        b = in_mm.file(sheet["dxf"]).read_bytes()
        assert a == b, sheet["dxf"]                           # byte-identical cut sheets
        assert in_m.file(sheet["png"]).read_bytes() == in_mm.file(sheet["png"]).read_bytes()
    assert in_m.file("parts_csv").read_bytes() == in_mm.file("parts_csv").read_bytes()
    assert (tmp_path / "m/flat.parts.csv").read_bytes() == \
        (tmp_path / "mm/flat.parts.csv").read_bytes()
    # the same wall: coordinates × 1000 up to the last bits of a different unit
    f_m, f_mm = read_net(tmp_path / "m/wall").f, read_net(tmp_path / "mm/wall").f
    assert np.array_equal(to_mm(f_m, "m"), f_mm)
    # a 6 m wall, 6,000 mm parts, not 6 mm ones
    length = max(p["length"] for p in read_flat(tmp_path / "m/flat").parts)
    assert 5.5 < length < 6.5
    assert in_m.data["utilization"]["overall"] > 0.5
