"""Issue 4 done-means: `dgpc extract-mold` and `dgpc inspect MOLD` (paper §4.2.2, Fig. 1, 16-17)."""

import json
import math
from types import SimpleNamespace

import numpy as np
from cli_helpers import dgpc, metrics
from data_files import WAVE
from mold_samples import (
    deform,
    gehry_nets,
    gehry_profile,
    sector_net,
    wavy_profile,
    write,
    write_profile_csv,
)

from dgpc_cli.io.mold import read_mold
from dgpc_cli.io.net import read_net, write_net
from dgpc_cli.mold.profile import mold_grid


def mold_doc(stem):
    return json.loads((stem.parent / f"{stem.name}.json").read_text())


def _wavy_net(tmp_path, m, n):
    """Our wavy profile and the m×n meridian net (90°) of its surface, written as ``n0``."""
    prof = wavy_profile()
    csv = write_profile_csv(tmp_path / "wavy.csv", prof.r, prof.h)
    dgpc("init", "--surface", "revolution", "--profile", csv, "--rows", m, "--cols", n,
         "--span", 90, "-o", tmp_path / "n0")
    return prof, read_net(tmp_path / "n0").f


def test_truth_recovers_our_profile_and_minding_gives_an_isometric_one(tmp_path):
    """A 90° sector of our own profile, bent isometrically (Minding λ = 0.8 and a rigid motion):
    --segments 4(n−1) recovers r(u), h(u); the default N = n−1 gives another, isometric
    surface of revolution (λ = 1/4 of the original's radius, roughly)."""
    m, n = 17, 13
    prof, f0 = _wavy_net(tmp_path, m, n)
    net = read_net(tmp_path / "n0")
    net.f = deform(f0, 0.8, axis=(1, 2, 0.5), angle=0.7, shift=(3, -1, 2))
    write_net(tmp_path / "bent", net)
    # really deformed: not a rigid copy of the sector (the radii differ by ~20 %)
    assert np.abs(np.linalg.norm(net.f[:, 0] - net.f[:, -1], axis=-1)
                  - np.linalg.norm(f0[:, 0] - f0[:, -1], axis=-1)).max() > 0.1

    out = dgpc("extract-mold", tmp_path / "bent", "--segments", 4 * (n - 1),
               "-o", tmp_path / "truth")
    assert out.stdout.strip() == str(tmp_path / "truth.json")
    doc = mold_doc(tmp_path / "truth")
    r_true, h_true, _ = prof.resample(m)
    r, h = np.array(doc["data"]["profile"]["r"]), np.array(doc["data"]["profile"]["h"])
    L = prof.length
    err_r = np.abs(r - r_true).max() / L
    err_h = np.abs((h - h[0]) - (h_true - h_true[0])).max() / L
    assert err_r <= 1e-4 and err_h <= 1e-4, (err_r, err_h)
    assert doc["metrics"]["isometry_error_max"] <= 1e-6
    assert doc["data"]["lambda"] == 4.0 and not doc["data"]["lambda_lowered"]
    assert abs(doc["data"]["sector"]["angle_deg"] - 90.0 / (n - 1)) <= 1e-9

    dgpc("extract-mold", tmp_path / "bent", "--lambda", "compact", "-o", tmp_path / "default")
    d = mold_doc(tmp_path / "default")
    r1 = np.array(d["data"]["profile"]["r"])
    assert d["data"]["segments"] == n - 1 and d["data"]["lambda"] == 1.0
    ratio = math.sin(math.pi / (4 * (n - 1))) / math.sin(math.pi / (n - 1))
    assert np.allclose(r1, ratio * r_true, rtol=1e-9)             # a different surface ...
    assert d["metrics"]["isometry_error_max"] <= 1e-6              # ... and isometric (Minding)
    assert all(p["isometry_error"] <= 1e-6 for p in d["data"]["panels"])
    # the profile CSV reads back as a dgpc profile and revolves into the mold's own net
    dgpc("init", "--surface", "revolution", "--profile", tmp_path / "default.profile.csv",
         "--rows", m, "--cols", n, "--span", 360, "-o", tmp_path / "remade")
    remade = read_net(tmp_path / "remade").f
    assert np.allclose(np.hypot(remade[:, 0, 0], remade[:, 0, 1]), r1, atol=1e-3 * L)


def test_panels_match_their_mold_patch_and_a_non_isometric_panel_is_caught(tmp_path):
    f = sector_net(wavy_profile(), 13, 9, 60.0)
    g = deform(f, 0.9, angle=0.4)
    g[6, 4] += 0.02 * np.linalg.norm(g[6, 4] - g[6, 5])          # dent one vertex
    write(tmp_path / "dented", g)
    # at the default --max-strain the dent is refused, naming its worst panel ...
    err = dgpc("extract-mold", tmp_path / "dented", "--panel-size", 2, "--revolution-tol", 0.05,
               "-o", tmp_path / "m", expect=1).stderr.strip()
    assert len(err.splitlines()) == 1 and "P-u0" in err and "--max-strain 0.0003" in err
    assert not list(tmp_path.glob("m.*"))
    # ... and a looser one maps it
    dgpc("extract-mold", tmp_path / "dented", "--panel-size", 2, "--revolution-tol", 0.05,
         "--max-strain", 0.05, "-o", tmp_path / "m")
    panels = {p["id"]: p for p in mold_doc(tmp_path / "m")["data"]["panels"]}
    # vertex (6, 4) is a corner of the panels of blocks (2|3, 1|2) only
    dented = {"P-u02-v01", "P-u02-v02", "P-u03-v01", "P-u03-v02"}
    assert all(panels[k]["isometry_error"] > 1e-4 for k in dented)
    assert max(p["isometry_error"] for k, p in panels.items() if k not in dented) <= 1e-2
    assert panels["P-u00-v00"]["rows"] == [0, 2] and panels["P-u00-v00"]["cols"] == [0, 2]


def test_fit_on_a_surface_not_isometric_to_revolution_fails_naming_rows(tmp_path):
    """A net fitted to a freeform patch (wave.obj) is a gpc net whose strip widths vary along
    the parallels: (5) fails and nothing is written."""
    dgpc("init", WAVE, "--method", "geodesic", "--rows", 12, "--cols", 8, "--extend", 0,
         "-o", tmp_path / "e0")
    dgpc("optimize", tmp_path / "e0", "--mode", "fit", "-o", tmp_path / "e")
    fitted = metrics(tmp_path / "e")
    assert fitted["gpc_angle_defect_max"] <= 1e-6                  # a real gpc net ...
    res = dgpc("extract-mold", tmp_path / "e", "-o", tmp_path / "mold", expect=1)
    err = res.stderr.strip()
    assert len(err.splitlines()) == 1
    assert str(tmp_path / "e.json") in err and "equation (5)" in err and "rows " in err
    assert not list(tmp_path.glob("mold*"))


def test_lambda_is_lowered_when_x_would_be_imaginary(tmp_path, caplog):
    """A net that winds 1.25 times about its axis (450°) on a steep profile: taken as one full
    turn (default N = n−1) its radii grow 1.25 times and the meridian cannot keep up; λ is
    lowered to the largest value with every x(u) real, and the mold is isometric."""
    m, n = 15, 46
    h = np.linspace(0.0, 1.0, 401)
    r = 3.0 - 2.0 * h + 0.6 * h**2             # dr/dh from -2 to -0.8: steep, like a lampshade
    prof_r, prof_h = r, h
    from dgpc_cli.surfaces.profiles import Profile, resample

    rr, hh, _ = resample(Profile("lampshade", prof_r, prof_h), m)
    theta = np.radians(450.0) * np.arange(n) / (n - 1)
    f = np.stack([rr[:, None] * np.cos(theta), rr[:, None] * np.sin(theta),
                  np.broadcast_to(hh[:, None], (m, n))], axis=-1)
    write(tmp_path / "spiral", f)
    res = dgpc("extract-mold", tmp_path / "spiral", "--lambda", "compact", "-o",
               tmp_path / "mold")
    doc = mold_doc(tmp_path / "mold")
    lam = doc["data"]["lambda"]
    assert doc["data"]["lambda_lowered"] and lam < 1.0
    assert "lowered λ to" in res.stderr and f"{lam:.6g}" in res.stderr
    # largest admissible: N = π / arcsin(max |Δd| / 2l), exactly one x(u) is (numerically) 0
    x = np.array(doc["data"]["profile"]["x"])
    assert x.min() <= 1e-6 * x.max() and np.all(x >= 0)
    d = np.array(doc["data"]["profile"]["d"])
    ell = np.array(doc["data"]["profile"]["l"])
    n_max = math.pi / math.asin((np.abs(np.diff(d)) / (2 * ell)).max())
    assert abs(doc["data"]["segments"] - n_max) <= 1e-9 * n_max
    assert doc["metrics"]["isometry_error_max"] <= 1e-6
    assert doc["status"]["lambda_lowered"] is True
    # a λ that is small enough is kept as asked
    dgpc("extract-mold", tmp_path / "spiral", "--lambda", 0.5, "-o", tmp_path / "half")
    half = mold_doc(tmp_path / "half")
    assert half["data"]["lambda"] == 0.5 and not half["data"]["lambda_lowered"]
    assert half["metrics"]["isometry_error_max"] <= 1e-6


def test_gehry_sample_four_deformations_one_mold(tmp_path):
    """Paper Fig. 1, 16, 17: four different isometric deformations of one net of a profile with
    a cylindrical section share one mold; the cylinder's panels are flat (no mold)."""
    stems = [write(tmp_path / f"facade{k}", f) for k, f in enumerate(gehry_nets(), 1)]
    out = tmp_path / "gehry"
    dgpc("extract-mold", *stems, "--panel-size", 2, "--mold-max-length", 1.3, "--lambda",
         "compact", "-o", out)
    doc = mold_doc(out)
    data, met = doc["data"], doc["metrics"]
    panels = data["panels"]
    assert len(panels) == 4 * 10 * 6 and met["panels"] == len(panels)
    assert {p["net"] for p in panels} == {0, 1, 2, 3}
    assert panels[0]["id"] == "N1-P-u00-v00" and panels[-1]["id"] == "N4-P-u09-v05"
    assert met["isometry_error_max"] <= 1e-6
    # the profile: rows 0..8 lie on the cylinder r = 3 (h ≤ 2 at spacing ≈ 5.26/20 per row)
    h = np.array(data["profile"]["h"])
    flat_rows = {tuple(p["rows"]) for p in panels if p["flat"]}
    assert flat_rows == {(0, 2), (2, 4), (4, 6)}                     # cylinder, away from the join
    assert met["panels_flat"] == 4 * 3 * 6 and met["panels_curved"] == 4 * 7 * 6
    for p in panels:
        assert (p["piece"] is None) == p["flat"]
    pieces = data["pieces"]
    assert met["pieces"] == len(pieces) >= 2
    lengths = [p["meridian_length"] for p in pieces]
    assert max(lengths) <= 1.3
    assert pieces[0]["rows"][0] == 6 and pieces[-1]["rows"][1] == 20      # curved rows only
    for a, b in zip(pieces, pieces[1:], strict=False):
        assert a["rows"][1] == b["rows"][0]
    # each curved panel lies inside its piece
    by_id = {p["id"]: p for p in pieces}
    for p in panels:
        if p["piece"]:
            lo, hi = by_id[p["piece"]]["rows"]
            assert lo <= p["rows"][0] < p["rows"][1] <= hi
    # the sector just carries the widest panel: 2 columns of 360°/12
    assert abs(data["sector"]["angle_deg"] - 2 * 30.0) <= 1e-9
    assert h[0] == 0.0 and np.all(np.diff(h) > 0)
    # inspect: profile, pieces, curved/flat counts
    ins = metrics(out)
    assert ins["pieces"] == len(pieces)
    assert ins["panels_curved"] == met["panels_curved"] and ins["panels_flat"] == met["panels_flat"]
    assert ins["profile"]["r"] == data["profile"]["r"]
    # the same deformations of a net of another profile do not share the mold
    other = sector_net(gehry_profile(), 21, 13, 120.0) * 1.01
    write(tmp_path / "other", other)
    res = dgpc("extract-mold", stems[0], tmp_path / "other", "-o", tmp_path / "x", expect=1)
    assert str(tmp_path / "other.json") in res.stderr and "same surface of revolution" in \
        res.stderr and "1.00e-02" in res.stderr


def test_flat_tol_and_panel_size_change_the_map(tmp_path):
    stem = write(tmp_path / "g", gehry_nets()[1])
    dgpc("extract-mold", stem, "-o", tmp_path / "a")
    dgpc("extract-mold", stem, "--flat-tol", 1.0, "-o", tmp_path / "b")
    a, b = mold_doc(tmp_path / "a"), mold_doc(tmp_path / "b")
    assert a["metrics"]["panels"] == 20 * 12 and a["metrics"]["panels_curved"] > 0
    assert b["metrics"]["panels_curved"] == 0 and b["metrics"]["pieces"] == 0
    assert a["parameters"] == {"segments": None, "lambda": "design", "panel_size": 1,
                               "flat_tol": 1e-5, "mold_max_length": None,
                               "revolution_tol": 6e-4, "max_strain": 3e-4, "units": "mm"}


def test_mold_max_length_shorter_than_a_panel_is_an_error(tmp_path):
    stem = write(tmp_path / "g", gehry_nets()[0])
    res = dgpc("extract-mold", stem, "--panel-size", 4, "--mold-max-length", 0.5,
               "-o", tmp_path / "m", expect=1)
    assert "--mold-max-length" in res.stderr and not list(tmp_path.glob("m.*"))


def test_usage_errors(tmp_path):
    stem = write(tmp_path / "g", gehry_nets()[0])
    res = dgpc("extract-mold", stem, "--segments", 12, "--lambda", 0.5, "-o", tmp_path / "m",
               expect=2)
    assert "mutually exclusive" in res.stderr
    dgpc("extract-mold", stem, "--segments", 1, "-o", tmp_path / "m", expect=2)
    dgpc("extract-mold", "-o", tmp_path / "m", expect=2)
    res = dgpc("extract-mold", stem, "--lambda", 0.1, "-o", tmp_path / "m", expect=1)
    assert "--lambda" in res.stderr
    dgpc("extract-mold", tmp_path / "missing", "-o", tmp_path / "m", expect=1)
    assert not list(tmp_path.glob("m.*"))


def test_refuses_to_overwrite_and_is_byte_deterministic(tmp_path):
    stem = write(tmp_path / "g", gehry_nets()[2])
    for name in ("a", "b"):
        dgpc("extract-mold", stem, "--panel-size", 3, "-o", tmp_path / name)
    for suffix in (".json", ".obj", ".profile.csv", ".profile.dxf", ".panels.csv"):
        a = (tmp_path / f"a{suffix}").read_bytes().replace(b'"a.', b'"')
        b = (tmp_path / f"b{suffix}").read_bytes().replace(b'"b.', b'"')
        assert a == b, suffix
    (tmp_path / "a.profile.dxf").unlink()
    res = dgpc("extract-mold", stem, "-o", tmp_path / "a", expect=1)
    assert "already exists" in res.stderr
    dgpc("extract-mold", stem, "-o", tmp_path / "a", "--force")
    assert read_mold(tmp_path / "a").data["panel_size"] == 1


def test_mold_obj_holds_the_surface_and_the_sector(tmp_path):
    stem = write(tmp_path / "g", gehry_nets()[0])
    dgpc("extract-mold", stem, "--panel-size", 2, "--lambda", "compact", "-o", tmp_path / "m")
    doc = mold_doc(tmp_path / "m")
    text = (tmp_path / "m.obj").read_text().splitlines()
    objects = [line for line in text if line.startswith("o ")]
    groups = [line[2:] for line in text if line.startswith("g ")]
    assert objects == ["o surface", "o sector"]
    assert groups == [p["id"] for p in doc["data"]["pieces"]] + ["no-mold"]
    v = np.array([[float(t) for t in line.split()[1:]] for line in text if line.startswith("v ")])
    m, cols = doc["data"]["rows"], doc["data"]["surface"]["columns"]
    surf = v[: m * cols].reshape(m, cols, 3)
    r = np.array(doc["data"]["profile"]["r"])
    assert cols == 13 and np.allclose(np.hypot(surf[..., 0], surf[..., 1]), r[:, None])
    assert np.allclose(surf[:, 0], surf[:, -1])                       # a full turn, N = 12
    sect = v[m * cols:].reshape(m, -1, 3)
    assert np.allclose(np.degrees(np.arctan2(sect[0, -1, 1], sect[0, -1, 0])), 60.0)
    # the sector's quads are the mold patches of the net's panels
    mold = read_mold(tmp_path / "m")
    meridian = SimpleNamespace(r=mold.r, h=mold.h)
    assert np.allclose(sect, mold_grid(meridian, np.radians([30.0, 30.0])))


def test_truth_through_an_isometric_optimization(tmp_path):
    """The issue's truth test with the deformation made by ``optimize --mode isometric``:
    three boundary handles of a 90° sector of our own profile are moved to where Minding's
    bending (λ = 0.8) takes them; the optimizer finds an isometric deformation (R ≤ 1e-8), and
    extract-mold recovers the profile from it."""
    m, n = 17, 13
    prof, f0 = _wavy_net(tmp_path, m, n)
    g = deform(f0, 0.8)
    idx = [(0, 0), (0, n - 1), (m - 1, n // 2)]
    handles = tmp_path / "handles.json"
    handles.write_text(json.dumps({"handles": [{"index": list(i), "target": g[i].tolist()}
                                               for i in idx]}))
    # the crease guard (on by default for drags) holds the third differences along the rows
    # near the start net's; a true bending of this wavy profile changes them, and the guard
    # costs it strain 1.1e-6: off here, where the bending is known to be exact
    dgpc("optimize", tmp_path / "n0", "--mode", "isometric", "--handles", handles,
         "--steps", 5, "--weight", "crease_guard=0", "-o", tmp_path / "bent")
    bent = metrics(tmp_path / "bent", "--against", tmp_path / "n0")
    assert bent["R"] <= 1e-8 and bent["strain"]["max"] <= 1e-6
    moved = read_net(tmp_path / "bent").f
    assert max(np.linalg.norm(moved[i] - f0[i]) for i in idx) >= 0.15 * prof.r.max()

    dgpc("extract-mold", tmp_path / "bent", "--segments", 4 * (n - 1), "-o", tmp_path / "truth")
    doc = mold_doc(tmp_path / "truth")
    r_true, h_true, _ = prof.resample(m)
    r, h = np.array(doc["data"]["profile"]["r"]), np.array(doc["data"]["profile"]["h"])
    assert np.abs(r - r_true).max() <= 1e-4 * prof.length
    assert np.abs((h - h[0]) - (h_true - h_true[0])).max() <= 1e-4 * prof.length
    dgpc("extract-mold", tmp_path / "bent", "-o", tmp_path / "default")
    assert mold_doc(tmp_path / "default")["metrics"]["isometry_error_max"] <= 1e-6
