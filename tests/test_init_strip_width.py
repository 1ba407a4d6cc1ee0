"""init's largest strip width (issue 27: the default net on an arched roof had strips up to 4 m
wide, so no part fit a 2500 mm sheet): where init chooses the columns, no strip of the net is
wider than --strip-width (default 2.4 m for a mesh in a unit, none without one); given --cols
win, and init warns."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.io.mesh import write_mesh_obj
from dgpc_cli.io.net import read_net
from dgpc_cli.layout.width import MAX_COLS, default_limit, next_cols
from dgpc_cli.metrics.width_ratio import widest_strip

#: The cap's size and its sphere's radius (m): geodesics from the middle section converge
#: away from it, so its strips are widest there.
SIZE, RADIUS = 10.0, 10.0
LIMIT = 0.3
#: The base curve given, the net kept on the mesh: one candidate, quick.
GIVEN = ("--direction", "1,0,0", "--extend", 0)


@pytest.fixture(scope="module")
def cap(tmp_path_factory):
    """A spherical cap in metres over a 10 × 10 m square, 30 × 30 cells."""
    k = 30
    u, v = np.meshgrid(np.linspace(-SIZE / 2, SIZE / 2, k + 1),
                       np.linspace(-SIZE / 2, SIZE / 2, k + 1), indexing="ij")
    z = np.sqrt(RADIUS ** 2 - u ** 2 - v ** 2)
    V = np.stack([u.ravel(), v.ravel(), z.ravel()], 1)
    vid = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                        np.stack([a, c, d], -1).reshape(-1, 3)])
    path = tmp_path_factory.mktemp("cap") / "cap.obj"
    path.write_bytes(write_mesh_obj(path, V, F))
    return path


def _widest(stem) -> float:
    return widest_strip(read_net(stem).f)[0]


def _record(stem) -> dict | None:
    doc = json.loads((stem.parent / f"{stem.name}.json").read_text())
    return doc["data"]["init"]["choice"].get("strip_width")


def test_widest_strip_and_the_columns_it_needs():
    """The widest v-edge over the kept ones, and its strip; the columns that bring 21 columns
    3 m wide within 2.4 m (ceil(20 · 3/2.4) + 1 = 26), capped."""
    f = np.zeros((3, 4, 3))
    f[..., 0] = [[0, 1, 2, 3], [0, 1, 3.5, 4], [0, 2, 3, 4]]
    assert widest_strip(f) == (2.5, 1)
    keep = np.ones((3, 3), bool)
    keep[1, 1] = False
    assert widest_strip(f, keep) == (2.0, 0)
    assert widest_strip(f, np.zeros((3, 3), bool)) is None
    assert next_cols(21, 3.0, 2.4) == 26
    assert next_cols(21, 2.41, 2.4) == 22             # at least one more
    assert next_cols(61, 10.0, 1.0) == MAX_COLS and next_cols(MAX_COLS, 10.0, 1.0) is None
    assert default_limit("m", True) == pytest.approx(2.4)
    assert default_limit("mm", True) == pytest.approx(2400.0)
    assert default_limit("m", False) is None


def test_init_makes_no_strip_wider_than_the_limit(cap, tmp_path):
    """Its default 21 columns are too wide for 0.3 m at the rim: init makes the net again with
    more columns, and every strip of the net written is at most 0.3 m wide everywhere along
    it; the record and stderr say so. A length in mm means the same."""
    r = dgpc("init", cap, "--units", "m", *GIVEN, "--strip-width", "0.3m",
             "-o", tmp_path / "n")
    record = _record(tmp_path / "n")
    assert record["limit"] == pytest.approx(LIMIT) and record["given"]
    assert record["chooses_columns"] and record["within"]
    first = record["steps"][0]
    assert first["cols"] == 21 and first["widest"] > LIMIT        # too wide as first made
    assert len(record["steps"]) >= 2
    net = read_net(tmp_path / "n")
    assert net.shape[1] == record["cols"] > 21
    assert _widest(tmp_path / "n") <= LIMIT * (1 + 1e-9)
    assert record["widest"] == pytest.approx(_widest(tmp_path / "n"))
    assert net.parameters["strip_width"] == pytest.approx(LIMIT)
    assert f"kept {record['cols']} columns" in r.stderr
    dgpc("init", cap, "--units", "m", *GIVEN, "--strip-width", "300mm",
         "-o", tmp_path / "mm")
    assert read_net(tmp_path / "mm").shape == net.shape


def test_given_columns_win_and_init_warns(cap, tmp_path):
    """--cols 11 with a limit its strips exceed: 11 columns as asked, a warning naming
    --strip-width, the record says it is not within."""
    r = dgpc("init", cap, "--units", "m", *GIVEN, "--cols", 11,
             "--strip-width", "0.3m", "-o", tmp_path / "n")
    assert read_net(tmp_path / "n").shape[1] == 11
    assert _widest(tmp_path / "n") > LIMIT
    record = _record(tmp_path / "n")
    assert not record["within"] and not record["chooses_columns"]
    assert len(record["steps"]) == 1
    assert "more than --strip-width 0.3 m" in r.stderr


def test_no_default_limit_without_units(cap, tmp_path):
    """Without --units the mesh's size is not known: no limit, nothing recorded."""
    dgpc("init", cap, *GIVEN, "-o", tmp_path / "n")
    assert _record(tmp_path / "n") is None
    dgpc("init", cap, *GIVEN, "--units", "m", "-o", tmp_path / "m")
    record = _record(tmp_path / "m")
    assert record["limit"] == pytest.approx(2.4) and not record["given"]
    assert record["within"] and len(record["steps"]) == 1


def test_strip_width_goes_with_a_mesh():
    r = dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
             "--strip-width", "1m", "-o", "x", expect=2)
    assert "--strip-width goes with REFERENCE" in r.stderr


def test_a_projected_net_is_made_finer_too(cap, tmp_path):
    """--method project: the same rule, the grid made again with more columns."""
    dgpc("init", cap, "--method", "project", "--units", "m", "--strip-width", "0.3m",
         "-o", tmp_path / "n")
    record = _record(tmp_path / "n")
    assert record["steps"][0]["widest"] > LIMIT and record["within"]
    assert read_net(tmp_path / "n").shape[1] == record["cols"] > 21
    assert _widest(tmp_path / "n") <= LIMIT * (1 + 1e-9)


@pytest.mark.parametrize("width", ["1e-9m", "0.01m"])
def test_a_strip_width_that_cannot_be_met_is_refused(cap, tmp_path, width):
    """Where init chooses the columns, a given --strip-width no net of at most MAX_COLS
    columns meets (1 nm; 1 cm on a 10 m cap, 100 columns at least) is an error naming the
    option, exit 1, nothing written; not a net written with a warning."""
    r = dgpc("init", cap, "--units", "m", *GIVEN, "--strip-width", width,
             "-o", tmp_path / "n", expect=1)
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert lines[-1].startswith("Error: --strip-width: ") and "cannot be met" in lines[-1]
    assert f"at most {MAX_COLS} columns" in lines[-1]
    assert not any(line.startswith("warning") for line in lines)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, words", [
    (["--strip-width", 2400], "--strip-width 2400 read as m (the net's unit) is a 2400 m strip "
                              "width, above the mesh's diagonal (14.44 m); did you mean 2400mm?"),
    (["--edge-length", 250], "--edge-length 250 read as m (the net's unit) is a 250 m edge, "
                             "above half the mesh's diagonal (7.2"),
])
def test_a_plain_length_far_off_the_mesh_is_a_usage_error(cap, tmp_path, args, words):
    """With --units m a plain 2400 meant in mm is a 2400 m strip on a 10 m cap: refused once
    the mesh is read, before any net is made, naming both readings; nothing written."""
    r = dgpc("init", cap, "--units", "m", *GIVEN, *args, "-o", tmp_path / "n", expect=2)
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and words in lines[0]
    assert list(tmp_path.iterdir()) == []
