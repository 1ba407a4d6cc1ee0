"""Bad inputs of every kind (issue 16): each gives exactly one line on stderr naming the option
or the file and field, the exit code of SPEC §2, and leaves every folder as it was."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import click
import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.cli.finite_float import FiniteFloat
from dgpc_cli.cli.main import COMMANDS, cli
from dgpc_cli.errors import DgpcError
from dgpc_cli.io.net import NetArtifact, write_net


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    """A small full-ring catenoid net through the stages: net, strips, flat, mold."""
    d = tmp_path_factory.mktemp("bad-inputs")
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 360, "-o", d / "cat")
    dgpc("planarize-strips", d / "cat", "-o", d / "strips")
    dgpc("unfold", d / "strips", "-o", d / "flat")
    dgpc("extract-mold", d / "cat", "-o", d / "mold")
    dgpc("nest", d / "flat", "--sheet", "2500x1250", "--scale", 100, "-o", d / "sheets")
    u, v = np.meshgrid(np.linspace(0, 4, 6), np.linspace(0, 4, 5), indexing="ij")
    for name, (x, y) in (("la", (v, u)), ("lb", (u, v))):  # two crossing families
        z = 0.1 * np.sin(y) * np.cos(x)
        write_net(d / name, NetArtifact(f=np.stack([x, y, z], axis=-1)))
    dgpc("laths", d / "la", d / "lb", "-o", d / "shell")
    return d


def snapshot(*folders) -> dict:
    """sha256 of every file under ``folders``, by path."""
    return {p: hashlib.sha256(p.read_bytes()).hexdigest()
            for folder in folders for p in sorted(folder.rglob("*")) if p.is_file()}


def assert_one_line(result, code, *words):
    """Exit ``code``, stderr one line starting with ``Error:`` and naming ``words``."""
    assert result.exit_code == code, (result.exit_code, result.stderr)
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("Error: ") and "internal error" not in lines[0], lines[0]
    for w in words:
        assert w in lines[0], (w, lines[0])


def run_bad(folders, args, code, *words):
    """Run ``dgpc ARGS`` expecting a one-line error; no file under ``folders`` changes."""
    before = snapshot(*folders)
    result = dgpc(*args, expect=None)
    assert_one_line(result, code, *words)
    assert snapshot(*folders) == before
    return result


def copy_artifact(src_json, dst_folder, name, edit=None):
    """Copy the artifact of ``src_json`` (its JSON and every file beside it of the same stem)
    to ``dst_folder/name``; ``edit(doc)`` changes the JSON (written back with Python's json,
    which writes NaN and Infinity)."""
    stem = src_json.name[: -len(".json")]
    for p in src_json.parent.glob(f"{stem}.*"):
        shutil.copy(p, dst_folder / (name + p.name[len(stem):]))
    doc = json.loads(src_json.read_text())
    doc["data"]["obj"] = f"{name}.obj"
    for record in doc["data"].get("files", {}).values():
        record["path"] = name + record["path"][len(stem):]
    if "cut_list" in doc["data"]:
        doc["data"]["cut_list"] = name + doc["data"]["cut_list"][len(stem):]
    if edit is not None:
        edit(doc)
    (dst_folder / f"{name}.json").write_text(json.dumps(doc))
    return dst_folder / name


# -- items 1 and 2: no NaN or inf reaches a check or a cut file ---------------------------------

def test_every_float_option_is_a_finite_float():
    """Every float option of every command has the type that refuses NaN and inf."""
    ctx = click.Context(cli)
    for name in COMMANDS:
        for param in cli.get_command(ctx, name).params:
            if isinstance(param.type, click.types.FloatParamType):
                assert isinstance(param.type, FiniteFloat), (name, param.name)


FLOAT_OPTIONS = [
    (["init", "--surface", "revolution", "--profile", "catenoid"], "--twist"),
    (["init", "--surface", "revolution", "--profile", "catenoid"], "--span"),
    (["init", "--surface", "revolution", "--profile", "catenoid"], "--edge-length"),
    (["init", "--surface", "revolution", "--profile", "catenoid"], "--extend"),
    (["optimize", "{d}/cat", "--mode", "revolution"], "--tol"),
    (["optimize", "{d}/cat", "--mode", "isometric"], "--max-strain"),
    (["optimize", "{d}/cat", "--mode", "isometric"], "--gpc-tol"),
    (["extract-mold", "{d}/cat"], "--revolution-tol"),
    (["extract-mold", "{d}/cat"], "--flat-tol"),
    (["extract-mold", "{d}/cat"], "--mold-max-length"),
    (["extract-mold", "{d}/cat"], "--lambda"),
    (["planarize-strips", "{d}/cat"], "--flat-angle"),
    (["unfold", "{d}/strips"], "--congruence-tol"),
    (["unfold", "{d}/strips"], "--stock-length"),
    (["unfold", "{d}/strips"], "--stagger"),
    (["nest", "{d}/flat", "--sheet", "700x500"], "--margin"),
    (["nest", "{d}/flat", "--sheet", "700x500"], "--spacing"),
    (["nest", "{d}/flat", "--sheet", "700x500"], "--scale"),
    (["nest", "{d}/flat", "--sheet", "700x500"], "--time-limit"),
    (["laths", "{d}/cat", "{d}/cat"], "--gap"),
]


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "NaN", "1e999"])
@pytest.mark.parametrize("args, option", FLOAT_OPTIONS,
                         ids=[f"{a[0]}{o}" for a, o in FLOAT_OPTIONS])
def test_non_finite_option_is_a_usage_error(sample, tmp_path, args, option, value):
    args = [a.format(d=sample) for a in args]
    run_bad([sample, tmp_path], [*args, option, value, "-o", tmp_path / "out"], 2,
            f"'{option}'", "not a finite")   # number, or length (a length option)


@pytest.mark.parametrize("value, what", [(float("nan"), "NaN"), (1e999, "inf"),
                                         (-1e999, "-inf")])
def test_non_finite_mold_profile_reaches_no_cut_file(sample, tmp_path, value, what):
    """data.profile.r[1] = NaN (or 1e999, which Python's json reads as inf) in a mold: nest
    --mold refuses it before nesting, naming the file and the field."""
    mold = copy_artifact(sample / "mold.json", tmp_path, "bad",
                         lambda d: d["data"]["profile"]["r"].__setitem__(1, value))
    text = (tmp_path / "bad.json").read_text()
    if what != "NaN":  # json.dumps writes Infinity; write the number as a mold shop might
        (tmp_path / "bad.json").write_text(text.replace("Infinity", "1e999"))
    run_bad([sample, tmp_path], ["nest", sample / "flat", "--mold", mold, "--sheet", "700x500",
                                 "--scale", 100, "-o", tmp_path / "sheets"], 1,
            "bad.json", "data.profile.r[1]", what)


@pytest.mark.parametrize("command, kind, edit, field", [
    (["nest", "{a}", "--sheet", "700x500", "--scale", 100], "flat",
     lambda d: d["data"]["parts"][0]["geodesics"][0][1].__setitem__(0, float("nan")),
     "data.parts[0].geodesics[0][1][0]"),
    (["planarize-strips", "{a}"], "cat",
     lambda d: d["data"].__setitem__("extra", [1, 2, float("-inf")]), "data.extra[2]"),
    (["inspect", "{a}"], "strips",
     lambda d: d["metrics"].__setitem__("huge", 10 ** 400), "metrics.huge"),
])
def test_non_finite_number_in_any_artifact(sample, tmp_path, command, kind, edit, field):
    bad = copy_artifact(sample / f"{kind}.json", tmp_path, "bad", edit)
    args = [str(a).format(a=bad) for a in command]
    out = [] if command[0] == "inspect" else ["-o", tmp_path / "out"]
    result = run_bad([sample, tmp_path], [*args, *out], 1, "bad.json", field)
    assert result.stdout == ""


# -- item 3: --force leaves no file of the previous output behind ------------------------------

def test_force_removes_the_sheets_of_a_previous_longer_layout(sample, tmp_path):
    out = tmp_path / "sh"
    dgpc("nest", sample / "flat", "--sheet", "700x500", "--scale", 100, "-o", out)
    many = sorted(p.name for p in tmp_path.glob("sh.sheet*"))
    dgpc("nest", sample / "flat", "--sheet", "2500x1250", "--scale", 100, "-o", out, "--force")
    doc = json.loads((tmp_path / "sh.json").read_text())
    listed = {r["path"] for r in doc["data"]["files"].values()} | {doc["data"]["obj"]}
    assert len(many) > 3 * doc["data"]["sheet_count"] > 0
    assert {p.name for p in tmp_path.iterdir()} == listed | {"sh.json"}
    assert not list(tmp_path.glob(".*"))


def test_force_removes_the_figures_of_a_previous_report(sample, tmp_path):
    user_file = tmp_path / "r-notes.png"            # not the report's: never removed
    user_file.write_bytes(b"mine")
    first = dgpc("report", sample / "cat", "-o", tmp_path / "r").stdout.split()
    second = dgpc("report", sample / "mold", "-o", tmp_path / "r", "--force").stdout.split()
    assert set(first) - set(second)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [user_file.name] + [p.rsplit("/", 1)[-1] for p in second])


def test_force_keeps_files_an_artifact_does_not_own(sample, tmp_path):
    """Paths in the previous JSON that lead out of its folder or to another stem are never
    removed."""
    dgpc("unfold", sample / "strips", "-o", tmp_path / "f")
    other = tmp_path / "other.txt"
    other.write_text("keep")
    doc = json.loads((tmp_path / "f.json").read_text())
    doc["data"]["files"]["parts_csv"]["path"] = "other.txt"
    doc["data"]["files"]["evil"] = {"path": f"../{tmp_path.name}/f.keep", "sha256": "0" * 64}
    (tmp_path / "f.keep").write_text("keep")
    (tmp_path / "f.json").write_text(json.dumps(doc))
    dgpc("unfold", sample / "strips", "-o", tmp_path / "f", "--force")
    assert other.read_text() == "keep" and (tmp_path / "f.keep").read_text() == "keep"


# -- item 10: paths -----------------------------------------------------------------------------

COMMAND_LINES = {
    "init": ["init", "--surface", "revolution", "--profile", "catenoid", "--rows", 5,
             "--cols", 5],
    "optimize": ["optimize", "{d}/cat", "--mode", "revolution"],
    "extract-mold": ["extract-mold", "{d}/cat"],
    "planarize-strips": ["planarize-strips", "{d}/cat"],
    "unfold": ["unfold", "{d}/strips"],
    "nest": ["nest", "{d}/flat", "--sheet", "700x500"],
    "report": ["report", "{d}/cat"],
    "laths": ["laths", "{d}/cat", "{d}/cat"],
    "batch": ["batch", "{d}/project.toml"],
    "edit": ["edit", "{d}/cat", "--replay", "{d}/drags.json"],
}


def test_every_command_with_an_output_is_listed():
    ctx = click.Context(cli)
    with_output = {name for name in COMMANDS
                   if any("-o" in p.opts for p in cli.get_command(ctx, name).params)}
    assert with_output == set(COMMAND_LINES)


@pytest.mark.parametrize("output", ["", " ", ".", "..", "sub/", "{t}/"])
@pytest.mark.parametrize("command", sorted(COMMAND_LINES))
def test_output_without_a_file_name_is_a_usage_error(sample, tmp_path, monkeypatch, command,
                                                     output):
    if command == "batch" and output not in ("", " "):
        return  # batch writes into a folder: only the empty path is no folder
    (sample / "project.toml").touch()
    monkeypatch.chdir(tmp_path)
    args = [str(a).format(d=sample) for a in COMMAND_LINES[command]]
    run_bad([sample, tmp_path], [*args, "-o", output.format(t=tmp_path)], 2, "'--output'")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args", [
    ["init", "{x}.obj", "--method", "project", "--direction", "0,0,1"],
    ["init", "{x}.stl", "--method", "geodesic"],
    ["init", "--from-quads", "{x}.obj"],
    ["init", "--surface", "revolution", "--profile", "{x}.csv", "--rows", 5, "--cols", 5],
    ["optimize", "{d}/cat", "--mode", "fit", "--reference", "{x}.obj"],
    ["optimize", "{d}/cat", "--mode", "isometric", "--handles", "{x}.json"],
    ["optimize", "{x}", "--mode", "revolution"],
    ["extract-mold", "{x}"],
    ["planarize-strips", "{x}"],
    ["unfold", "{x}"],
    ["nest", "{x}", "--sheet", "700x500"],
    ["nest", "{d}/flat", "--mold", "{x}", "--sheet", "700x500"],
    ["laths", "{d}/cat", "{x}"],
    ["report", "{x}"],
    ["inspect", "{x}"],
])
def test_a_folder_as_an_input_file_is_bad_data(sample, tmp_path, args):
    """A folder where a mesh, profile, handles file or artifact is expected: exit 1 (an
    unreadable input, SPEC §2) everywhere, naming it."""
    x = tmp_path / "in"
    for suffix in (".obj", ".stl", ".csv", ".json"):
        (tmp_path / f"in{suffix}").mkdir()
    args = [str(a).format(d=sample, x=x) for a in args]
    out = [] if args[0] == "inspect" else ["-o", tmp_path / "out"]
    run_bad([sample, tmp_path], [*args, *out], 1, "in", "directory")


# -- item 4: the OBJs of every artifact are parsed and checked against their JSON --------------

def _vertex_line(lines, k=0):
    return [i for i, line in enumerate(lines) if line.startswith(b"v ")][k]


def _edit_lines(change):
    def edit(data):
        lines = data.splitlines()
        change(lines)
        return b"\n".join(lines) + b"\n"
    return edit


OBJ_EDITS = {
    "garbage": lambda data: bytes(range(256)) * 8,
    "text": lambda data: b"this is not an OBJ file\n",
    "empty": lambda data: b"",
    "truncated": lambda data: data[: len(data) // 2].rsplit(b"\n", 1)[0] + b"\n",
    "vertex-removed": _edit_lines(lambda ls: ls.pop(_vertex_line(ls, 1))),
    "vertex-added": _edit_lines(lambda ls: ls.insert(_vertex_line(ls) + 1, b"v 0.5 0.5 0.0")),
    "nan": _edit_lines(lambda ls: ls.__setitem__(_vertex_line(ls, 1), b"v nan 0.0 0.0")),
    "inf": _edit_lines(lambda ls: ls.__setitem__(_vertex_line(ls, 2), b"v 1.0 1e999 0.0")),
    "huge": _edit_lines(lambda ls: ls.__setitem__(_vertex_line(ls, 3), b"v 1e308 0.0 0.0")),
}

#: kind -> (the OBJ's suffix, its sha256 field, the commands that read it; {x} the artifact).
OBJ_READERS = {
    "flat": (".obj", ("obj_sha256",), [["nest", "{x}", "--sheet", "2500x1250", "--scale", 100],
                                       ["inspect", "{x}"]]),
    "mold": (".obj", ("obj_sha256",), [["nest", "{d}/flat", "--mold", "{x}", "--sheet",
                                        "2500x1250", "--scale", 100]]),
    "mold-panels": (".panels.obj", ("files", "panels_obj", "sha256"), [["inspect", "{x}"]]),
    "sheets": (".obj", ("obj_sha256",), [["report", "{x}"], ["inspect", "{x}"]]),
    "strips": (".obj", ("obj_sha256",), [["unfold", "{x}"], ["inspect", "{x}"]]),
    "shell": (".obj", ("obj_sha256",), [["inspect", "{x}"], ["report", "{x}"]]),
    "cat": (".obj", ("obj_sha256",), [["planarize-strips", "{x}"], ["inspect", "{x}"],
                                      ["optimize", "{x}", "--mode", "revolution"],
                                      ["extract-mold", "{x}"]]),
}


@pytest.mark.parametrize("edit", sorted(OBJ_EDITS))
@pytest.mark.parametrize("kind", sorted(OBJ_READERS))
def test_edited_obj_with_its_hash_updated(sample, tmp_path, kind, edit):
    """Garbage, truncated, one vertex less or more, NaN or inf in the OBJ of any artifact,
    the sha256 in its JSON updated to match: exit 1, one line naming the OBJ."""
    suffix, field, commands = OBJ_READERS[kind]
    data = OBJ_EDITS[edit]((sample / f"{kind.split('-')[0]}{suffix}").read_bytes())

    def update(doc):
        record = doc["data"]
        for key in field[:-1]:
            record = record[key]
        record[field[-1]] = hashlib.sha256(data).hexdigest()

    bad = copy_artifact(sample / f"{kind.split('-')[0]}.json", tmp_path, "bad", update)
    (tmp_path / f"bad{suffix}").write_bytes(data)
    for command in commands:
        args = [str(a).format(d=sample, x=bad) for a in command]
        out = [] if args[0] == "inspect" else ["-o", tmp_path / "out"]
        result = run_bad([sample, tmp_path], [*args, *out], 1, f"bad{suffix}")
        assert result.stdout == ""


# -- item 9: the files an artifact lists lie in its folder; a recorded reference is checked -----

#: kind -> the listed files moved out of the artifact's folder ((field path in data, suffix)),
#: and the commands that read them ({x} the artifact, {d} the sample folder).
LISTED = {
    "mold": ([(("obj",), ".obj"), (("files", "profile_csv", "path"), ".profile.csv"),
              (("files", "panels_obj", "path"), ".panels.obj")],
             [["nest", "{d}/flat", "--mold", "{x}", "--sheet", "2500x1250", "--scale", 100],
              ["inspect", "{x}"], ["report", "{x}"]]),
    "sheets": ([(("files", "sheet01_png", "path"), ".sheet01.png"), (("obj",), ".obj")],
               [["report", "{x}"], ["inspect", "{x}"]]),
    "shell": ([(("cut_list",), ".csv")], [["inspect", "{x}"], ["report", "{x}"]]),
    "flat": ([(("files", "parts_csv", "path"), ".parts.csv")],
             [["nest", "{x}", "--sheet", "2500x1250", "--scale", 100]]),
    "cat": ([(("obj",), ".obj")], [["planarize-strips", "{x}"], ["inspect", "{x}"]]),
}


def _listed_cases():
    for kind, (fields, commands) in sorted(LISTED.items()):
        for field, suffix in fields:
            for how in ("absolute", "dotdot", "symlink"):
                yield pytest.param(kind, field, suffix, how, commands,
                                   id=f"{kind}-{'.'.join(field)}-{how}")


@pytest.mark.parametrize("kind, field, suffix, how, commands", list(_listed_cases()))
def test_a_listed_file_outside_the_artifacts_folder(sample, tmp_path, kind, field, suffix,
                                                    how, commands):
    """A listed file moved out of the artifact's folder, its path in the JSON an absolute one
    or one with '..' (or the JSON unchanged and a symbolic link left in the file's place), its
    sha256 still matching: exit 1, one line naming the JSON and field."""
    art, elsewhere = tmp_path / "art", tmp_path / "elsewhere"
    art.mkdir()
    elsewhere.mkdir()
    moved = elsewhere / f"bad{suffix}"
    target = {"absolute": str(moved), "dotdot": f"../elsewhere/bad{suffix}",
              "symlink": f"bad{suffix}"}[how]

    def point_out(doc):
        record = doc["data"]
        for key in field[:-1]:
            record = record[key]
        record[field[-1]] = target

    bad = copy_artifact(sample / f"{kind}.json", art, "bad", point_out)
    (art / f"bad{suffix}").rename(moved)
    if how == "symlink":
        (art / f"bad{suffix}").symlink_to(moved)
    name = ".".join(("data", *(field[:-1] if field[-1] == "path" else field)))
    for command in commands:
        args = [str(a).format(d=sample, x=bad) for a in command]
        out = [] if args[0] == "inspect" else ["-o", tmp_path / "out"]
        result = run_bad([sample, tmp_path], [*args, *out], 1, "bad.json", name, target)
        assert result.stdout == ""
        assert {"absolute": "absolute", "dotdot": "'..'",
                "symlink": "symbolic link"}[how] in result.stderr


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A small net of revolution whose reference mesh is recorded one folder up ('..')."""
    d = tmp_path_factory.mktemp("reference")
    (d / "nets").mkdir()
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 7, "--cols", 5,
         "--reference-out", d / "ref.obj", "-o", d / "nets" / "net")
    return d


def test_a_recorded_reference_may_lie_elsewhere(fitted, tmp_path):
    """The exception: a reference mesh recorded outside the net's folder is used (sha256
    checked) by optimize --mode fit, inspect and report."""
    assert json.loads((fitted / "nets" / "net.json").read_text())["data"]["reference"][
        "path"] == "../ref.obj"
    result = dgpc("optimize", fitted / "nets" / "net", "--mode", "fit", "--max-iter", 2,
                  "-o", tmp_path / "fit", expect=None)
    assert result.exit_code in (0, 3), result.stderr
    assert "hausdorff" in json.loads(dgpc("inspect", fitted / "nets" / "net").stdout)


@pytest.mark.parametrize("command", [["optimize", "{n}", "--mode", "fit", "-o", "{o}/fit"],
                                     ["inspect", "{n}"], ["report", "{n}", "-o", "{o}/r"]])
def test_a_changed_recorded_reference_is_refused(fitted, tmp_path, command):
    """The recorded reference edited after the net was written: every command that uses it
    refuses it (exit 1, one line naming the net and data.reference), before any solve."""
    d = tmp_path / "copy"
    shutil.copytree(fitted, d)
    with open(d / "ref.obj", "ab") as fh:
        fh.write(b"v 0 0 0\n")
    args = [a.format(n=d / "nets" / "net", o=tmp_path) for a in command]
    result = run_bad([d, tmp_path], args, 1, "net.json", "data.reference", "../ref.obj",
                     "sha256")
    assert result.stdout == ""


@pytest.mark.parametrize("edit, words", [
    pytest.param(lambda r: r.pop("sha256"), ["no sha256 recorded"], id="no-sha256"),
    pytest.param(lambda r: r.__setitem__("path", "../../nowhere.obj"), ["missing"],
                 id="missing"),
])
def test_a_recorded_reference_without_a_hash_or_file(fitted, tmp_path, edit, words):
    d = tmp_path / "copy"
    shutil.copytree(fitted, d)
    doc = json.loads((d / "nets" / "net.json").read_text())
    edit(doc["data"]["reference"])
    (d / "nets" / "net.json").write_text(json.dumps(doc))
    run_bad([d, tmp_path], ["optimize", d / "nets" / "net", "--mode", "fit",
                            "-o", tmp_path / "fit"], 1, "net.json", "data.reference", *words)


# -- item 6: a net beyond the memory limit is refused before it is made -------------------------

FELT = Path(__file__).resolve().parents[1] / "samples" / "meshes" / "felt.obj"


@pytest.mark.parametrize("args, option", [
    (["--surface", "revolution", "--profile", "catenoid", "--rows", 100000, "--cols", 100000],
     "--rows/--cols"),
    ([FELT, "--method", "geodesic", "--rows", 100000, "--cols", 100000], "--rows/--cols"),
    ([FELT, "--method", "geodesic", "--cols", 100000], "--rows/--cols"),
    ([FELT, "--method", "geodesic", "--edge-length", 1e-9], "--edge-length"),
    ([FELT, "--method", "project", "--direction", "0,0,1", "--edge-length", 1e-300],
     "--edge-length"),
    ([FELT, "--method", "project", "--direction", "0,0,1", "--rows", 3000, "--cols", 3000],
     "--rows/--cols"),
], ids=["revolution", "geodesic-rows-cols", "geodesic-cols", "geodesic-spacing",
        "project-spacing", "project-rows-cols"])
def test_a_net_beyond_the_memory_limit_is_refused(tmp_path, args, option):
    result = run_bad([tmp_path], ["init", *args, "-o", tmp_path / "big"], 1, option,
                     "memory", "beyond the limit of 4 GiB")
    assert result.stdout == "" and not any(tmp_path.iterdir())


def test_optimize_and_from_quads_beyond_the_memory_limit_are_refused(sample, tmp_path):
    """optimize estimates its memory from the net's shape before reading its OBJ (6 KiB a
    vertex); --from-quads counts the OBJ's vertices before parsing it."""
    big = copy_artifact(sample / "cat.json", tmp_path, "big",
                        lambda doc: doc["data"].update(shape=[900, 900]))
    result = run_bad([tmp_path], ["optimize", big, "--mode", "revolution", "-o",
                                  tmp_path / "out"], 1, "big.json", "revolution", "900 × 900",
                     "memory", "beyond the limit of 4 GiB")
    assert result.stdout == ""
    (tmp_path / "q.obj").write_bytes(b"v 0 0 0\n" * 2_200_000)
    run_bad([tmp_path], ["init", "--from-quads", tmp_path / "q.obj", "-o", tmp_path / "out"],
            1, "q.obj", "2200000 vertices", "beyond the limit of 4 GiB")


def test_the_memory_limit():
    from dgpc_cli.layout.net_size import MAX_NET_BYTES, check_net_size

    check_net_size(1448, 1448, "--rows/--cols", "")
    for m, n in ((1449, 1448), (float("inf"), 3), (1e300, 1e300)):
        with pytest.raises(DgpcError):
            check_net_size(m, n, "--rows/--cols", "")
    assert MAX_NET_BYTES == 4 * 2**30  # the README documents it


# -- item 5: extreme but finite numbers end in one line, not an internal error ------------------

def test_a_profile_row_at_1e308(tmp_path):
    (tmp_path / "p.csv").write_text("r,h\n1,0\n1.2,0.5\n1e308,1e308\n")
    run_bad([tmp_path], ["init", "--surface", "revolution", "--profile", tmp_path / "p.csv",
                         "--rows", 9, "--cols", 7, "-o", tmp_path / "out"], 1,
            "p.csv", "line 4", "1e+308")


def test_a_mesh_vertex_at_1e308(tmp_path):
    text = FELT.read_text().splitlines()
    k = next(i for i, line in enumerate(text) if line.startswith("v "))
    text[k] = "v 1e308 0 0"
    (tmp_path / "m.obj").write_text("\n".join(text) + "\n")
    run_bad([tmp_path], ["init", tmp_path / "m.obj", "--method", "geodesic",
                         "-o", tmp_path / "out"], 1, "m.obj", "vertex 1", "1e+308")


def test_a_handle_at_1e308(sample, tmp_path):
    (tmp_path / "h.json").write_text(json.dumps(
        {"handles": [{"index": [0, 0], "target": [1e308, 0, 0]}]}))
    run_bad([sample, tmp_path], ["optimize", sample / "cat", "--mode", "isometric", "--handles",
                                 tmp_path / "h.json", "-o", tmp_path / "out"], 1,
            "h.json", "handles[0].target", "1e+308")


@pytest.mark.parametrize("kind, edit, field", [
    ("flat", lambda d: d["data"]["parts"][0]["geodesics"][0][1].__setitem__(0, 1e308),
     "data.parts[0].geodesics[0][1]"),
    ("flat", lambda d: d["data"]["parts"][1]["outline"][2].__setitem__(1, -1e300),
     "data.parts[1].outline[2]"),
    ("mold", lambda d: d["data"]["profile"]["r"].__setitem__(1, 1e308), "data.profile.r[1]"),
])
def test_a_number_at_1e308_in_an_artifact(sample, tmp_path, kind, edit, field):
    bad = copy_artifact(sample / f"{kind}.json", tmp_path, "bad", edit)
    args = (["nest", bad] if kind == "flat" else ["nest", sample / "flat", "--mold", bad])
    run_bad([sample, tmp_path], [*args, "--sheet", "2500x1250", "--scale", 100,
                                 "-o", tmp_path / "out"], 1, "bad.json", field, "beyond")


@pytest.mark.parametrize("args, option", [
    (["--sheet", "1e308x1e308"], "--sheet"),
    (["--sheet", "2500x1250", "--margin", 1e300], "--margin"),
    (["--sheet", "2500x1250", "--spacing", 1e300], "--spacing"),
    (["--sheet", "2500x1250", "--scale", 1e308], "--scale"),
])
def test_a_huge_nest_option(sample, tmp_path, args, option):
    """Lengths beyond the one limit of every length are usage errors; a scale that takes the
    parts beyond it is bad data."""
    run_bad([sample, tmp_path], ["nest", sample / "flat", *args, "-o", tmp_path / "out"],
            1 if option == "--scale" else 2, option, "beyond")


@pytest.mark.parametrize("args, option", [
    ([FELT, "--method", "geodesic", "--extend", 1e308], "--extend"),
    ([FELT, "--method", "geodesic", "--extend", 1e30], "--extend"),
    (["--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
      "--twist", 1e308], "--twist"),
])
def test_a_huge_init_option(tmp_path, args, option):
    """Beyond the option's range (shown in its help): a usage error."""
    run_bad([tmp_path], ["init", *args, "-o", tmp_path / "out"], 2, option, "range")


def test_a_non_manifold_mesh(tmp_path):
    """A fin on an inner edge of the mesh (three faces on one edge) is refused on reading,
    not deep in the geodesic tracer."""
    lines = FELT.read_text().splitlines()
    vertices = sum(line.startswith("v ") for line in lines)
    faces = [line for line in lines if line.startswith("f ")]
    a, b = (p.split("/")[0] for p in faces[len(faces) // 2].split()[1:3])
    lines += ["v 0 0 50", f"f {a} {b} {vertices + 1}"]
    (tmp_path / "fin.obj").write_text("\n".join(lines) + "\n")
    run_bad([tmp_path], ["init", tmp_path / "fin.obj", "--method", "geodesic",
                         "-o", tmp_path / "out"], 1, "fin.obj", "not a manifold mesh",
            "borders 3 faces")


# -- found by trying the hardening as a user would ----------------------------------------------

def test_a_shape_of_floats_or_an_oversized_net_obj(sample, tmp_path):
    """data.shape [9.0, 7] (JSON Schema takes it for integers) and a net OBJ of 300,000
    vertices for a 9 × 7 net (sha256 updated): one line each, refused before the OBJ is
    parsed."""
    floats = copy_artifact(sample / "cat.json", tmp_path, "floats",
                           lambda doc: doc["data"].update(shape=[9.0, 7]))
    for args in (["inspect", floats], ["optimize", floats, "--mode", "revolution", "-o",
                                       tmp_path / "out"]):
        run_bad([tmp_path], args, 1, "floats.json", "data.shape", "whole numbers")
    data = b"v 1 2 3\n" * 300_000
    big = copy_artifact(sample / "cat.json", tmp_path, "big", lambda doc: doc["data"].update(
        obj_sha256=hashlib.sha256(data).hexdigest()))
    (tmp_path / "big.obj").write_bytes(data)
    run_bad([tmp_path], ["inspect", big], 1, "big.obj", "300000 vertices", "9 x 7 = 63")


def test_an_unreadable_journal_says_what_to_do(sample, tmp_path):
    art = copy_artifact(sample / "cat.json", tmp_path, "net")
    (tmp_path / ".net.json.journal").write_text("garbage")
    run_bad([tmp_path], ["inspect", art], 1, ".net.json.journal", "remove it")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_stdout_on_a_full_disk_is_one_line(sample):
    import subprocess
    import sys

    with open("/dev/full", "w") as full:
        result = subprocess.run([str(Path(sys.executable).parent / "dgpc"), "inspect",
                                 str(sample / "cat")], stdout=full, stderr=subprocess.PIPE,
                                text=True)
    assert result.returncode == 1
    assert result.stderr.strip().splitlines() == [
        "Error: cannot write the output: No space left on device"]


def test_a_scale_that_shrinks_the_parts_below_a_kerf(sample, tmp_path):
    run_bad([sample, tmp_path], ["nest", sample / "flat", "--sheet", "2500x1250", "--scale",
                                 1e-15, "-o", tmp_path / "s"], 1, "--scale",
            "below 0.1 mm")
