"""Simulated buildings for place recognition: the ``PlaceNav`` Gymnasium environments.

Importing this package registers ``PlaceNav-v0`` and ``PlaceNav-ReachRoom-v0`` and, unless the
user has chosen a backend, selects MuJoCo's headless EGL renderer (``MUJOCO_GL=egl``), which
must happen before ``mujoco`` is imported anywhere.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
# PyOpenGL reads its platform from this variable; keep it consistent with MuJoCo's choice.
if os.environ["MUJOCO_GL"] in ("egl", "osmesa"):
    os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])

from gymnasium.envs.registration import register  # noqa: E402

from envs.place_id import PlaceIdWrapper  # noqa: E402
from envs.place_nav import PlaceNavEnv  # noqa: E402
from envs.reach_room import ReachRoomEnv  # noqa: E402

register(
    id="PlaceNav-v0",
    entry_point="envs.place_nav:PlaceNavEnv",
    max_episode_steps=500,
)
register(
    id="PlaceNav-ReachRoom-v0",
    entry_point="envs.reach_room:ReachRoomEnv",
    max_episode_steps=300,
)

__all__ = ["PlaceIdWrapper", "PlaceNavEnv", "ReachRoomEnv"]
