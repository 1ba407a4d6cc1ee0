"""Running the ``dgpc`` command in-process and reading what it wrote."""

from __future__ import annotations

import json

import numpy as np
from click.testing import CliRunner

from dgpc_cli.cli.main import cli
from dgpc_cli.core.problem import mean_edge_length
from dgpc_cli.io.net import NetArtifact, read_net, write_net
from dgpc_cli.surfaces.minding import minding_bend


def dgpc(*args, expect=0):
    """Run ``dgpc ARGS``; assert the exit code (any with ``expect=None``); return the result
    (stdout, stderr apart)."""
    result = CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)
    assert expect is None or result.exit_code == expect, \
        (result.exit_code, result.stdout, result.stderr)
    return result


def metrics(stem, *extra):
    return json.loads(dgpc("inspect", stem, *extra).stdout)


def add_noise(src, dst, fraction, seed=0):
    """Copy the net ``src`` to ``dst`` with Gaussian noise of ``fraction`` of the mean edge."""
    net = read_net(src)
    rng = np.random.default_rng(seed)
    net.f = net.f + fraction * mean_edge_length(net.f) * rng.standard_normal(net.f.shape)
    write_net(dst, net)
    return dst


def revolution_strips(d, profile, rows, cols, span, units, net="net"):
    """In folder ``d``: a net of revolution of the built-in ``profile`` (``rows`` × ``cols``,
    ``span`` degrees, in ``units``) as ``d/net`` and its planar-quad strips as ``d/s``."""
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", rows, "--cols", cols,
         "--span", span, "--units", units, "-o", d / net)
    dgpc("planarize-strips", d / net, "-o", d / "s")
    return d / "s"


def bent_catenoid_chain(d):
    """In folder ``d``: a 9×7 catenoid ring bent by Minding (λ 0.7) as ``bent``, its ``mold``,
    ``strips``, ``flat`` and ``sheets`` (700×500 mm, 100 mm per unit): one artifact of
    every kind a report draws."""
    dgpc("init", "--surface", "revolution", "--profile", "catenoid", "--rows", 9, "--cols", 7,
         "--span", 360, "-o", d / "cat")
    write_net(d / "bent", NetArtifact(f=minding_bend(read_net(d / "cat").f, 0.7)))
    dgpc("extract-mold", d / "bent", "-o", d / "mold")
    dgpc("planarize-strips", d / "bent", "-o", d / "strips")
    dgpc("unfold", d / "strips", "-o", d / "flat")
    dgpc("nest", d / "flat", "--sheet", "700x500", "--scale", 100, "-o", d / "sheets")


def wall_net(d, rows, cols, name="wall"):
    """The demo wall's net (``samples/profiles/wall.csv``, 60°, in m) as ``d/name``."""
    from pathlib import Path

    profile = Path(__file__).resolve().parents[1] / "samples" / "profiles" / "wall.csv"
    dgpc("init", "--surface", "revolution", "--profile", profile, "--rows", rows, "--cols",
         cols, "--span", 60, "--units", "m", "-o", d / name)
    return d / name
