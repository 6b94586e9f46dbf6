"""The conditions a building can be seen under: its lightings and its appearance changes.

One table that the scene (:mod:`envs.world.scene` lights it), the env (``PlaceNav-v0``'s
``lighting`` argument), the CLI (``--lighting``) and the benchmark (``--conditions``) all read:
a new lighting is one entry of :data:`LIGHTS`, a new named condition one entry of
:data:`APPEARANCE`. Pure data: importing it loads neither MuJoCo nor OpenCV, so a benchmark's
parent process can check condition names without the simulator.

Examples:
    >>> LIGHTING
    ('day', 'cloudy', 'night')
    >>> CONDITIONS["night"], CONDITIONS["noisy"]["camera_blur"]
    ({'lighting': 'night'}, 1.0)
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

#: The lightings of the COLD database. Each: the headlight's ambient and diffuse grey levels,
#: and directional lights as (direction, diffuse RGB).
LIGHTS: Mapping[str, Mapping[str, Any]] = MappingProxyType({
    "day": {"ambient": 0.35, "headlight": 0.25,
            "sun": [((0.4, 0.3, -1.0), (0.55, 0.53, 0.48)),
                    ((-0.5, -0.2, -1.0), (0.2, 0.2, 0.22))]},
    "cloudy": {"ambient": 0.45, "headlight": 0.2,
               "sun": [((0.0, 0.0, -1.0), (0.3, 0.32, 0.36))]},
    "night": {"ambient": 0.12, "headlight": 0.35,
              "sun": [((0.2, -0.3, -1.0), (0.28, 0.22, 0.14))]},
})
#: the names of :data:`LIGHTS`, in order
LIGHTING: tuple[str, ...] = tuple(LIGHTS)

#: Named appearance changes (``PlaceNav-v0`` keyword arguments, :mod:`envs.world.changes`),
#: seen in the default lighting.
APPEARANCE: Mapping[str, Mapping[str, Any]] = MappingProxyType({
    # people moved things: a third of the furniture moved, a fifth removed, half the posters
    "moved": {"furniture_moved": 0.3, "furniture_removed": 0.2, "posters_swapped": 0.5,
              "changes_seed": 1},
    # a cheap camera: noise and blur
    "noisy": {"camera_noise": 8.0, "camera_blur": 1.0, "changes_seed": 1},
})

#: Every named condition the benchmark crosses (``day>night``, ``day>moved``...): each lighting
#: by its name, then each appearance change; values are ``PlaceNav-v0`` keyword arguments.
CONDITIONS: Mapping[str, dict[str, Any]] = MappingProxyType({
    **{name: {"lighting": name} for name in LIGHTS},
    **{name: dict(kwargs) for name, kwargs in APPEARANCE.items()},
})


#: the ``PlaceNav-v0`` keyword arguments a condition sets: a world under another condition is the
#: same world with these replaced
CONDITION_KEYS = frozenset({"lighting", "furniture_moved", "furniture_removed", "posters_swapped",
                            "camera_noise", "camera_blur", "changes_seed"})


def check_lighting(lighting: str) -> None:
    """A ``ValueError`` naming the lightings if ``lighting`` is not one of :data:`LIGHTING`."""
    if lighting not in LIGHTS:
        raise ValueError(f"unknown lighting {lighting!r}; choose one of {LIGHTING}")
