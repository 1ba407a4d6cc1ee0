"""planarize-strips and unfold on exactly developable and revolution-isometric nets (issue 5):
cylinder, cone (against its analytic development), a Minding-bent catenoid; bad input."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc, metrics

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import load_envelope
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.io.strips import read_strips
from dgpc_cli.strips.congruence import kabsch
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.planarize import parse_strip_range, planarize_strips
from dgpc_cli.surfaces.minding import minding_bend

SPAN = 120.0


def _pipeline(tmp_path, profile, rows=15, cols=9, *extra):
    net = tmp_path / profile
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", rows,
         "--cols", cols, "--span", SPAN, "-o", net)
    dgpc("planarize-strips", net, "-o", tmp_path / "s", *extra)
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    return net, tmp_path / "s", tmp_path / "f"


@pytest.mark.parametrize("profile", ["cylinder", "cone"])
def test_exactly_developable_nets_give_planar_strips_and_unstrained_developments(tmp_path,
                                                                                  profile):
    net, s, f = _pipeline(tmp_path, profile)
    ms, mf = metrics(s), metrics(f)
    assert ms["n_strips"] == 8 and mf["n_parts"] == 8
    assert ms["max_planarity_diagonal_relative"] <= 1e-9
    assert ms["max_deviation_relative"] <= 1e-9
    assert mf["max_strain"] <= 1e-9
    assert mf["max_straightness_relative"] <= 1e-9  # a developable's meridians develop straight
    assert mf["n_classes"] == 1                      # all strips of revolution are congruent
    assert mf["max_congruence_error"] <= 1e-9
    strips = read_strips(s)
    assert [r["id"] for r in strips.records] == [f"S-v{v:02d}" for v in range(8)]
    f3 = read_net(net).f
    for (A, B), r in zip(strips.geometry, strips.records, strict=True):   # vertices kept
        assert np.allclose(A, f3[:, r["v"]], atol=1e-12)
        assert np.allclose(B, f3[:, r["v"] + 1], atol=1e-12)


def test_cone_strips_match_the_analytic_development(tmp_path):
    """Cone r = 3 − h/2: generators of slant length ρ = √5 r from the apex; a planar strip
    between meridians Δθ apart is a trapezoid of the annular sector with opening angle
    α = 2 arcsin(sin(Δθ/2)/√5) (→ Δθ/√5, the smooth development, as Δθ → 0)."""
    net, _, f = _pipeline(tmp_path, "cone")
    f3 = read_net(net).f
    rho = np.sqrt(5.0) * np.hypot(f3[:, 0, 0], f3[:, 0, 1])
    dtheta = np.radians(SPAN) / (f3.shape[1] - 1)
    alpha = 2 * np.arcsin(np.sin(dtheta / 2) / np.sqrt(5.0))
    assert abs(alpha - dtheta / np.sqrt(5.0)) < dtheta**3           # smooth limit
    # seen from the normal side, u runs towards the apex and v clockwise about it
    A_an = np.stack([rho, np.zeros_like(rho)], axis=-1)
    B_an = np.stack([rho * np.cos(alpha), -rho * np.sin(alpha)], axis=-1)
    Y = np.concatenate([A_an, B_an])
    for part in read_flat(f).parts:
        A, B = (np.asarray(g) for g in part["geodesics"])
        X = np.concatenate([A, B])
        R, t = kabsch(X, Y, allow_reflection=False)
        assert np.linalg.det(R) > 0
        err = np.max(np.linalg.norm(X @ R.T + t - Y, axis=1))
        assert err <= 1e-6 * part["length"], (part["id"], err)


def test_minding_bent_net_gives_one_congruence_class(tmp_path):
    """A meridian net of a catenoid bent isometrically (paper §4.2.2, Minding) into another
    surface of revolution: all strips planar, close to the original and congruent (SPEC §8)."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 21, "--cols",
         11, "--span", 90, "-o", tmp_path / "cat")
    src = read_net(tmp_path / "cat")
    bent = minding_bend(src.f, 0.7)
    lu0, lv0 = (np.linalg.norm(np.diff(src.f, axis=a), axis=-1) for a in (0, 1))
    lu1, lv1 = (np.linalg.norm(np.diff(bent, axis=a), axis=-1) for a in (0, 1))
    assert np.allclose(lu0, lu1, atol=1e-12) and np.allclose(lv0, lv1, atol=1e-12)  # isometric
    write_net(tmp_path / "iso", NetArtifact(f=bent))
    dgpc("planarize-strips", tmp_path / "iso", "-o", tmp_path / "s")
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    ms, mf = metrics(tmp_path / "s"), metrics(tmp_path / "f")
    assert ms["max_planarity_diagonal_relative"] <= 1e-4
    assert ms["max_deviation_relative"] <= 1e-2
    assert mf["n_classes"] == 1 and mf["classes"]["C01"]["quantity"] == 10
    assert mf["max_congruence_error"] <= 1e-3
    assert mf["max_straightness_relative"] > 1e-3  # a catenoid's meridians develop curved
    # the bent strips develop to the same shape as the unbent ones (isometry)
    s0 = planarize_strips(src.f, [4])[0]
    d0 = develop_strip(s0.A, s0.B)
    part = read_flat(tmp_path / "f").parts[4]
    X = np.concatenate([np.asarray(g) for g in part["geodesics"]])
    Y = np.concatenate([d0.A, d0.B])
    R, t = kabsch(X, Y, allow_reflection=False)
    assert np.max(np.linalg.norm(X @ R.T + t - Y, axis=1)) <= 1e-9 * d0.length


def test_non_planar_strips_are_polished(tmp_path):
    """A catenoid net with twisted u-lines has non-planar strips: the rulings and the polish
    make them planar while the vertices stay near the original strip."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 15, "--cols",
         7, "--span", 90, "--twist", 0.3, "-o", tmp_path / "tw")
    dgpc("planarize-strips", tmp_path / "tw", "-o", tmp_path / "s")
    strips = read_strips(tmp_path / "s")
    assert all(r["construction_planarity"] > 1e-4 for r in strips.records)
    assert all(r["polish"]["applied"] for r in strips.records)
    assert max(r["planarity"] for r in strips.records) <= 1e-9
    assert max(r["deviation"] for r in strips.records) <= 2e-2
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    assert metrics(tmp_path / "f")["max_strain"] <= 1e-9


def test_strip_range_and_determinism(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 7, "--cols", 9,
         "-o", tmp_path / "c")
    for stem in ("a", "b"):
        dgpc("planarize-strips", tmp_path / "c", "--strips", "2:4", "-o", tmp_path / stem)
        dgpc("unfold", tmp_path / stem, "-o", tmp_path / f"{stem}f")
    for suffix in (".obj", "f.obj"):
        assert (tmp_path / f"a{suffix}").read_bytes() == (tmp_path / f"b{suffix}").read_bytes()
    ja = load_envelope(tmp_path / "af.json", "flat")
    jb = load_envelope(tmp_path / "bf.json", "flat")
    for doc in (ja, jb):
        doc["inputs"] = {}
        doc["data"].pop("obj")                      # the OBJ's file name
        for record in doc["data"]["files"].values():   # the cut lists' and DXFs' names
            record.pop("path")
        doc["data"]["files"]["parts_csv"].pop("sha256")   # the cut list names the DXFs
    assert (tmp_path / "af.parts.csv").read_text().replace("af.", "bf.") == \
        (tmp_path / "bf.parts.csv").read_text()
    assert ja == jb
    assert [p["id"] for p in ja["data"]["parts"]] == ["S-v02", "S-v03", "S-v04"]
    obj = (tmp_path / "a.obj").read_text().splitlines()
    assert [line for line in obj if line.startswith("o ")] == ["o S-v02", "o S-v03", "o S-v04"]
    assert sum(line.startswith("f ") for line in obj) == 3 * 6
    assert sum(line.startswith("l ") for line in obj) == 3 * 7


def test_parse_strip_range():
    assert parse_strip_range(None, 5) == [0, 1, 2, 3]
    assert parse_strip_range("1:2", 5) == [1, 2]
    assert parse_strip_range("3", 5) == [3]
    assert parse_strip_range(":1", 5) == [0, 1]
    for bad in ("0:4", "3:2", "-1:2", "a:b"):
        with pytest.raises(DgpcError, match="--strips"):
            parse_strip_range(bad, 5)


def test_bad_input_exits_with_one_line_and_writes_nothing(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 5,
         "-o", tmp_path / "c")
    dgpc("planarize-strips", tmp_path / "c", "-o", tmp_path / "s")
    before = sorted(p.name for p in tmp_path.iterdir())
    cases = [
        (("unfold", tmp_path / "c", "-o", tmp_path / "x"), 1, "expected 'strips'"),
        (("planarize-strips", tmp_path / "c", "--strips", "2:7", "-o", tmp_path / "x"), 1,
         "--strips"),
        (("unfold", tmp_path / "s", "--congruence-tol", "0", "-o", tmp_path / "x"), 2,
         "--congruence-tol"),
        (("unfold", tmp_path / "s", "--congruence-tol", "-1", "-o", tmp_path / "x"), 2,
         "--congruence-tol"),
        (("planarize-strips", tmp_path / "s", "-o", tmp_path / "x"), 1, "expected 'net'"),
        (("planarize-strips", tmp_path / "c", "-o", tmp_path / "s"), 1, "already exists"),
    ]
    for args, code, text in cases:
        result = dgpc(*args, expect=code)
        assert text in result.stderr
        if code == 1:
            assert len(result.stderr.strip().splitlines()) == 1, result.stderr
        assert result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_strips_artifact_rejects_edited_obj(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", "cone", "--rows", 5, "--cols", 4,
         "-o", tmp_path / "c")
    dgpc("planarize-strips", tmp_path / "c", "-o", tmp_path / "s")
    obj = tmp_path / "s.obj"
    obj.write_text(obj.read_text().replace("o S-v00", "o S-v00 "))
    result = dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f", expect=1)
    assert "sha256" in result.stderr and not (tmp_path / "f.json").exists()
    doc = json.loads((tmp_path / "s.json").read_text())
    assert doc["kind"] == "strips"


def _twisted(tmp_path, name, twist, turn_deg):
    """A twisted catenoid net (non-planar strips, polished), turned about z by ``turn_deg``."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 11, "--cols", 4,
         "--span", 45, "--twist", twist, "-o", tmp_path / name)
    f = read_net(tmp_path / name).f
    c, s = np.cos(np.radians(turn_deg)), np.sin(np.radians(turn_deg))
    return f @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def test_mirror_images_share_a_class_only_with_mirror_ok(tmp_path):
    """Strips of a net twisted by +T and of one twisted by −T are mirror images: two classes
    (plus the strip joining the halves) without --mirror-ok, one class with it."""
    plus = _twisted(tmp_path, "p", 0.3, 0.0)
    minus = _twisted(tmp_path, "m", -0.3, 90.0)
    write_net(tmp_path / "both", NetArtifact(f=np.concatenate([plus, minus], axis=1)))
    dgpc("planarize-strips", tmp_path / "both", "-o", tmp_path / "s")
    assert metrics(tmp_path / "s")["max_planarity_diagonal_relative"] <= 1e-9
    counts = {}
    for flag in ((), ("--mirror-ok",)):
        stem = tmp_path / f"f{len(flag)}"
        # parts some 3 units long: a tolerance of 1e-3 of that, in the net's unit
        dgpc("unfold", tmp_path / "s", *flag, "--congruence-tol", "0.003", "-o", stem)
        flat = read_flat(stem)
        counts[flag] = sorted(c["quantity"] for c in flat.classes)
        for c in flat.classes:
            assert c["max_relative_error"] <= 1e-3
        mirrored = sum(p["alignment"]["mirrored"] for p in flat.parts)
        assert mirrored == (3 if flag else 0)
    assert counts[()] == [1, 3, 3]
    assert counts[("--mirror-ok",)] == [1, 6]


def _cylinder_then_curved(tmp_path):
    """A profile straight (a cylinder) below h = 2 and curved above."""
    profile = tmp_path / "p.csv"
    h = np.linspace(0.0, 4.0, 81)
    r = np.where(h <= 2.0, 2.0, 2.0 + 0.25 * (h - 2.0) ** 2)
    profile.write_text("r,h\n" + "".join(f"{a:.12g},{b:.12g}\n" for a, b in zip(r, h, strict=True)))
    return profile


def test_flat_angle_marks_the_straight_part_of_a_profile_flat(tmp_path):
    """A profile straight (a cylinder) below h = 2 and curved above: the strip normals do not
    turn in the straight part, so its rows are flat and take the rulings of the nearest curved
    rows; a huge --flat-angle makes every row flat (the v-edges stay the rulings)."""
    profile = _cylinder_then_curved(tmp_path)
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", 17, "--cols", 5,
         "--span", 60, "-o", tmp_path / "n")
    f = read_net(tmp_path / "n").f
    straight = np.hypot(f[:, 0, 0], f[:, 0, 1]) <= 2.0 + 1e-12
    dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s")
    rec = read_strips(tmp_path / "s").records[1]
    flat = np.asarray(rec["flat_rows"])
    assert flat.any() and not flat.all()
    k = int(straight.sum())                     # rows 0..k-1 on the cylinder, the rest curved
    assert straight[:k].all() and 4 < k < len(straight) - 4
    # a row's normals stencil reaches two rows on (its own tangent and the next normal's)
    assert flat[:k - 2].all() and not flat[k:].any()
    assert metrics(tmp_path / "s")["max_planarity_diagonal_relative"] <= 1e-9
    dgpc("planarize-strips", tmp_path / "n", "--flat-angle", 3.0, "-o", tmp_path / "all")
    strips = read_strips(tmp_path / "all")
    assert all(all(r["flat_rows"]) for r in strips.records)
    for (A, B), r in zip(strips.geometry, strips.records, strict=True):
        # meridian strips with the v-edges as rulings: isosceles trapezoids, planar already
        assert not r["polish"]["applied"]
        assert np.allclose(A, f[:, r["v"]], atol=1e-12, rtol=0)
        assert np.allclose(B, f[:, r["v"] + 1], atol=1e-12, rtol=0)


def test_polish_keeps_the_rulings_in_order_where_the_surface_is_a_cylinder(tmp_path):
    """Twisted u-lines over a cylinder-then-curved profile: the curved part needs the polish,
    and on the cylinder part any parallel rulings give planar quads. The rulings must keep
    their order along both geodesics (no zigzag turning quads into folded near-triangles), so
    every developed outline is a simple polygon a cutter can follow."""
    from shapely.geometry import Polygon

    dgpc("init", "--surface", "revolution", "--profile", _cylinder_then_curved(tmp_path),
         "--rows", 17, "--cols", 5, "--span", 60, "--twist", 0.3, "-o", tmp_path / "n")
    dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s")
    strips = read_strips(tmp_path / "s")
    assert all(r["polish"]["applied"] and r["rulings_ordered"] for r in strips.records)
    for (A, B), (P, Q) in zip(strips.geometry, _geodesics(tmp_path / "n", strips), strict=True):
        for X, curve in ((A, P), (B, Q)):
            # every step runs forward along the original geodesic
            assert np.einsum("ij,ij->i", np.diff(X, axis=0), np.diff(curve, axis=0)).min() > 0
    assert metrics(tmp_path / "s")["max_planarity_diagonal_relative"] <= 1e-9
    assert metrics(tmp_path / "s")["max_deviation_relative"] <= 3e-2
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    assert all(Polygon(p["outline"]).is_valid for p in read_flat(tmp_path / "f").parts)


def _geodesics(net, strips):
    f = read_net(net).f
    return [(f[:, r["v"]], f[:, r["v"] + 1]) for r in strips.records]


def test_folded_strips_exit_3_and_unfold_refuses_them(tmp_path, monkeypatch):
    """Without the slide fairness the polish folds the twisted cylinder strips: planarize-strips
    names them and exits 3 (written anyway); unfold refuses the strips with one line naming
    their status, and with --accept-status refuses the strip whose outline crosses itself."""
    import dgpc_cli.strips.polish as polish
    from dgpc_cli.core.solver import Schedule

    monkeypatch.setattr(polish, "SLIDE_WEIGHT", Schedule.constant(0.0))
    dgpc("init", "--surface", "revolution", "--profile", _cylinder_then_curved(tmp_path),
         "--rows", 17, "--cols", 5, "--span", 60, "--twist", 0.3, "-o", tmp_path / "n")
    res = dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s", expect=3)
    assert "cross" in res.stderr and "S-v00" in res.stderr
    assert load_envelope(tmp_path / "s.json", "strips")["status"]["rulings_cross"]
    res = dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f", expect=1)
    assert "its status is rulings_cross (S-v00" in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1
    res = dgpc("-q", "unfold", tmp_path / "s", "--accept-status", "-o", tmp_path / "f",
               expect=1)
    assert "crosses itself" in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert not list(tmp_path.glob("f.*"))


def test_polish_short_of_its_tolerance_exits_3_and_writes(tmp_path, monkeypatch):
    """SPEC §2: an optimization that misses its tolerance exits 3, artifact written, status
    recorded (here the final projection gets no iterations)."""
    import dgpc_cli.strips.polish as polish
    monkeypatch.setattr(polish, "PROJECTION_MAX_ITER", 0)
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 4,
         "--span", 60, "--twist", 0.3, "-o", tmp_path / "tw")
    result = dgpc("planarize-strips", tmp_path / "tw", "-o", tmp_path / "s", expect=3)
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("Error: ") and "S-v00" in last and "written anyway" in last
    assert result.stdout.strip().endswith("s.json")
    doc = json.loads((tmp_path / "s.json").read_text())
    assert doc["status"]["polish_not_converged"] == ["S-v00", "S-v01", "S-v02"]
