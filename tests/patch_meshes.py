"""Reference meshes for ``init --patches``: two lobes joined by a valley (one net over both
needs strips whose width varies many times along them), and a gentle vault (one net is fine).
Built here so that the tests own them."""

from __future__ import annotations

import numpy as np
from outline_meshes import _grid_faces

#: Two lobes: plan LOBES_SIZE (x × y, metres), lobe centres at x = ±LOBE_OFFSET, height and
#: radius of each Gaussian lobe.
LOBES_SIZE, LOBE_OFFSET, LOBE_HEIGHT, LOBE_RADIUS = (24.0, 10.0), 6.0, 2.0, 4.0


def two_lobes(rows: int = 48, cols: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Two round hills over the plan ``|x| ≤ 12``, ``|y| ≤ 5``, the valley between them along
    ``x = 0``: ``z = H (exp(−((x − a)² + y²) / r²) + exp(−((x + a)² + y²) / r²))``."""
    lx, ly = LOBES_SIZE
    x, y = np.meshgrid(np.linspace(-lx / 2, lx / 2, rows + 1),
                       np.linspace(-ly / 2, ly / 2, cols + 1), indexing="ij")
    z = LOBE_HEIGHT * (np.exp(-((x - LOBE_OFFSET) ** 2 + y ** 2) / LOBE_RADIUS ** 2)
                       + np.exp(-((x + LOBE_OFFSET) ** 2 + y ** 2) / LOBE_RADIUS ** 2))
    return np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1), _grid_faces(rows, cols)


def vault(rows: int = 40, cols: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """A gentle barrel vault over ``0 ≤ x ≤ 20``, ``0 ≤ y ≤ 10``: ``z = 2 + 0.08 y (10 − y)``."""
    x, y = np.meshgrid(np.linspace(0, 20, rows + 1), np.linspace(0, 10, cols + 1),
                       indexing="ij")
    z = 2.0 + 0.08 * y * (10 - y)
    return np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1), _grid_faces(rows, cols)
