"""The env each agent sees: which observations it gets decides what it can know.

| agent | observation keys besides ``goal``, ``heading``, ``ranges``, ``odometry`` |
|-------|------------------------------------------------------------------------|
| ``place`` | ``place_id`` from the online recognizer on a fixed map (:mod:`train.mapping`) |
| ``noplace`` | nothing: it must find its way from the rangefinders and compass alone |
| ``oracle`` | ``place_id`` = the ground-truth room: the upper bound |
| ``planner`` | all of ``PlaceNav``'s keys, ``goal_panorama`` and ``place_id`` (no learning) |

No agent sees the panorama itself: learning from pixels is not what this benchmark is about,
and it would not train on a CPU in an hour.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
from gymnasium.wrappers import FilterObservation

import envs  # noqa: F401  (registers the environments)
from envs.place_id import PlaceIdWrapper, TrueRoomWrapper
from placeclust import OnlinePlaceClustering

AGENTS = ("place", "noplace", "oracle", "planner")
SENSORS = ["goal", "heading", "ranges", "odometry"]
MAX_PLACES = 64


def make_env(agent: str, scene_seed: int = 0, n_rooms: int = 4, map_path: str | Path | None = None,
             max_episode_steps: int | None = None, **task: Any) -> gym.Env:
    """A ``PlaceNav-ReachRoom-v0`` env wrapped for ``agent`` (one of :data:`AGENTS`).

    Args:
        agent: which observations the agent gets (see the module's table).
        scene_seed, n_rooms: the world.
        map_path: the fixed place map (``place`` and ``planner`` agents only).
        max_episode_steps: step budget; None keeps the registered 300.
        **task: more arguments of :class:`envs.reach_room.ReachRoomEnv`.
    """
    if agent not in AGENTS:
        raise ValueError(f"unknown agent {agent!r}; choose one of {AGENTS}")
    looks = agent in ("place", "planner")
    if looks and map_path is None:
        raise ValueError(f"the {agent!r} agent needs map_path (see train.mapping.build_map)")
    kwargs = {} if max_episode_steps is None else {"max_episode_steps": max_episode_steps}
    env = gym.make("PlaceNav-ReachRoom-v0", scene_seed=scene_seed, n_rooms=n_rooms,
                   panorama=looks, goal_panorama=agent == "planner", **kwargs, **task)
    if looks:
        recognizer = OnlinePlaceClustering.load(map_path, world=env.unwrapped.world_id)
        env = PlaceIdWrapper(env, recognizer, max_places=MAX_PLACES, learn=False)
    if agent == "oracle":
        env = TrueRoomWrapper(env)
    if agent in ("place", "oracle"):
        return FilterObservation(env, ["place_id", *SENSORS])
    if agent == "noplace":
        return FilterObservation(env, SENSORS)
    return env
