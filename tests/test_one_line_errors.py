"""Every error is exactly one line (issue "nothing destroyed, nothing corrupt"): a warning found
before the error (a deprecated option name) is folded into the error's line, and init's "no
--units given" notice is said only once the net is written; the message names what is wrong
(extract-mold on a net of one strip names the net, not ``--lambda``, which was not given)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from cli_helpers import dgpc
from refusals import refused, tree

from dgpc_cli.io.net import NetArtifact, write_net

PROFILE = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"


def test_a_deprecated_option_before_an_error_is_one_line(tmp_path):
    r = dgpc("nest", tmp_path / "missing", "--sheet", "1000x1000", "--units", "mm", "-o",
             tmp_path / "o", expect=1)
    refused(r.stderr, r.exit_code, 1, "missing.json", "no such file",
            "(also: --units is deprecated, it is now --expect-units)")
    assert list(tmp_path.iterdir()) == []


def test_a_deprecated_option_still_warns_when_the_command_passes(tmp_path):
    dgpc("init", "--surface", "revolution", "--profile", PROFILE, "--rows", 5, "--cols", 5,
         "--units", "m", "-o", tmp_path / "n")
    r = dgpc("extract-mold", tmp_path / "n", "--tol", "1e-3", "-o", tmp_path / "m")
    assert "warning: --tol is deprecated, it is now --revolution-tol" in r.stderr
    assert r.stderr.strip().splitlines()[-1].startswith("warning: --tol")


def test_init_without_units_before_an_error_is_one_line(tmp_path):
    """The net cannot be written (its OBJ's name is a folder): the error alone; a net that is
    written gets the notice."""
    (tmp_path / "n.obj").mkdir()
    before = tree(tmp_path)
    args = ("init", "--surface", "revolution", "--profile", PROFILE, "--rows", 5, "--cols", 5)
    r = dgpc(*args, "-o", tmp_path / "n", "--force", expect=1)
    refused(r.stderr, r.exit_code, 1, "n.obj", "is a directory")
    assert tree(tmp_path) == before and (tmp_path / "n.obj").is_dir()
    r = dgpc(*args, "-o", tmp_path / "ok")
    assert r.stderr.startswith("init: no --units given: the net is in mm")


def test_extract_mold_of_one_strip_names_the_net(tmp_path):
    for m in (2, 5):
        theta = np.linspace(0.0, 0.6, 2)
        z = np.linspace(0.0, 1.0, m)
        f = np.stack(np.broadcast_arrays(np.cos(theta)[None], np.sin(theta)[None],
                                         z[:, None]), axis=-1)
        write_net(tmp_path / f"c{m}", NetArtifact(f=f, units="m"))
        before = tree(tmp_path)
        r = dgpc("extract-mold", tmp_path / f"c{m}", "-o", tmp_path / "mold", expect=1)
        line = refused(r.stderr, r.exit_code, 1, f"c{m}.json: the net is {m} x 2",
                       "one strip")
        assert "--lambda:" not in line and tree(tmp_path) == before
    # with --lambda given, N = λ(n − 1) is the user's: that mold is made
    dgpc("extract-mold", tmp_path / "c5", "--lambda", 4, "-o", tmp_path / "mold")
