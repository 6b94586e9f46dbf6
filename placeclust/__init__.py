"""placeclust: unsupervised, online place recognition from image sequences.

Free of gymnasium and MuJoCo: numpy, OpenCV and scientific Python only, so it runs on real
image sequences as well as on the simulator's tours.
"""

from placeclust.online import UNKNOWN, OnlinePlaceClustering

__all__ = ["UNKNOWN", "OnlinePlaceClustering"]
__version__ = "0.4.0"
