"""``dgpc report`` on a flat artifact: the overlay and side-by-side PNGs (paper Fig. 18)."""

import numpy as np
from cli_helpers import dgpc
from PIL import Image


def _flat(tmp_path, twist="0"):
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 6,
         "--span", 90, "--twist", twist, "-o", tmp_path / "n")
    dgpc("planarize-strips", tmp_path / "n", "-o", tmp_path / "s")
    dgpc("unfold", tmp_path / "s", "-o", tmp_path / "f")
    return tmp_path / "f"


def test_report_writes_two_deterministic_pngs(tmp_path):
    flat = _flat(tmp_path)
    out = dgpc("report", flat, "-o", tmp_path / "a").stdout.split()
    assert out == [str(tmp_path / "a-overlay.png"), str(tmp_path / "a-strips.png"),
                   str(tmp_path / "a-index.html")]
    dgpc("report", flat, "-o", tmp_path / "b")
    for name in ("overlay", "strips"):
        a = (tmp_path / f"a-{name}.png").read_bytes()
        assert a == (tmp_path / f"b-{name}.png").read_bytes()
        img = np.asarray(Image.open(tmp_path / f"a-{name}.png").convert("L"))
        assert img.shape[0] > 100 and img.shape[1] > 100
        assert (img < 128).mean() > 1e-3                      # something was drawn


def test_report_refuses_existing_files(tmp_path):
    flat = _flat(tmp_path)
    dgpc("report", flat, "-o", tmp_path / "r")
    result = dgpc("report", flat, "-o", tmp_path / "r", expect=1)
    assert "already exists" in result.stderr
    dgpc("report", flat, "-o", tmp_path / "r", "--force")
