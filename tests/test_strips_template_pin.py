"""The template of a net whose strips change width several times along their length (a bowling
pin dragged by a designer, isometric to its surface of revolution): the shared outline's curves
follow the strip (their degree from the net's developed strip) and the fit from the net's own
strips keeps one template close to the net, where the per-strip strips' developments differ by
several percent of the width (issue: strips that build the design)."""

import json

import numpy as np
import pytest
from cli_helpers import dgpc

from dgpc_cli.core.constraints.template import chebyshev_basis
from dgpc_cli.io.net import read_net
from dgpc_cli.strips.congruence import align
from dgpc_cli.strips.develop import develop_strip
from dgpc_cli.strips.fabrication import ruling_angles
from dgpc_cli.strips.planarize import planarize_strips, template_qualifies, template_strips
from dgpc_cli.strips.quality import planarity_defect
from dgpc_cli.strips.template import (
    OUTLINE_DEGREE,
    OUTLINE_MARGIN,
    OUTLINE_TOL,
    outline_degree,
    start_template,
)
from dgpc_cli.surfaces.profiles import builtin_profile
from dgpc_cli.surfaces.revolution import revolution_net


def _strips(f):
    return np.moveaxis(f[:, :-1], 1, 0), np.moveaxis(f[:, 1:], 1, 0)


def _outline_error(T, degree):
    """Largest distance (over the mean width) of the template ``T``'s boundaries from their
    least-squares Chebyshev curves x(y) of ``degree`` (the gauge of the fit)."""
    y, x = T[..., 1], T[..., 0]
    t = (y - 0.5 * (y.max() + y.min())) / (OUTLINE_MARGIN * 0.5 * np.ptp(y))
    width = np.linalg.norm(T[:, 1] - T[:, 0], axis=-1).mean()
    worst = 0.0
    for j in (0, 1):
        V, _ = chebyshev_basis(t[:, j], degree)
        c = np.linalg.lstsq(V, x[:, j], rcond=None)[0]
        worst = max(worst, np.abs(V @ c - x[:, j]).max())
    return worst / width


def test_the_outline_degree_follows_the_strip():
    """A bowling pin's meridian strip (width changing fourfold, a neck between) needs curves
    above the lowest degree, the lowest that holds it within the tolerance; a cylinder's
    straight strip keeps the lowest degree."""
    pin = revolution_net(builtin_profile("bowling-pin"), 21, 5)
    T = start_template(*_strips(pin))
    d = outline_degree(*_strips(pin))
    assert OUTLINE_DEGREE < d < pin.shape[0] - 1
    assert _outline_error(T, d) <= OUTLINE_TOL < _outline_error(T, d - 1)
    assert _outline_error(T, OUTLINE_DEGREE) > 10 * OUTLINE_TOL       # the old degree, far off
    cylinder = revolution_net(builtin_profile("cylinder"), 21, 5)
    assert outline_degree(*_strips(cylinder)) == OUTLINE_DEGREE


@pytest.fixture(scope="module")
def pin(tmp_path_factory):
    """A 13×5 bowling-pin meridian net twisted by a designer's drag (one end row's corners
    pushed out and in by 0.3 of their radius), optimized to stay isometric to the pin."""
    d = tmp_path_factory.mktemp("pin")
    base = revolution_net(builtin_profile("bowling-pin"), 13, 5)
    handles = []
    for (u, v), k in (((0, 0), 0.0), ((0, -1), 0.0), ((-1, 0), 0.3), ((-1, -1), -0.3)):
        p = base[u, v]
        handles.append({"index": [u % 13, v % 5],
                        "target": (p + k * np.array([p[0], p[1], 0.0])).tolist()})
    (d / "h.json").write_text(json.dumps({"handles": handles}))
    dgpc("init", "--surface", "revolution", "--profile", "bowling-pin", "--units", "m",
         "--rows", 13, "--cols", 5, "--span", 90, "-o", d / "base")
    dgpc("optimize", d / "base", "--mode", "isometric", "--handles", d / "h.json", "--steps", 5,
         "--max-strain", "3e-4", "--gpc-tol", "1e-4", "-o", d / "net", expect=None)
    return read_net(d / "net").f_mm


def test_a_dragged_bowling_pin_keeps_one_template(pin):
    """The dragged pin qualifies; its template is kept (not refused for deviating beyond the
    strips on their own), the shared outline fitted from the net's own strips, close to the
    net: every strip an exact planar bending, its outline the template's up to the chords
    between the outline's vertices, neighbouring rulings within 20°."""
    cols = list(range(pin.shape[1] - 1))
    assert template_qualifies(pin, cols) is None
    strips = planarize_strips(pin, cols)
    fitted, record = template_strips(pin, strips, "mm")
    assert fitted is not None, record.get("rejected")
    assert (record["variant"], record["start"]) == ("shared-outline", "net")
    P, Q = _strips(pin)
    width = np.linalg.norm(Q - P, axis=-1).mean()
    worst = max(s.deviation for s in fitted)
    assert worst <= record["per_strip_deviation"] + 0.005
    assert worst <= 0.035
    T = np.stack([np.asarray(record["A"]), np.asarray(record["B"])], axis=1)
    per = [develop_strip(s.A, s.B) for s in strips]
    assert max(align(d.A, d.B, per[0].A, per[0].B).error for d in per) > 0.05 * width
    for s in fitted:
        assert planarity_defect(s.A, s.B).max() <= 1e-9 * width
        assert ruling_angles(s.A, s.B).max() <= 20.0 + 1e-6
        d = develop_strip(s.A, s.B)
        assert align(d.A, d.B, T[:, 0], T[:, 1]).error <= 0.01 * width
