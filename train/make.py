"""The env each agent sees: which observations it gets decides what it can know.

| agent | observation keys besides ``goal``, ``heading``, ``ranges``, ``odometry`` |
|-------|------------------------------------------------------------------------|
| ``place`` | ``place_id`` from the online recognizer on a fixed map (:mod:`train.mapping`) |
| ``noplace`` | nothing: it must find its way from the rangefinders and compass alone |
| ``oracle`` | ``place_id`` = the ground-truth room: the upper bound |
| ``planner`` | all of ``PlaceNav``'s keys, ``goal_panorama`` and ``place_id`` (no learning) |
| ``errands`` | guided tours of many buildings (:class:`train.buildings.TrainBuildings`) |

``errands`` is another task, ``PlaceNav-GuidedTour-v1`` in a new ``train`` building every
episode. Its config's ``observe`` says what the agent sees: ``hints``, the tour planner's
suggestion to correct (:mod:`envs.agents.hints`, ``ppo_errands.yml``), or ``noplace``,
``place`` or ``oracle``, an agent on its own (:mod:`envs.agents.tour_features`,
``ppo_tour.yml`` and ``ppo_tour_carried.yml``).

No agent sees the panorama itself: learning from pixels is not what this benchmark is about,
and it would not train on a CPU in an hour.

``sensors`` and ``range_limit`` narrow the robot's own sensors for every agent alike: the
config ``train/hyperparams/ppo_proximity.yml`` trains a robot whose rangefinders reach 0.8 m
instead of 4 m, enough not to hit walls but not to see the shape of the room. The world can
take that away instead: ``train/hyperparams/ppo_corridor.yml`` (``layout: corridor``) puts
the full ring in identical offices along a corridor (:mod:`envs.world.corridor`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.spaces import Box, Dict
from gymnasium.wrappers import FilterObservation, TransformObservation

import envs  # noqa: F401  (registers the environments)
from envs.tasks.place_id import PlaceIdWrapper, TrueRoomWrapper
from envs.world.robot import MAX_RANGE
from placeclust import OnlinePlaceClustering

AGENTS = ("place", "noplace", "oracle", "planner", "errands")
SENSORS = ("goal", "heading", "ranges", "odometry")
#: what the planner's controller steers with (:func:`envs.agents.topological.steer`)
PLANNER_SENSORS = frozenset({"heading", "ranges"})
MAX_PLACES = 64


def make_env(agent: str, scene_seed: int = 0, n_rooms: int = 4, map_path: str | Path | None = None,
             max_episode_steps: int | None = None, sensors: Sequence[str] = SENSORS,
             range_limit: float | None = None, **task: Any) -> gym.Env:
    """A ``PlaceNav-ReachRoom-v0`` env wrapped for ``agent`` (one of :data:`AGENTS`).

    Args:
        agent: which observations the agent gets (see the module's table).
        scene_seed, n_rooms: the world.
        map_path: the fixed place map (``place`` and ``planner`` agents only).
        max_episode_steps: step budget; None keeps the registered 300.
        sensors: the robot's sensors the agent observes, a subset of :data:`SENSORS` that holds
            ``goal`` (an agent that is not told the goal cannot be scored on reaching it).
        range_limit: if given, the rangefinders read at most this many metres (nothing nearer
            reads as the limit): proximity sensors instead of a ring that sees the whole room.
        **task: more arguments of :class:`envs.tasks.reach_room.ReachRoomEnv`.
    """
    if agent not in AGENTS:
        raise ValueError(f"unknown agent {agent!r}; choose one of {AGENTS}")
    if agent == "errands":  # guided tours of many buildings (train.buildings)
        from train.buildings import TrainBuildings

        return TrainBuildings(n_rooms=n_rooms, **task)
    sensors = _check_sensors(sensors)
    if agent == "planner" and not PLANNER_SENSORS <= set(sensors):
        raise ValueError("the planner steers by compass around what its rangefinders see; "
                         "its sensors must include 'heading' and 'ranges'")
    if range_limit is not None and not 0.0 < range_limit <= MAX_RANGE:
        raise ValueError(f"range_limit must be in (0, {MAX_RANGE}] m, got {range_limit}")
    looks = agent in ("place", "planner")
    if looks and map_path is None:
        raise ValueError(f"the {agent!r} agent needs map_path (see train.mapping.build_map)")
    kwargs = {} if max_episode_steps is None else {"max_episode_steps": max_episode_steps}
    env = gym.make("PlaceNav-ReachRoom-v0", scene_seed=scene_seed, n_rooms=n_rooms,
                   panorama=looks, goal_panorama=agent == "planner", **kwargs, **task)
    if looks:
        recognizer = OnlinePlaceClustering.load(map_path, world=env.unwrapped.world_id)
        env = PlaceIdWrapper(env, recognizer, max_places=MAX_PLACES, learn=False)
    if range_limit is not None:
        env = _limit_ranges(env, range_limit)
    if agent == "oracle":
        env = TrueRoomWrapper(env)
    if agent in ("place", "oracle"):
        return FilterObservation(env, ["place_id", *sensors])
    if agent == "noplace":
        return FilterObservation(env, sensors)
    return env


def _limit_ranges(env: gym.Env, limit: float) -> gym.Env:
    space = env.observation_space["ranges"]
    spaces = {**env.observation_space.spaces,
              "ranges": Box(0.0, limit, space.shape, space.dtype)}

    def clip(obs: dict[str, Any]) -> dict[str, Any]:
        return {**obs, "ranges": np.minimum(obs["ranges"], np.float32(limit))}

    return TransformObservation(env, clip, Dict(spaces))


def _check_sensors(sensors: Sequence[str]) -> list[str]:
    if isinstance(sensors, str):
        raise ValueError(f"sensors must be a list of names, got the string {sensors!r}")
    unknown = sorted(set(sensors) - set(SENSORS))
    if unknown:
        raise ValueError(f"unknown sensors {unknown}; choose from {list(SENSORS)}")
    if "goal" not in sensors:
        raise ValueError(f"sensors {list(sensors)} lack 'goal': the agent must be told the goal")
    return [s for s in SENSORS if s in sensors]  # one order, whatever the config's
