"""Bad input: one line on stderr naming the problem, exit 1 or 2, nothing written (SPEC §2)."""

import json

import pytest
from cli_helpers import dgpc


@pytest.fixture
def net0(tmp_path):
    stem = tmp_path / "n0"
    dgpc("init", "--surface", "revolution", "--profile", "cylinder", "--rows", 5, "--cols", 4,
         "-o", stem)
    return stem


def assert_one_line_error(result, *words):
    err = result.stderr.strip()
    assert len(err.splitlines()) == 1, err
    assert err.startswith("Error:") and "Traceback" not in err
    for w in words:
        assert w in err, (w, err)


def outputs(tmp_path, stem="out"):
    return sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(stem))


def test_missing_file(tmp_path):
    r = dgpc("optimize", tmp_path / "nope", "--mode", "revolution", "-o", tmp_path / "out",
             expect=1)
    assert_one_line_error(r, "nope.json")
    assert outputs(tmp_path) == []


def test_empty_obj(tmp_path, net0):
    net0.with_suffix(".obj").write_text("")
    r = dgpc("optimize", net0, "--mode", "revolution", "-o", tmp_path / "out", expect=1)
    assert_one_line_error(r, "n0.obj")
    assert outputs(tmp_path) == []


def test_json_of_another_kind(tmp_path, net0):
    doc = json.loads(net0.with_suffix(".json").read_text())
    doc["kind"] = "mold"
    net0.with_suffix(".json").write_text(json.dumps(doc))
    r = dgpc("inspect", net0, expect=1)
    assert_one_line_error(r, "n0.json", "mold")


@pytest.mark.parametrize("opt", ["--rows", "--cols"])
def test_grid_smaller_than_3(tmp_path, opt):
    args = {"--rows": 5, "--cols": 5, opt: 2}
    r = dgpc("init", "--surface", "revolution", "--profile", "sphere",
             *[x for kv in args.items() for x in kv], "-o", tmp_path / "out", expect=2)
    assert opt in r.stderr
    assert outputs(tmp_path) == []


def test_nan_coordinate(tmp_path, net0):
    obj = net0.with_suffix(".obj")
    lines = obj.read_text().splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("v "))
    lines[i] = "v nan 0 0"
    obj.write_text("\n".join(lines) + "\n")
    r = dgpc("optimize", net0, "--mode", "revolution", "-o", tmp_path / "out", expect=1)
    assert_one_line_error(r, "n0")
    assert outputs(tmp_path) == []


def test_handle_outside_the_grid(tmp_path, net0):
    handles = tmp_path / "h.json"
    handles.write_text(json.dumps({"handles": [{"index": [9, 1], "offset": [0, 0, 1]}]}))
    r = dgpc("optimize", net0, "--mode", "isometric", "--handles", handles,
             "-o", tmp_path / "out", expect=1)
    assert_one_line_error(r, "h.json", "outside")
    assert outputs(tmp_path) == []


def test_unknown_weight_name(tmp_path, net0):
    r = dgpc("optimize", net0, "--mode", "revolution", "--weight", "bogus=1",
             "-o", tmp_path / "out", expect=2)
    assert "bogus" in r.stderr
    assert outputs(tmp_path) == []


def test_negative_radius_in_profile(tmp_path):
    csv = tmp_path / "p.csv"
    csv.write_text("r,h\n1,0\n-0.5,1\n1,2\n")
    r = dgpc("init", "--surface", "revolution", "--profile", csv, "--rows", 5, "--cols", 5,
             "-o", tmp_path / "out", expect=1)
    assert_one_line_error(r, "p.csv", "negative")
    assert outputs(tmp_path) == []


def test_existing_output_needs_force(tmp_path, net0):
    before = net0.with_suffix(".json").read_bytes()
    r = dgpc("init", "--surface", "revolution", "--profile", "sphere", "--rows", 5, "--cols", 5,
             "-o", net0, expect=1)
    assert_one_line_error(r, "n0", "--force")
    assert net0.with_suffix(".json").read_bytes() == before
    dgpc("init", "--surface", "revolution", "--profile", "sphere", "--rows", 5, "--cols", 5,
         "-o", net0, "--force")
    assert net0.with_suffix(".json").read_bytes() != before


def test_isometric_needs_handles(tmp_path, net0):
    r = dgpc("optimize", net0, "--mode", "isometric", "-o", tmp_path / "out", expect=2)
    assert_one_line_error(r, "--handles")


def test_fit_needs_a_reference(tmp_path, net0):
    r = dgpc("optimize", net0, "--mode", "fit", "-o", tmp_path / "out", expect=1)
    assert_one_line_error(r, "--reference")


def test_unreadable_reference_mesh(tmp_path, net0):
    png = tmp_path / "ref.obj"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(64))
    r = dgpc("optimize", net0, "--mode", "fit", "--reference", png, "-o", tmp_path / "out",
             expect=1)
    assert_one_line_error(r, "ref.obj")
    assert outputs(tmp_path) == []


def test_stdout_carries_data_only(tmp_path, net0):
    r = dgpc("inspect", net0)
    json.loads(r.stdout)
    r = dgpc("optimize", net0, "--mode", "revolution", "-o", tmp_path / "out")
    assert r.stdout.strip().endswith("out.json")
