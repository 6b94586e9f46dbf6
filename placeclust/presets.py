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
from typing import Any

#: Settings for 360° panoramas with the heading at the centre column (``envs.world.panorama``): side
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
PANORAMA: Mapping[str, Any] = MappingProxyType(
    {"view": "sides", "kernel_capacity": 600, "scene_change": 0.25, "scale": 0.75,
     "consolidate": 0.85})

#: :data:`PANORAMA` with two thresholds set for ORB's binary descriptors:
#: ``OnlinePlaceClustering("orb", **PANORAMA_ORB)``; on the CLI, ``--preset panorama-orb
#: --features orb``. The gate's threshold is a share of matched features and ``t_new_cluster``
#: a distance, and both run in other ranges for ORB than for SIFT: with :data:`PANORAMA`'s
#: values ORB opens 5.6 places per room on ``test``, and a lower gate (fewer scene changes
#: inside rooms, so fewer frames that may open a place) removes most of them. Chosen on the
#: ``val`` split (24 tours, 150 frames per room; the ORB bar is precision
#: >= 0.93 and at most 3 places per room): a gate at 0.15 / 0.12 / 0.11 / 0.10 gave 4.0 / 3.2 /
#: 2.9 / 2.5 places per room (worst precision 0.96 / 0.96 / 0.92 / 0.75); at 0.12,
#: ``t_new_cluster`` 0.85 / 0.92 / 0.94 met the bar on 8 / 21 / 23 of 24 tours
#: (``docs/benchmarks.md``). With SIFT these values would merge rooms: keep :data:`PANORAMA`.
PANORAMA_ORB: Mapping[str, Any] = MappingProxyType(
    {**PANORAMA, "scene_change": 0.12, "t_new_cluster": 0.94})

#: Named configurations of :class:`OnlinePlaceClustering` (the CLI's ``--preset``): ``paper``
#: is seed 000's recognizer with the library's defaults, ``panorama`` is :data:`PANORAMA` and
#: ``panorama-orb`` :data:`PANORAMA_ORB`.
PRESETS: Mapping[str, Mapping[str, Any]] = MappingProxyType(
    {"paper": MappingProxyType({}), "panorama": PANORAMA, "panorama-orb": PANORAMA_ORB})
