"""Simulated buildings for place recognition: the ``PlaceNav`` Gymnasium environments.

Importing this package registers ``PlaceNav-v0``, ``PlaceNav-ReachRoom-v0``,
``PlaceNav-GuidedTour-v1``, ``PlaceNav-ImageGoal-v0`` and ``PlaceNav-ImageGoal-v1``
(:mod:`envs.tasks.image_goal`, placenav-v5's) and, unless the user has chosen a
backend, selects MuJoCo's headless EGL renderer (``MUJOCO_GL=egl``), which must happen
before ``mujoco`` is imported anywhere.

Four subpackages by role, each importing only those before it: ``world`` (the building and
how it is drawn), ``tasks`` (the Gymnasium envs and wrappers), ``agents`` (the planners that
act on a recognizer's map) and ``commands`` (the ``placeclust`` command); ``docs/design.md``
maps every module.

In a clone this package is ``envs``; a wheel installs it as ``placeclust_envs`` (a top-level
``envs`` would shadow the PyPI package of that name). Every import inside it is relative, so
the code is the same under either name; ``gym.make(f"{envs.__name__}:PlaceNav-v0")`` names it
for spawned workers either way.

Examples:
    >>> import gymnasium as gym
    >>> env = gym.make("PlaceNav-v0", panorama_width=64, panorama_height=16)
    >>> obs, info = env.reset(seed=0)
    >>> obs["panorama"].shape, info["room_name"]
    ((16, 64, 3), 'toilet')
    >>> env.close()
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
# PyOpenGL reads its platform from this variable; keep it consistent with MuJoCo's choice.
if os.environ["MUJOCO_GL"] in ("egl", "osmesa"):
    os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])

from gymnasium.envs.registration import register, registry  # noqa: E402

from .tasks import image_goal  # noqa: E402,F401  (registers PlaceNav-ImageGoal-v1)
from .tasks.guided_tour import GuidedTourEnv  # noqa: E402
from .tasks.place_id import PlaceIdWrapper  # noqa: E402
from .tasks.place_nav import PlaceNavEnv  # noqa: E402
from .tasks.reach_room import ReachRoomEnv  # noqa: E402

# One registration per id, whichever name (envs, placeclust_envs) imported the package first.
_TOUR = "tasks.guided_tour:GuidedTourEnv"
for _id, _entry, _steps, _kwargs in (
        ("PlaceNav-v0", "tasks.place_nav:PlaceNavEnv", 500, {}),
        ("PlaceNav-ReachRoom-v0", "tasks.reach_room:ReachRoomEnv", 300, {}),
        # errands bound the episode: no step limit of its own
        ("PlaceNav-GuidedTour-v1", _TOUR, None, {}),
        # errands to a picture of a spot, declared arrived by the agent (ImageNav's STOP)
        ("PlaceNav-ImageGoal-v0", _TOUR, None, {"goal_kind": "image"}),
        # v0 let an errand start a step from its goal; kept to reproduce figures made with it
        ("PlaceNav-GuidedTour-v0", _TOUR, None, {"min_errand_distance": 0.0})):
    if _id not in registry:
        register(id=_id, entry_point=f"{__name__}.{_entry}", max_episode_steps=_steps,
                 kwargs=_kwargs)

__all__ = ["GuidedTourEnv", "PlaceIdWrapper", "PlaceNavEnv", "ReachRoomEnv"]
