"""Figures and the HTML index of ``dgpc report`` (SPEC §2; paper Fig. 11, 13, 17, 18).

* :mod:`.render` — matplotlib (Agg) figures rendered to deterministic PNG bytes;
* :mod:`.net` — nets in a fixed 3-D view coloured per quad, the Clairaut plot, the mold profile;
* :mod:`.html` — the ``index.html`` page: the figures and the artifact's metrics as a table.

The dispatch per artifact kind lives in :mod:`dgpc_cli.stages.report`.
"""
