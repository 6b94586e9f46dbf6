"""Named configurations of :class:`~placeclust.online.OnlinePlaceClustering`.

Examples:
    :data:`PANORAMA` is read-only, so that one caller's change cannot leak into another's
    recognizer; derive a variant with ``dict``:

    >>> from placeclust import PANORAMA, OnlinePlaceClustering
    >>> model = OnlinePlaceClustering(**PANORAMA)
    >>> model.view, model.kernel_capacity, model.scene_change, model.scale, model.consolidate
    ('sides', 600, 0.25, 0.75, 0.85)
    >>> OnlinePlaceClustering(**dict(PANORAMA, scale=1.0)).scale
    1.0
    >>> PANORAMA["scale"] = 1.0
    Traceback (most recent call last):
        ...
    TypeError: 'mappingproxy' object does not support item assignment
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

#: Settings for 360° panoramas with the heading at the centre column (``envs.panorama``): side
#: views, kernels of half the size for half the features, the scene-change gate, detection on a
#: 0.75 copy of the frame, and consolidation (a young place that keeps matching an older one is
#: merged into it, :mod:`placeclust.consolidation`). The thresholds stay the defaults.
#: ``OnlinePlaceClustering(**PANORAMA)``; on the CLI, ``--preset panorama``. Read-only, so that
#: one caller's change cannot leak into another's recognizer.
#:
#: Why consolidation: on long tours rooms are entered again from other doors and seen from new
#: sides, and such a visit opened a second place for the room; on the ``val`` split's 250-frame
#: tours consolidation took the tours meeting the bar from 9 to 20 of 24 (``docs/design.md``).
#: ``dict(PANORAMA, consolidate=None)`` turns it off.
#:
#: Why ``scale=0.75``: SIFT is most of a frame's time, and OpenCV's SIFT doubles its input for
#: its first octave, so a 0.75 copy still yields nearly all the features, faster, with the same
#: quality on the simulator's tours (``docs/benchmarks.md``). Its price is poorer reuse
#: under another condition (light, furniture, noise), which the gate already makes poor;
#: ``dict(PANORAMA, scale=1.0)`` gives the full-size detection back.
PANORAMA: Mapping[str, object] = MappingProxyType(
    {"view": "sides", "kernel_capacity": 600, "scene_change": 0.25, "scale": 0.75,
     "consolidate": 0.85})

#: Named configurations of :class:`OnlinePlaceClustering` (the CLI's ``--preset``): ``paper``
#: is seed 000's recognizer with the library's defaults, ``panorama`` is :data:`PANORAMA`.
PRESETS: Mapping[str, Mapping[str, object]] = MappingProxyType(
    {"paper": MappingProxyType({}), "panorama": PANORAMA})
