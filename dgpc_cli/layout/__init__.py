"""Laying nets on reference meshes (SPEC §5): base curves and the nets traced or projected from
them (``grids``), the candidates and their choice (``choice``), the search by the result
(``search``), the largest strip width (``width``), patches (``patches``), quad nets imported
(``quads``) and the size guard of a net (``net_size``).

Pure functions over meshes and nets: nothing here writes an artifact (``stages.init`` does).
It takes from ``geodesics``, ``surfaces``, ``io`` (reading), ``metrics`` and ``core``, never
from ``stages``: what it needs of the optimizer (the quick fit that ranks candidates) is
handed to it (``search.NetFit``).
"""
