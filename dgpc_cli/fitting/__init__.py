"""Optimization policy on top of the solver (``core``): the modes' weights and schedules
(``modes``), the polish of a nearly gpc net (``polish``), the run of one optimization with its
handle steps, relaxation and final projection, and the judgement of its result (``optimize``),
and the soundness gate a net or strips pass before a fabrication stage uses them
(``soundness``).

Pure functions over nets: nothing here reads or writes an artifact (``stages.optimize`` does).
It takes from ``core``, ``metrics``, ``mold`` and ``strips``, never from ``stages`` or above.
"""
