"""dgpc: discrete geodesic parallel coordinates for architectural fabrication.

Wang, Pellis, Rist, Pottmann, Müller (2019), "Discrete Geodesic Parallel Coordinates".
"""

__version__ = "0.1.0"
