"""Bounds on every input (issue "nothing destroyed, nothing corrupt"), each refused in one line
with no traceback and nothing written:

* option values that would need absurd memory or time, or overflow the engine: ``--refine``
  (1 to 16), ``nest --seed`` (0 to 2^32 - 1) and ``--time-limit`` (finite, at most a day);
* files that are not what a mesh or an artifact can be: a device (``/dev/zero``), a named
  pipe, a symbolic link loop, a file over 2 GiB;
* a mesh pinched at a vertex (a bow-tie: two boundary loops through one vertex), named by the
  vertex's index in the file, in ``init`` and inside ``batch``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import dgpc
from refusals import refused, tree

from dgpc_cli.io.bounded_read import MAX_FILE_BYTES
from dgpc_cli.io.mesh import pinched_vertices

DGPC = str(Path(sys.executable).parent / "dgpc")
PROFILE = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"


@pytest.fixture(scope="module")
def walls(tmp_path_factory) -> Path:
    """A wall's net ``n`` and its flat ``f`` (its strips ``s``)."""
    d = tmp_path_factory.mktemp("walls")
    dgpc("init", "--surface", "revolution", "--profile", PROFILE, "--rows", 9, "--cols", 5,
         "--span", 40, "--units", "m", "-o", d / "n")
    dgpc("planarize-strips", d / "n", "-o", d / "s")
    dgpc("unfold", d / "s", "-o", d / "f")
    return d


@pytest.mark.parametrize("args, needle", [
    (("planarize-strips", "n", "--refine", 17), "17 is not from 1 to 16"),
    (("planarize-strips", "n", "--refine", 5000), "5000 is not from 1 to 16"),
    (("planarize-strips", "n", "--refine", "9" * 20), "999999…(20 digits) is not from 1 to 16"),
    (("planarize-strips", "n", "--refine", 0), "0 is not from 1 to 16"),
    (("planarize-strips", "n", "--refine", "1e3"), "neither an integer from 1 to 16"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--seed", 2**64), "--seed"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--seed", 2**32), "--seed"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--seed", -1), "--seed"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--time-limit", "1e308"),
     "--time-limit"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--time-limit", "inf"),
     "--time-limit"),
    (("nest", "f", "--sheet", "7000x3000", "--engine", "spyrrow", "--time-limit", 86401),
     "--time-limit"),
])
def test_option_values_out_of_bounds_are_usage_errors(walls, monkeypatch, args, needle):
    monkeypatch.chdir(walls)
    before = tree(walls)
    r = dgpc(*args, "-o", "out", expect=2)
    refused(r.stderr, r.exit_code, 2, needle)
    assert "OverflowError" not in r.stderr and tree(walls) == before


def test_the_bounds_themselves_are_accepted(walls, tmp_path):
    """The largest --refine runs; the largest seed and time limit pass the option parsing
    (the nesting itself is not run: --sheet is too small for the part, exit 1 before it)."""
    dgpc("planarize-strips", walls / "n", "--strips", "0:0", "--refine", 16, "-o", tmp_path / "s")
    r = dgpc("nest", walls / "f", "--sheet", "100x100", "--engine", "spyrrow", "--seed",
             2**32 - 1, "--time-limit", 86400, "-o", tmp_path / "o", expect=1)
    refused(r.stderr, r.exit_code, 1, "does not fit")


def _init_mesh(path: Path, cwd: Path) -> subprocess.CompletedProcess:
    """``dgpc init PATH`` in a process of its own (a hang would be caught by its timeout)."""
    return subprocess.run([DGPC, "init", str(path), "-o", "net"], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


@pytest.mark.parametrize("make, needle", [
    (lambda d: os.symlink("/dev/zero", d / "zero.obj"), "is not a regular file"),
    (lambda d: os.mkfifo(d / "pipe.obj"), "is not a regular file"),
    (lambda d: (os.symlink(d / "b.obj", d / "a.obj"), os.symlink(d / "a.obj", d / "b.obj")),
     "symbolic link"),
    (lambda d: os.truncate(_touch(d / "huge.obj"), MAX_FILE_BYTES + 1), "larger than the 2 GiB"),
], ids=["dev-zero", "fifo", "symlink-loop", "over-2GiB"])
def test_a_mesh_that_is_no_regular_file_is_refused(tmp_path, make, needle):
    if not hasattr(os, "mkfifo"):
        pytest.skip("POSIX only")
    make(tmp_path)
    mesh = sorted(p for p in tmp_path.iterdir() if p.suffix == ".obj")[0]
    before = tree(tmp_path)
    r = _init_mesh(mesh, tmp_path)
    refused(r.stderr, r.returncode, 1, needle, mesh.name)
    assert tree(tmp_path) == before and not (tmp_path / "net.json").exists()


def _touch(path: Path) -> Path:
    path.touch()
    return path


@pytest.mark.parametrize("command", [("inspect", "z"), ("planarize-strips", "z", "-o", "out"),
                                     ("report", "z", "-o", "out")])
def test_an_artifact_json_that_is_a_device_is_refused(tmp_path, command):
    os.symlink("/dev/zero", tmp_path / "z.json")
    before = tree(tmp_path)
    r = subprocess.run([DGPC, *command], cwd=tmp_path, capture_output=True, text=True,
                       timeout=300)
    refused(r.stderr, r.returncode, 1, "z.json", "is not a regular file")
    assert tree(tmp_path) == before


def bowtie_obj(path: Path) -> tuple[Path, int]:
    """Two 8×8 grids of a gently curved sheet that touch at one corner (a bow-tie vertex, both
    grids' vertex there listed once); the path and that vertex's 1-based index in the file."""
    k = 8
    u, v = np.meshgrid(np.linspace(0.0, 1.0, k), np.linspace(0.0, 1.0, k), indexing="ij")
    grid = np.stack([u, v, 0.1 * np.sin(2 * u) * v], axis=-1).reshape(-1, 3)
    second = np.column_stack([2.0 - grid[:, 0], 2.0 - grid[:, 1], grid[:, 2]])
    vertices = np.vstack([grid, second])
    corner_a, corner_b = k * k - 1, k * k + k * k - 1       # (1, 1, z) in both
    assert np.allclose(vertices[corner_a], vertices[corner_b])
    vertices[corner_b] = vertices[corner_a]
    faces = []
    for offset in (0, k * k):
        for i in range(k - 1):
            for j in range(k - 1):
                a, b, c, d = (offset + i * k + j, offset + (i + 1) * k + j,
                              offset + (i + 1) * k + j + 1, offset + i * k + j + 1)
                faces += [(a, b, c), (a, c, d)]
    faces = np.array(faces)
    faces[faces == corner_b] = corner_a                     # one vertex for both corners
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path, corner_a + 1


def test_pinched_vertices_finds_the_bowtie_only():
    k = 4
    fan = np.array([[0, i, i % k + 1] for i in range(1, k + 1)])  # a closed fan around 0
    assert pinched_vertices(fan).size == 0
    two = np.vstack([fan, fan[:, [0, 2, 1]] + np.array([0, k, k])])  # a second fan at 0
    assert pinched_vertices(two).tolist() == [0]
    open_fan = fan[:-1]
    assert pinched_vertices(open_fan).size == 0
    assert pinched_vertices(np.vstack([open_fan, open_fan + np.array([0, k, k])])).tolist() \
        == [0]


def test_a_bowtie_mesh_is_refused_by_init(tmp_path):
    mesh, index = bowtie_obj(tmp_path / "bowtie.obj")
    before = tree(tmp_path)
    r = _init_mesh(mesh, tmp_path)
    line = refused(r.stderr, r.returncode, 1, "bowtie.obj", f"vertex {index} (1, 1, ",
                   "bow-tie")
    assert "GC_SAFETY" not in line and tree(tmp_path) == before


def test_a_bowtie_mesh_fails_its_patch_in_batch_in_one_line(tmp_path):
    bowtie_obj(tmp_path / "bowtie.obj")
    (tmp_path / "p.toml").write_text('[patches.a.init]\nreference = "bowtie.obj"\n')
    r = subprocess.run([DGPC, "-q", "batch", "p.toml", "-o", "out", "--workers", "1"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert r.returncode == 1, r.stderr
    message = json.loads((tmp_path / "out" / "batch.json").read_text())["patches"]["a"][
        "message"]
    assert "bow-tie" in message and "\n" not in message and "GC_SAFETY" not in message
    assert "Traceback" not in r.stderr and "GC_SAFETY" not in r.stderr
