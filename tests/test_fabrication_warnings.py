"""planarize-strips' warnings about strips that fail to build the design, with a strip the trim
dropped (wholly beyond the outline: no end gaps at all) among them."""

from dgpc_cli.stages.strip_fabrication import fabrication_warnings


def test_a_dropped_strip_has_no_end_gaps_and_the_worst_is_named():
    fab = {"max_end_gap": 15.0, "area_ratio": 1.0,
           "per_strip": {"S-v00": {"end_gaps": [None, None]},
                         "S-v01": {"end_gaps": [2.0, None]},
                         "S-v02": {"end_gaps": [-15.0, 0.5]}}}
    (line,) = fabrication_warnings(fab)
    assert "up to 15 mm" in line and "(S-v02)" in line
