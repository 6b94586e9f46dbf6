"""What every task with a goal room shares: walking distances, the shaped reward, success.

A task here is a :class:`NavTask`: a ``gym.Env`` that owns a ``PlaceNav-v0``
(:class:`~envs.tasks.place_nav.PlaceNavEnv`, as ``self.nav``) and scores the robot's progress
towards a room with a :class:`GoalRoom`. It never subclasses ``PlaceNavEnv``: the base env keeps
one reset and one step, and a task adds its goal around them. ``docs/design.md`` ("Adding a
task") walks through a new one.

Examples:
    >>> import numpy as np
    >>> from envs.world.layout import generate_floor_plan
    >>> plan = generate_floor_plan(3, np.random.default_rng(0))
    >>> goal = GoalRoom(plan)
    >>> x, y = plan.rooms[0].center
    >>> goal.start(0, (x, y)) == 0.0  # inside the goal room
    True
    >>> goal.start(1, (x, y)) > 0.0
    True
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import gymnasium as gym
import networkx as nx
import numpy as np
from gymnasium import spaces

from ..world.layout import FloorPlan
from .place_nav import PlaceNavEnv


def door_graph(plan: FloorPlan) -> nx.Graph:
    """The doors as a graph: an edge joins two doors of the same room, weighted by the straight
    line (m) between their centres."""
    g = nx.Graph()
    g.add_nodes_from(range(len(plan.doors)))
    for i, a in enumerate(plan.doors):
        for j in range(i + 1, len(plan.doors)):
            b = plan.doors[j]
            if set(a.rooms) & set(b.rooms):
                g.add_edge(i, j, weight=math.dist((a.x, a.y), (b.x, b.y)))
    return g


def door_distances(plan: FloorPlan, goal: int) -> dict[int, float]:
    """Shortest walking distance (m) from each door's centre to the goal room, through doors
    (:func:`door_graph`); the doors of the goal room are at distance 0.
    """
    g = door_graph(plan)
    sources = {i for i, d in enumerate(plan.doors) if goal in d.rooms}
    return dict(nx.multi_source_dijkstra_path_length(g, sources)) if sources else {}


def walking_distance(plan: FloorPlan, to_goal: dict[int, float], goal: int, x: float,
                     y: float, room: int | None = None) -> float:
    """Walking distance (m) from (x, y) to room ``goal`` through doors, 0 inside it.

    ``to_goal`` is :func:`door_distances` of ``goal``; ``room`` is the room (x, y) is taken to
    be in (default: the one it lies in). A point outside every room, or in a room with no path
    to the goal, is ``inf``.
    """
    room = plan.room_at(x, y) if room is None else room
    if room == goal:
        return 0.0
    return min((math.dist((x, y), (d.x, d.y)) + to_goal[i]
               for i, d in enumerate(plan.doors) if room in d.rooms and i in to_goal),
               default=math.inf)


class GoalRoom:
    """The walk to one goal room: its distance, the shaped reward of a step, success.

    The reward of a step is ``shaping * (d_before - d_after) - step_cost``, with ``d`` the
    ground-truth walking distance to the goal room (potential-based shaping, Ng et al. 1999:
    it does not change which policies are optimal), plus ``success_reward`` on entering it.
    Where the distance is undefined (outside every room) the last one stands, so shaping
    pauses.

    Args:
        plan: the building.
        success_reward, step_cost, shaping: the reward's terms (per step, per metre).
    """

    def __init__(self, plan: FloorPlan, success_reward: float = 10.0, step_cost: float = 0.01,
                 shaping: float = 1.0) -> None:
        self.plan = plan
        self.success_reward, self.step_cost, self.shaping = success_reward, step_cost, shaping
        self._to_goal = {r.id: door_distances(plan, r.id) for r in plan.rooms}
        self.goal = 0
        self.distance = 0.0

    def distance_from(self, x: float, y: float, room: int | None = None) -> float:
        """Walking distance (m) from (x, y) to the goal room (:func:`walking_distance`)."""
        return walking_distance(self.plan, self._to_goal[self.goal], self.goal, x, y, room)

    def walk(self, goal: int, pose: Sequence[float], room: int | None = None) -> float:
        """Walking distance (m) from ``pose`` (x, y[, heading]) to room ``goal``, without
        aiming at it (:func:`walking_distance`; ``room`` as in :meth:`step`)."""
        return walking_distance(self.plan, self._to_goal[goal], goal, pose[0], pose[1], room)

    def start(self, goal: int, pose: Sequence[float], room: int | None = None) -> float:
        """Aim at room ``goal`` from ``pose`` (x, y[, heading]); returns the distance to walk
        (may be ``inf``). ``room``: as in :meth:`step`."""
        self.goal = goal
        self.distance = self.distance_from(pose[0], pose[1], room)
        return self.distance

    def step(self, pose: Sequence[float], room_id: int, room: int | None = None
             ) -> tuple[float, bool]:
        """The robot is now at ``pose`` (x, y[, heading]), in ``room_id`` (-1: none); returns
        (reward, success).

        ``room`` is the room the distance is measured from (default: the one (x, y) lies in).
        """
        distance = self.distance_from(pose[0], pose[1], room)
        if not math.isfinite(distance):
            distance = self.distance
        success = room_id == self.goal
        reward = self.shaping * (self.distance - distance) - self.step_cost
        if success:
            reward += self.success_reward
        self.distance = distance
        return float(reward), bool(success)


class NavTask(gym.Env):
    """Base of the tasks: a ``gym.Env`` around the ``PlaceNav-v0`` it owns, ``self.nav``.

    It gives a task the building's ``plan``, ``world_id`` and ``image_key``, renders and closes
    through ``nav``. A subclass builds ``nav`` in its ``__init__``, declares its spaces, and
    implements ``reset`` (calling ``super().reset(seed=seed)`` first; then either
    :meth:`share_rng`, so that the task's draws and the start pose come from one generator, or
    ``nav.reset(seed=...)`` with a seed drawn from ``self.np_random``) and ``step``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    nav: PlaceNavEnv
    observation_space: spaces.Dict

    @property
    def plan(self) -> FloorPlan:
        """The building's floor plan (ground truth, for scoring and drawing)."""
        return self.nav.plan

    @property
    def world_id(self) -> str:
        """The building's and camera's fingerprint (``PlaceNav-v0``'s ``world_id``)."""
        return self.nav.world_id

    @property
    def image_key(self) -> str:
        """The observation key of the camera image: ``panorama`` or ``image``."""
        return self.nav.image_key

    def share_rng(self) -> None:
        """Hand this task's generator to ``nav``: one stream for goals and start poses."""
        self.nav.np_random = self.np_random

    def render(self) -> np.ndarray | None:
        return self.nav.render()

    def close(self) -> None:
        self.nav.close()


class HeardGoal(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """``PlaceNav-GuidedTour-v1`` for stable-baselines3: the errand's goal, a room *name*
    (``Text``, which SB3's policies cannot take), as a one-hot over the names in the order the
    guide said them on this episode's tour.

    The order is the tour's, not the building's: the agent learns nothing it was not told (the
    guide's first name is index 0 in every building). ``Box(0, 1, (max_rooms,), float32)``;
    ``max_rooms`` (default 32, the most rooms a building has) bounds the names.

    Examples:
        >>> import gymnasium as gym
        >>> import envs
        >>> from stable_baselines3.common.env_checker import check_env
        >>> env = HeardGoal(gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3,
        ...                          n_errands=1, tour_steps_per_room=40))
        >>> obs, info = env.reset(seed=0)
        >>> obs["goal"].shape, info["named"].index(info["goal"]) == int(obs["goal"].argmax())
        ((32,), True)
        >>> check_env(env)  # SB3's own checks; MultiInputPolicy trains on it
        >>> env.close()
    """

    def __init__(self, env: gym.Env, max_rooms: int = 32) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, max_rooms=max_rooms)
        gym.ObservationWrapper.__init__(self, env)
        space = env.observation_space
        if not isinstance(space, spaces.Dict) or "goal" not in space.spaces:
            raise ValueError("HeardGoal wraps PlaceNav-GuidedTour-v1 (a Dict with a 'goal')")
        self.max_rooms = max_rooms
        self.observation_space = spaces.Dict(
            {**space.spaces, "goal": spaces.Box(0.0, 1.0, (max_rooms,), np.float32)})
        self._named: list[str] = []

    def reset(self, *, seed: int | None = None, options: dict | None = None
              ) -> tuple[dict, dict]:
        obs, info = self.env.reset(seed=seed, options=options)
        self._named = list(info["named"])
        if len(self._named) > self.max_rooms:
            raise ValueError(f"the guide named {len(self._named)} rooms; HeardGoal was made "
                             f"for at most max_rooms={self.max_rooms}")
        return self.observation(obs), info

    def observation(self, observation: dict) -> dict:
        one_hot = np.zeros(self.max_rooms, np.float32)
        one_hot[self._named.index(str(observation["goal"]))] = 1.0
        return {**observation, "goal": one_hot}
