"""Running the ``dgpc`` command in-process and reading what it wrote."""

from __future__ import annotations

import json

import numpy as np
from click.testing import CliRunner

from dgpc_cli.cli.main import cli
from dgpc_cli.core.problem import mean_edge_length
from dgpc_cli.io.net import read_net, write_net


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
