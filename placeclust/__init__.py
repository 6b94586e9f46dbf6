"""placeclust: unsupervised, online place recognition from image sequences.

Free of gymnasium and MuJoCo: numpy, OpenCV and scientific Python only, so it runs on real
image sequences as well as on the simulator's tours.
"""

from placeclust.allocator import keep_frame_buffers

# before any frame is processed: per-frame buffers stay in the heap (see placeclust.allocator)
keep_frame_buffers()

from placeclust.online import PANORAMA, PRESETS, UNKNOWN, OnlinePlaceClustering  # noqa: E402
from placeclust.presets import PANORAMA_ORB  # noqa: E402

__all__ = ["PANORAMA", "PANORAMA_ORB", "PRESETS", "UNKNOWN", "OnlinePlaceClustering"]
__version__ = "0.19.0"
