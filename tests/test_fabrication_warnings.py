"""planarize-strips' warnings about strips that fail to build the design, with a strip the trim
dropped (wholly beyond the outline: no end gaps at all) among them."""

from dgpc_cli.stages.strip_fabrication import fabrication_warnings


def test_a_dropped_strip_has_no_end_gaps_and_the_worst_is_named():
    fab = {"max_end_gap_mm": 15.0, "area_ratio": 1.0,
           "per_strip": {"S-v00": {"end_gaps_mm": [None, None]},
                         "S-v01": {"end_gaps_mm": [2.0, None]},
                         "S-v02": {"end_gaps_mm": [-15.0, 0.5]}}}
    (line,) = fabrication_warnings(fab)
    assert "up to 15 mm" in line and "(S-v02)" in line


def test_deviation_and_seam_steps_beyond_their_targets_are_said_in_mm_and_percent():
    fab = {"max_end_gap_mm": 0.0, "area_ratio": 1.0, "per_strip": {},
           "max_deviation_mm": 5.35, "max_deviation_relative": 0.0152,
           "max_seam_step_mm": 9.14, "max_seam_step_relative": 0.026}
    dev, seam = fabrication_warnings(fab)
    assert "deviate from the net by up to 5.35 mm (1.52 % of the mean strip width" in dev
    assert "step at their seams by up to 9.14 mm (2.60 %" in seam
    fab.update(max_deviation_relative=0.015, max_seam_step_relative=0.01)
    assert fabrication_warnings(fab) == []
