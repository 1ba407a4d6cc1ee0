"""How far a net's quads are from the surface of revolution it is to be pressed on (paper
§4.2.2, §6.2.3): the fabrication error of a drag in revolution or isometric mode.

Per quad the largest relative difference of its four edges and two diagonals against its
quad on the mold (:func:`~dgpc_cli.mold.panels.quad_isometry_error`): the mold that
``extract-mold`` builds from the net itself (N = n − 1 segments, one full turn), or, for an
isometric deformation, the input net's quads (a meridian net is its own mold patch).
"""

from __future__ import annotations

import numpy as np

from dgpc_cli.errors import DgpcError
from dgpc_cli.mold.panels import quad_isometry_error
from dgpc_cli.mold.profile import column_factors, meridian, mold_grid, net_widths


def own_mold_grid(f: np.ndarray) -> np.ndarray | None:
    """The mold patch ``(m, n, 3)`` of the surface of revolution that ``extract-mold`` builds
    from the net ``f (m, n, 3)`` (one full turn), or None where no surface of revolution fits
    (the strip widths change faster than the meridian steps allow)."""
    widths = net_widths(f)
    c = column_factors(widths.w, widths.d)
    try:
        mer = meridian(widths.d, widths.l, f.shape[1] - 1, c_max=float(c.max()))
    except DgpcError:
        return None
    return mold_grid(mer, mer.column_angles(c))


def panel_errors(f: np.ndarray, against: np.ndarray | None = None) -> np.ndarray | None:
    """Per quad ``(m−1, n−1)`` the isometry error of the net ``f`` against its own mold, or
    against the quads of ``against (m, n, 3)``; None where no mold fits."""
    f = np.asarray(f, dtype=float)
    mold = own_mold_grid(f) if against is None else np.asarray(against, dtype=float)
    if mold is None:
        return None
    return quad_isometry_error(f, mold)


def panel_error_summary(f: np.ndarray, against: np.ndarray | None = None) -> dict:
    """``{"max": float | None, "worst_quad": [u, v] | None}`` of :func:`panel_errors`."""
    err = panel_errors(f, against)
    if err is None or not np.isfinite(err).any():
        return {"max": None, "worst_quad": None}
    u, v = np.unravel_index(int(np.nanargmax(err)), err.shape)
    return {"max": float(err[u, v]), "worst_quad": [int(u), int(v)]}
