"""init on a mesh aims at the whole surface (issue "cover the reference"): boundary curves as
base curves, an in-plane angle for both methods, the automatic choice, and no folded net
written: shrunk to its sound rectangle, or refused with a candidate that works."""

from types import SimpleNamespace

import numpy as np
import pytest
from cli_helpers import dgpc
from outline_meshes import clipped_dome, roof, write

from dgpc_cli.core.reference import ReferenceSurface
from dgpc_cli.errors import DgpcError
from dgpc_cli.geodesics.boundary import boundary_curves
from dgpc_cli.geodesics.extension import extend_mesh, folded_faces
from dgpc_cli.io.mesh import load_mesh
from dgpc_cli.io.net import read_net
from dgpc_cli.layout import choice as init_choice
from dgpc_cli.metrics.degenerate import degeneracies
from dgpc_cli.strips.planarize import trim_records


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    d = tmp_path_factory.mktemp("meshes")
    return {"roof": write(d / "roof.obj", roof()),
            "dome": write(d / "dome.obj", clipped_dome())}


def test_boundary_curves_are_the_outline_cut_at_its_corners(meshes):
    r = load_mesh(meshes["roof"])
    curves = boundary_curves(r.vertices, r.faces)
    assert [c.name for c in curves] == ["b1", "b2", "b3", "b4"]
    lengths = sorted(c.length for c in curves)
    assert lengths[0] == pytest.approx(12.0, rel=0.02) and lengths[3] > 20.0
    # b1 the straight edge y = 0 (the roof rises along it), b2 the curved edge, bulging out
    # to y = 12.5 in the middle
    assert np.abs(curves[0].curve.points[:, 1]).max() == 0.0
    assert curves[1].curve.points[:, 1].max() == pytest.approx(12.5, abs=1e-9)
    d = load_mesh(meshes["dome"])
    curves = boundary_curves(d.vertices, d.faces)
    assert len(curves) == 2
    ground, cut = curves                       # half the ground circle, then the cut arc
    assert np.abs(ground.curve.points[:, 2]).max() < 1e-9
    assert np.abs(cut.curve.points[:, 0] - 4.0).max() < 1e-9
    assert ground.length == pytest.approx(np.pi * 10 * (1 - np.arccos(0.4) / np.pi) * 2,
                                          rel=0.01)


def test_a_boundary_base_curve_is_the_first_row(meshes, tmp_path):
    dgpc("init", meshes["roof"], "--method", "geodesic", "--base", "b1", "--cols", 11,
         "--extend", 0, "-o", tmp_path / "n")
    net = read_net(tmp_path / "n")
    assert net.data["init"]["base"] == "boundary" and net.data["init"]["base_name"] == "b1"
    assert net.parameters["base"] == "b1"
    surface = ReferenceSurface.from_mesh(load_mesh(meshes["roof"]))
    foot, _ = surface.closest_on_boundary(net.f[0])
    assert np.linalg.norm(net.f[0] - foot, axis=1).max() <= 1e-9    # row 0 on the edge
    assert np.abs(net.f[0, :, 1]).max() <= 1e-9                     # b1: the edge y = 0
    assert net.f[-1, :, 1].min() > 10.0                               # geodesics run inwards
    r = dgpc("init", meshes["roof"], "--method", "geodesic", "--base", "b9", "-o",
             tmp_path / "x", expect=1)
    assert "--base" in r.stderr and "b4 (" in r.stderr


def test_the_angle_turns_the_grid_in_its_plane(meshes, tmp_path):
    for a in (0, 90):
        dgpc("init", meshes["roof"], "--method", "project", "--angle", a, "-o",
             tmp_path / f"p{a}")
    p0, p90 = read_net(tmp_path / "p0"), read_net(tmp_path / "p90")
    assert p90.data["init"]["angle"] == 90 and p90.parameters["angle"] == 90
    u0 = p0.f[-1, 0] - p0.f[0, 0]
    u90 = p90.f[-1, 0] - p90.f[0, 0]
    assert abs(u0[:2] @ u90[:2]) <= 1e-6 * np.linalg.norm(u0) * np.linalg.norm(u90)
    dgpc("init", meshes["roof"], "--method", "geodesic", "--angle", 90, "-o", tmp_path / "g")
    g = read_net(tmp_path / "g")
    assert g.data["init"]["angle"] == 90 and g.data["init"]["choice"]["chosen"] == "section 90°"


def test_a_folded_explicit_choice_is_shrunk_and_says_so(meshes, tmp_path):
    """Sections across the dome: the geodesics meet where the rim is; the net is shrunk to the
    largest sound rectangle, made again there, and stderr names the rows and columns."""
    r = dgpc("init", meshes["dome"], "--method", "geodesic", "--direction", "0,1,0",
             "-o", tmp_path / "n")
    assert "degenerate" in r.stderr and "rows" in r.stderr and "shrunk" in r.stderr
    net = read_net(tmp_path / "n")
    assert not degeneracies(net.f)
    assert net.data["init"]["shrunk"]["from"][0] > net.shape[0]


def test_a_mostly_folded_explicit_choice_is_refused(meshes, monkeypatch):
    """Where the sound rectangle keeps too little, init refuses: one line naming the rows and
    columns and the candidate that works."""
    monkeypatch.setattr(init_choice, "MIN_KEPT", 0.99)
    mesh = load_mesh(meshes["dome"])
    with pytest.raises(DgpcError) as err:
        init_choice.choose(mesh, mesh, "geodesic", direction=[0.0, 1.0, 0.0])
    msg = str(err.value)
    assert "degenerate" in msg and "rows" in msg and "columns" in msg
    assert "gives a sound net covering" in msg


def test_the_continuation_of_a_plane_cut_does_not_fold(meshes):
    """The dome's cut through the icosphere's equator leaves sliver triangles and tiny edges
    along the ground: their normals are noise. The rings follow the averaged outward direction
    and do not fold, and they reach out to the distance asked for."""
    d = load_mesh(meshes["dome"])
    V, F = extend_mesh(d.vertices, d.faces, 0.1 * d.bbox_diagonal)
    assert folded_faces(V, F, len(d.faces)) == 0
    assert V[:, 2].min() == pytest.approx(-0.1 * d.bbox_diagonal, rel=0.02)


def test_trim_drops_parts_shorter_than_a_quad():
    """A strip over a roof and a narrow second piece of it: the piece leaves a part half a
    quad long, dropped with a note."""
    def square(x0, x1):
        V = np.array([[x0, 0, 0], [x1, 0, 0], [x1, 10, 0], [x0, 10, 0.0]])
        return V, np.array([[0, 1, 2], [0, 2, 3]])
    (V1, F1), (V2, F2) = square(0.0, 10.0), square(10.5, 11.0)
    surface = ReferenceSurface(np.vstack([V1, V2]), np.vstack([F1, F2 + 4]))
    x = np.arange(-3.0, 15.0)
    A = np.stack([x, np.full_like(x, 4.0), np.zeros_like(x)], 1)
    strip = SimpleNamespace(id="S-v03", A=A, B=A + [0.0, 1.0, 0.0])
    records, notes = trim_records([strip], surface)
    parts = records[0]["parts"]
    assert [p["id"] for p in parts] == ["S-v03"]
    ts = np.asarray(parts[0]["outline"])
    assert ts[:, 0].min() == pytest.approx(3.0, abs=1e-9)            # x = 0
    assert ts[:, 0].max() == pytest.approx(13.0, abs=1e-9)           # x = 10
    assert records[0]["dropped"][0]["quads"] == pytest.approx(0.5, abs=1e-9)
    assert len(notes) == 1 and "shorter than one quad" in notes[0]
