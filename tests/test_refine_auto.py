"""planarize-strips --refine auto (the default): K = 1 where one template's strips meet the
deviation and seam-step targets, K = 2 where they miss one and K = 2 lowers the seam step
without raising the deviation; the choice recorded in parameters.refine_auto."""

from types import SimpleNamespace

import pytest
from cli_helpers import dgpc

from dgpc_cli.stages.planarize_run import _auto_refine
from dgpc_cli.stages.strip_fabrication import DEVIATION_WARN, SEAM_STEP_WARN


def _fitted(deviation, seam_step, template=True):
    art = SimpleNamespace(template={"fit": "shared-outline"} if template else None,
                          parameters={},
                          metrics={"fabrication": {"max_deviation_relative": deviation,
                                                   "max_seam_step_relative": seam_step}})
    return SimpleNamespace(art=art)


def _never():
    raise AssertionError("K = 2 fitted although K = 1 meets the targets")


def test_k1_kept_without_a_second_fit_where_it_meets_the_targets():
    first = _fitted(0.9 * DEVIATION_WARN, 0.9 * SEAM_STEP_WARN)
    assert _auto_refine(first, _never) is first
    assert first.art.parameters == {}                 # the K = 1 artifact unchanged


def test_per_strip_strips_never_refined():
    first = _fitted(2 * DEVIATION_WARN, 2 * SEAM_STEP_WARN, template=False)
    assert _auto_refine(first, _never) is first


@pytest.mark.parametrize("dev1, step1", [(2 * DEVIATION_WARN, 0.5 * SEAM_STEP_WARN),
                                         (0.5 * DEVIATION_WARN, 2 * SEAM_STEP_WARN)])
def test_k2_kept_where_k1_misses_and_k2_is_better(dev1, step1, caplog):
    first, second = _fitted(dev1, step1), _fitted(0.4 * DEVIATION_WARN, 0.4 * SEAM_STEP_WARN)
    with caplog.at_level("WARNING"):
        kept = _auto_refine(first, lambda: second)
    assert kept is second
    auto = second.art.parameters["refine_auto"]
    assert auto["tried"] == [1, 2] and auto["kept"] == 2
    assert auto["figures"]["1"] == {"deviation": dev1, "seam_step": step1}
    lines = [r.getMessage() for r in caplog.records if "--refine auto" in r.getMessage()]
    assert len(lines) == 1 and "K = 2 kept" in lines[0]


@pytest.mark.parametrize("dev2, step2", [
    (2.1 * DEVIATION_WARN, 0.5 * SEAM_STEP_WARN),      # deviation higher than K = 1's
    (0.5 * DEVIATION_WARN, 1.2 * SEAM_STEP_WARN),      # seam step not lower
])
def test_k1_kept_where_k2_is_not_better(dev2, step2):
    first, second = _fitted(2 * DEVIATION_WARN, 1.2 * SEAM_STEP_WARN), _fitted(dev2, step2)
    kept = _auto_refine(first, lambda: second)
    assert kept is first
    assert first.art.parameters["refine_auto"]["kept"] == 1


def test_refine_option_takes_auto_and_integers(tmp_path):
    for bad in ("0", "two"):
        assert "--refine" in dgpc("planarize-strips", tmp_path / "x", "--refine", bad,
                                  "-o", tmp_path / "y", expect=2).stderr
    for good in ("auto", "AUTO", "2"):                 # past the option: the net is missing
        result = dgpc("planarize-strips", tmp_path / "x", "--refine", good,
                      "-o", tmp_path / "y", expect=None)
        assert result.exit_code not in (0, 2) and "--refine" not in result.stderr
