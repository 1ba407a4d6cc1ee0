"""One writer per stem and reads that check what they read (SPEC §3): an unusable lock is a
refusal, an output that is one of the command's inputs is refused even with --force, a
journal obeys only for its own artifact's files, and every artifact reader refuses (one line,
exit 1) what does not hold together: faces against the shape, ``data.obj`` against the files,
units across ``--against``, options that do not apply, deep nesting, self-crossing outlines.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.errors import DgpcError
from dgpc_cli.io import lock as lock_module
from dgpc_cli.io.artifact import dumps_json, sha256_bytes
from dgpc_cli.io.lock import output_lock


def one_line_error(result, *needles):
    """The command failed with exit 1 and one line on stderr holding ``needles``."""
    assert result.exit_code == 1, (result.exit_code, result.stderr)
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in result.stderr, result.stderr


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """A 9×7 catenoid net (m), its copy in mm, its strips, flat and mold."""
    d = tmp_path_factory.mktemp("chain")
    common = ["--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
              "--span", 120]
    dgpc("init", *common, "--units", "m", "-o", d / "net")
    dgpc("init", *common, "--units", "mm", "-o", d / "net-mm")
    dgpc("init", *common, "--twist", 10, "--units", "m", "-o", d / "other")
    dgpc("planarize-strips", d / "net", "-o", d / "strips")
    dgpc("unfold", d / "strips", "-o", d / "flat")
    dgpc("extract-mold", d / "net", "-o", d / "mold")
    return d


def copy_artifact(src: Path, dst: Path, stem: str) -> Path:
    """``stem``'s JSON and the files it lists, copied into ``dst``."""
    dst.mkdir(exist_ok=True)
    for p in src.iterdir():
        if p.is_file() and p.name.startswith(f"{stem}."):
            (dst / p.name).write_bytes(p.read_bytes())
    return dst / stem


def edit_json(stem: Path, change) -> None:
    path = stem.with_suffix(".json")
    doc = json.loads(path.read_text())
    change(doc)
    path.write_bytes(dumps_json(doc))


# -- one writer per stem ---------------------------------------------------------------------

def test_a_lock_path_that_is_a_folder_is_a_refusal(tmp_path):
    (tmp_path / ".net.lock").mkdir()
    result = dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 5,
                  "--cols", 5, "-o", tmp_path / "net", expect=None)
    one_line_error(result, ".net.lock", "remove it")
    assert not (tmp_path / "net.json").exists()


def test_a_lock_this_user_cannot_open_is_a_refusal(tmp_path, monkeypatch):
    """A stale lock of another user (mode 0600): opening it fails with EACCES."""
    real_open = os.open

    def no_access(path, *args, **kwargs):
        if str(path).endswith(".net.lock"):
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, *args, **kwargs)

    (tmp_path / ".net.lock").write_text("")
    monkeypatch.setattr(lock_module.os, "open", no_access)
    with pytest.raises(DgpcError, match="Permission denied"):
        with output_lock(tmp_path / "net"):
            pytest.fail("the block ran without the lock")
    with output_lock(tmp_path / "net", wait=True) as held:     # a reader goes on
        assert held


@pytest.mark.parametrize("args", [
    ["optimize", "{net}", "--mode", "isometric", "-o", "{net}", "--force"],
    ["planarize-strips", "{net}", "-o", "{net}", "--force"],
    ["planarize-strips", "{net}.json", "-o", "{net}", "--force"],
    ["unfold", "{strips}", "-o", "{strips}", "--force"],
    ["nest", "{flat}", "--sheet", "7000x5000", "-o", "{flat}.json", "--force"],
    ["extract-mold", "{net}", "{other}", "-o", "{other}", "--force"],
    ["laths", "{net}", "{other}", "-o", "{net}", "--force"],
    ["optimize", "{net}", "--mode", "isometric", "--handles", "{net}.json", "-o", "{net}",
     "--force"],
])
def test_an_output_that_is_an_input_is_refused_even_with_force(chain, tmp_path, args):
    d = tmp_path / "d"
    for stem in ("net", "other", "strips", "flat"):
        copy_artifact(chain, d, stem)
    before = snapshot(d)
    names = {k: d / k for k in ("net", "other", "strips", "flat")}
    result = dgpc(*[a.format(**names) for a in args], expect=None)
    one_line_error(result, "is also an input")
    assert snapshot(d) == before


# -- journals --------------------------------------------------------------------------------

@pytest.mark.parametrize("journal", [
    {"replace": [], "remove": ["precious.txt"]},
    {"replace": [[".precious.txt.a1b2c3.tmp", "precious.txt"]], "remove": []},
    {"replace": [[".net.obj.a1b2c3.tmp", "net.obj"]], "remove": ["../precious.txt"]},
])
def test_a_journal_naming_files_of_no_artifact_of_its_own_is_refused(chain, tmp_path,
                                                                       journal):
    net = copy_artifact(chain, tmp_path, "net")
    (tmp_path / "precious.txt").write_text("mine")
    (tmp_path / ".precious.txt.a1b2c3.tmp").write_text("overwritten")
    (tmp_path / ".net.obj.a1b2c3.tmp").write_text("v 0 0 0\n")
    (tmp_path / ".net.json.journal").write_text(json.dumps(journal))
    before = snapshot(tmp_path)
    one_line_error(dgpc("inspect", net, expect=None), ".net.json.journal",
                   "not a file of its artifact")
    assert snapshot(tmp_path) == before
    assert (tmp_path / "precious.txt").read_text() == "mine"


def test_a_journal_of_its_own_files_is_still_finished(chain, tmp_path):
    """The renames and removals a real interrupted write lists (temp files, backups and the
    stale files of the artifact) are carried out."""
    net = copy_artifact(chain, tmp_path, "net")
    obj = (tmp_path / "net.obj").read_bytes()
    (tmp_path / "net.obj").write_bytes(b"half written\n")
    (tmp_path / ".net.obj.k3y_9.tmp").write_bytes(obj)
    (tmp_path / ".net.obj.0123456789ab.bak").write_bytes(b"old")
    (tmp_path / "net.old.dxf").write_bytes(b"stale")
    (tmp_path / ".net.json.journal").write_text(json.dumps(
        {"replace": [[".net.obj.k3y_9.tmp", "net.obj"]],
         "remove": ["net.old.dxf", ".net.obj.0123456789ab.bak"]}))
    dgpc("inspect", net)
    assert (tmp_path / "net.obj").read_bytes() == obj
    assert not any(p.name.startswith(".net.") for p in tmp_path.iterdir())
    assert not (tmp_path / "net.old.dxf").exists()


# -- reads -----------------------------------------------------------------------------------

def test_a_net_face_naming_a_vertex_the_net_has_not_is_refused(chain, tmp_path):
    net = copy_artifact(chain, tmp_path, "net")
    obj = (tmp_path / "net.obj").read_bytes().replace(b"\nf 1 ", b"\nf 999 ", 1)
    (tmp_path / "net.obj").write_bytes(obj)
    edit_json(net, lambda doc: doc["data"].update(obj_sha256=sha256_bytes(obj)))
    result = dgpc("planarize-strips", net, "-o", tmp_path / "strips", expect=None)
    one_line_error(result, "net.obj", "vertex 999", "63")
    assert not (tmp_path / "strips.json").exists()


def test_a_shape_that_is_not_the_objs_grid_is_refused(chain, tmp_path):
    net = copy_artifact(chain, tmp_path, "net")
    edit_json(net, lambda doc: doc["data"].update(shape=[7, 9]))
    one_line_error(dgpc("inspect", net, expect=None), "not the quads of a 7 x 9 net")
    one_line_error(dgpc("planarize-strips", net, "-o", tmp_path / "s", expect=None),
                   "not the quads of a 7 x 9 net")


@pytest.mark.parametrize("stem", ["net", "strips", "flat"])
def test_a_data_obj_naming_a_folder_is_refused(chain, tmp_path, stem):
    path = copy_artifact(chain, tmp_path, stem)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / f"{stem}.obj").write_bytes((tmp_path / f"{stem}.obj").read_bytes())
    edit_json(path, lambda doc: doc["data"].update(obj="sub"))
    one_line_error(dgpc("inspect", path, expect=None), "data.obj", "is a folder")


def test_strain_across_units_is_refused(chain):
    one_line_error(dgpc("inspect", chain / "net", "--against", chain / "net-mm", expect=None),
                   "--against", "mm", "different units")


@pytest.mark.parametrize("stem, option", [("mold", "--against"), ("flat", "--against"),
                                          ("strips", "--axis")])
def test_options_that_do_not_apply_are_refused(chain, stem, option):
    value = chain / "net" if option == "--against" else "0,0,0,0,0,1"
    result = dgpc("inspect", chain / stem, option, value, expect=2)
    assert option in result.stderr and "applies to a net" in result.stderr


def test_laths_of_a_net_and_itself_are_refused(chain, tmp_path):
    copy_artifact(chain, tmp_path, "net")
    (tmp_path / "copy.json").write_bytes((tmp_path / "net.json").read_bytes())
    (tmp_path / "copy.obj").write_bytes((tmp_path / "net.obj").read_bytes())
    for other in ("net", "copy"):
        result = dgpc("laths", tmp_path / "net", tmp_path / other, "-o", tmp_path / "laths",
                      expect=None)
        one_line_error(result, "the same net")
    assert not (tmp_path / "laths.json").exists()


def test_json_nested_2000_deep_is_one_line(tmp_path):
    (tmp_path / "deep.json").write_text("[" * 2000 + "]" * 2000)
    one_line_error(dgpc("inspect", tmp_path / "deep", expect=None), "nested more than")
    (tmp_path / "deep.json").write_text('{"kind": "net", "data": ' + "[" * 80 + "]" * 80 + "}")
    one_line_error(dgpc("inspect", tmp_path / "deep", expect=None), "nested more than")


def test_a_bow_tie_outline_is_one_line(chain, tmp_path):
    flat = copy_artifact(chain, tmp_path, "flat")

    def bow_tie(doc):
        outline = np.asarray(doc["data"]["parts"][0]["outline"])
        half = len(outline) // 2                # one long side reversed: a bow tie
        outline[:half] = outline[:half][::-1].copy()
        doc["data"]["parts"][0]["outline"] = outline.tolist()

    edit_json(flat, bow_tie)
    one_line_error(dgpc("inspect", flat, expect=None), "data.parts[0]", "crosses itself")
    one_line_error(dgpc("nest", flat, "--sheet", "7000x5000", "-o", tmp_path / "sheets",
                        expect=None), "crosses itself")


def test_an_output_option_is_not_taken_for_an_input(tmp_path):
    """init --reference-out names a file init writes, beside -o: not an input to protect."""
    from cli_helpers import dgpc

    dgpc("init", "--surface", "revolution", "--profile", "cylinder", "--rows", 5, "--cols", 5,
         "--units", "m", "--reference-out", tmp_path / "ref.obj", "-o", tmp_path / "n")
    dgpc("init", "--surface", "revolution", "--profile", "cylinder", "--rows", 5, "--cols", 5,
         "--units", "m", "--reference-out", tmp_path / "ref.obj", "-o", tmp_path / "n",
         "--force")
    assert (tmp_path / "ref.obj").exists() and (tmp_path / "n.json").exists()
