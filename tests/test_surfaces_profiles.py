"""Meridian profiles: resampling, built-in dimensions, CSV reading and its errors (SPEC §5)."""

import numpy as np
import pytest

from dgpc_cli.errors import DgpcError
from dgpc_cli.surfaces.profiles import (
    BUILTIN_PROFILES,
    CATENOID_C,
    Profile,
    arc_length,
    builtin_profile,
    profile_from_spec,
    read_profile_csv,
    resample,
)

# resampling --------------------------------------------------------------------------------------


def test_arc_length_of_a_known_polyline():
    p = Profile("L", [1.0, 4.0, 4.0, 1.0], [0.0, 4.0, 6.0, 6.0])
    np.testing.assert_allclose(arc_length(p), [0.0, 5.0, 7.0, 10.0], rtol=0, atol=1e-15)
    assert p.length == pytest.approx(10.0, abs=1e-15)


@pytest.mark.parametrize("m", [2, 3, 7, 21, 400])
@pytest.mark.parametrize("name", sorted(BUILTIN_PROFILES))
def test_resample_is_equidistant_in_arc_length(name, m):
    p = builtin_profile(name)
    r, h, s = resample(p, m)
    assert r.shape == h.shape == s.shape == (m,)
    step = np.diff(s)
    np.testing.assert_allclose(step, p.length / (m - 1), rtol=1e-12, atol=0)
    assert (r[0], h[0], r[-1], h[-1]) == (p.r[0], p.h[0], p.r[-1], p.h[-1])
    assert s[0] == 0.0 and s[-1] == pytest.approx(p.length, rel=1e-15)


def test_resample_interpolates_on_the_polyline():
    # Arc length 10 along three segments with a corner at s = 5 and s = 7.
    p = Profile("L", [1.0, 4.0, 4.0, 1.0], [0.0, 4.0, 6.0, 6.0])
    r, h, s = p.resample(11)
    np.testing.assert_allclose(s, np.arange(11.0), atol=1e-14)
    expected_r = [1.0, 1.6, 2.2, 2.8, 3.4, 4.0, 4.0, 4.0, 3.0, 2.0, 1.0]
    expected_h = [0.0, 0.8, 1.6, 2.4, 3.2, 4.0, 5.0, 6.0, 6.0, 6.0, 6.0]
    np.testing.assert_allclose(r, expected_r, atol=1e-14)
    np.testing.assert_allclose(h, expected_h, atol=1e-14)


def test_resample_of_a_straight_profile_has_equal_chords():
    r, h, _ = resample(builtin_profile("cone"), 17)
    chords = np.hypot(np.diff(r), np.diff(h))
    np.testing.assert_allclose(chords, np.sqrt(20.0) / 16, rtol=1e-12)


def test_resample_needs_two_points():
    with pytest.raises(ValueError):
        resample(builtin_profile("cylinder"), 1)


# built-ins ---------------------------------------------------------------------------------------


def test_every_builtin_is_dense_off_axis_and_described():
    assert {"bowling-pin", "sphere", "sphere-zone", "cylinder", "cone",
            "catenoid"} <= set(BUILTIN_PROFILES)
    for name, entry in BUILTIN_PROFILES.items():
        p = builtin_profile(name)
        assert p.name == name
        assert len(p) >= 1001
        assert np.all(p.r > 0.5), name
        assert entry.description and "\n" not in entry.description
        assert not p.r.flags.writeable and not p.h.flags.writeable


def test_cylinder():
    p = builtin_profile("cylinder")
    np.testing.assert_array_equal(p.r, 2.0)
    assert (p.h[0], p.h[-1]) == (0.0, 6.0)
    assert np.all(np.diff(p.h) > 0)


def test_cone():
    p = builtin_profile("cone")
    np.testing.assert_allclose(p.r, 3.0 - 0.5 * p.h, atol=1e-15)
    assert (p.r[0], p.h[0], p.r[-1], p.h[-1]) == (3.0, 0.0, 1.0, 4.0)


def test_sphere_points_are_at_distance_5_from_the_centre():
    p = builtin_profile("sphere")
    np.testing.assert_allclose(np.hypot(p.r, p.h), 5.0, rtol=1e-14)
    # from the equator up to a polar angle of 8°
    assert (p.r[0], p.h[0]) == (5.0, 0.0)
    assert np.degrees(np.arctan2(p.r[-1], p.h[-1])) == pytest.approx(8.0, abs=1e-12)
    assert p.r.min() == pytest.approx(5.0 * np.sin(np.radians(8.0)), rel=1e-12)


def test_sphere_zone():
    p = builtin_profile("sphere-zone")
    np.testing.assert_allclose(np.hypot(p.r, p.h), 5.0, rtol=1e-14)
    lat = np.degrees(np.arctan2(p.h, p.r))
    assert lat[0] == pytest.approx(-45.0, abs=1e-12)
    assert lat[-1] == pytest.approx(45.0, abs=1e-12)
    assert p.length == pytest.approx(5.0 * np.pi / 2, rel=1e-6)


def test_catenoid_is_c_cosh_h_over_c():
    p = builtin_profile("catenoid")
    assert CATENOID_C == 1.5
    np.testing.assert_allclose(p.r, 1.5 * np.cosh(p.h / 1.5), rtol=1e-14)
    assert (p.h[0], p.h[-1]) == (-2.0, 2.0)
    assert p.r.min() == pytest.approx(1.5, rel=1e-6)


def test_bowling_pin_proportions():
    p = builtin_profile("bowling-pin")
    assert (p.h[0], p.h[-1]) == (0.0, 38.1)
    assert np.all(np.diff(p.h) > 0)
    assert p.r[0] == pytest.approx(2.6, abs=0.1)
    assert p.r[-1] == pytest.approx(1.5, abs=1e-12)
    assert p.r.min() >= 1.5  # never reaches the axis

    # belly, neck and head: the only local extrema of r(h), where the proportions say
    ext = np.flatnonzero(np.diff(np.sign(np.diff(p.r))) != 0) + 1
    assert len(ext) == 3
    (h_belly, h_neck, h_head), (r_belly, r_neck, r_head) = p.h[ext], p.r[ext]
    assert (h_belly, r_belly) == (pytest.approx(11.4, abs=0.3), pytest.approx(6.05, abs=0.02))
    assert (h_neck, r_neck) == (pytest.approx(25.0, abs=0.5), pytest.approx(2.3, abs=0.02))
    assert (h_head, r_head) == (pytest.approx(33.0, abs=0.5), pytest.approx(3.2, abs=0.02))
    assert r_belly == p.r.max()

    # smooth, no kinks: the discrete curvature (turning angle / mean segment length) stays
    # below 1 per unit, i.e. every radius of curvature, the crown's included, is above 1
    d = np.stack([np.diff(p.r), np.diff(p.h)], axis=1)
    length = np.linalg.norm(d, axis=1)
    d /= length[:, None]
    turn = np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1, 1))
    assert np.max(turn / (0.5 * (length[1:] + length[:-1]))) < 1.0


def test_builtin_profile_unknown_name():
    with pytest.raises(KeyError, match="bowling-pin"):
        builtin_profile("teapot")


def test_profile_rejects_points_on_the_axis_and_duplicates():
    with pytest.raises(ValueError, match="> 0"):
        Profile("p", [0.0, 1.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="duplicate"):
        Profile("p", [1.0, 1.0, 2.0], [0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="1-D"):
        Profile("p", [1.0], [0.0])


# CSV ---------------------------------------------------------------------------------------------


def _write(tmp_path, text, name="profile.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_read_csv(tmp_path):
    path = _write(tmp_path, "r,h\n1,0\n2,1\n1.5,3\n")
    p = read_profile_csv(path)
    np.testing.assert_array_equal(p.r, [1.0, 2.0, 1.5])
    np.testing.assert_array_equal(p.h, [0.0, 1.0, 3.0])
    assert p.name == str(path)


def test_read_csv_column_order_whitespace_and_blank_lines(tmp_path):
    path = _write(tmp_path, "\n  h ,  r \n 0 , 1\n\n1,  2.5 \n  2,3e0\n\n")
    p = read_profile_csv(path)
    np.testing.assert_array_equal(p.r, [1.0, 2.5, 3.0])
    np.testing.assert_array_equal(p.h, [0.0, 1.0, 2.0])


def test_profile_from_spec(tmp_path):
    assert profile_from_spec("sphere") is builtin_profile("sphere")
    path = _write(tmp_path, "r,h\n1,0\n1,1\n")
    np.testing.assert_array_equal(profile_from_spec(str(path)).h, [0.0, 1.0])
    np.testing.assert_array_equal(profile_from_spec(path).r, [1.0, 1.0])


def test_profile_from_spec_unknown_lists_the_builtins(tmp_path):
    spec = str(tmp_path / "nothing-here")
    with pytest.raises(DgpcError) as info:
        profile_from_spec(spec)
    message = str(info.value)
    assert message.startswith(f"{spec}: ")
    assert "\n" not in message
    for name in BUILTIN_PROFILES:
        assert name in message


@pytest.mark.parametrize("text, needles", [
    ("", ["empty"]),
    ("\n \n", ["empty"]),
    ("x,y\n1,0\n2,1\n", ["header", "'x,y'"]),
    ("r\n1\n2\n", ["header", "'r'"]),
    ("r,h,w\n1,0,0\n2,1,0\n", ["header", "'r,h,w'"]),
    ("r,h\n1,0\n", ["at least 2 data rows", "found 1"]),
    ("r,h\n", ["at least 2 data rows", "found 0"]),
    ("r,h\n1,0\n2,abc\n3,2\n", ["line 3", "'abc'"]),
    ("r,h\n1,0\n2,1,5\n", ["line 3", "2 fields"]),
    ("r,h\n1,0\n2,nan\n", ["line 3", "non-finite"]),
    ("r,h\n1,0\ninf,1\n", ["line 3", "non-finite"]),
    ("r,h\n1,0\n2,1\n-0.5,2\n", ["line 4", "negative radius", "-0.5"]),
    ("r,h\n0,0\n2,1\n", ["line 2", "r = 0", "pole"]),
    ("r,h\n1,0\n2,1\n2,1\n3,2\n", ["line 4", "line 3", "duplicate"]),
    ("r,h\n1,0\n1,1\n1,0.5\n", ["line 3", "reverses on itself"]),
    ("r,h\n1,0\n2,2\n1.5,1\n", ["line 3", "reverses on itself"]),
])
def test_csv_errors_are_one_line_and_name_the_file(tmp_path, text, needles):
    path = _write(tmp_path, text)
    with pytest.raises(DgpcError) as info:
        read_profile_csv(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ")
    assert info.value.source == str(path)
    assert "\n" not in message
    for needle in needles:
        assert needle in message, message


def test_csv_line_numbers_count_blank_lines(tmp_path):
    path = _write(tmp_path, "r,h\n\n1,0\n\n-2,1\n")
    with pytest.raises(DgpcError, match="line 5: negative radius"):
        read_profile_csv(path)


def test_csv_missing_file_and_directory(tmp_path):
    missing = tmp_path / "missing.csv"
    with pytest.raises(DgpcError, match="not found") as info:
        read_profile_csv(missing)
    assert str(info.value).startswith(f"{missing}: ")
    with pytest.raises(DgpcError, match="directory") as info:
        read_profile_csv(tmp_path)
    assert str(info.value).startswith(f"{tmp_path}: ")


def test_csv_binary_file(tmp_path):
    path = tmp_path / "profile.csv"
    path.write_bytes(b"\xff\xfe\x00\x81r,h")
    with pytest.raises(DgpcError, match="not a text file") as info:
        read_profile_csv(path)
    assert "\n" not in str(info.value)


def test_a_bent_csv_profile_is_not_a_reversal(tmp_path):
    # sharp turns are allowed; only a 180° turn folds the surface onto itself
    path = _write(tmp_path, "r,h\n1,0\n2,1\n1.5,0.9\n")
    assert len(read_profile_csv(path)) == 3
