"""``PlaceNav-ReachRoom-v0``: drive to the room named in the observation."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import mujoco
import networkx as nx
import numpy as np
from gymnasium import spaces

from .layout import FloorPlan
from .place_nav import PlaceNavEnv


def door_distances(plan: FloorPlan, goal: int) -> dict[int, float]:
    """Shortest walking distance (m) from each door's centre to the goal room, through doors.

    Doors are the nodes of a graph whose edges join two doors of the same room, weighted by the
    straight line between their centres; the doors of the goal room are at distance 0.
    """
    g = nx.Graph()
    g.add_nodes_from(range(len(plan.doors)))
    for i, a in enumerate(plan.doors):
        for j in range(i + 1, len(plan.doors)):
            b = plan.doors[j]
            if set(a.rooms) & set(b.rooms):
                g.add_edge(i, j, weight=math.dist((a.x, a.y), (b.x, b.y)))
    sources = {i for i, d in enumerate(plan.doors) if goal in d.rooms}
    return nx.multi_source_dijkstra_path_length(g, sources) if sources else {}


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


class ReachRoomEnv(PlaceNavEnv):
    """Reach a named room of the building: :class:`~envs.place_nav.PlaceNavEnv` with a goal.

    Each episode names a goal room (drawn from the episode's seed, or fixed by ``goal`` or by
    ``reset(options={"goal": name})``) and starts the robot in another room.

    ## Observation Space
    The keys of ``PlaceNav-v0`` plus ``goal``, ``Box(0, 1, (n_rooms,), float32)``: the goal
    room as a one-hot vector over ``plan.rooms``; with ``goal_panorama=True`` also
    ``goal_panorama``, the panorama seen from the goal room's centre facing +x.

    ## Rewards
    ``shaping * (d_before - d_after) - step_cost`` per step, where ``d`` is the ground-truth
    walking distance (m) to the goal room through doorways (:func:`door_distances`): potential
    -based shaping, so it does not change which policies are optimal. ``success_reward`` on
    entering the goal room.

    ## Episode End
    Terminates on entering the goal room (``info["is_success"] = True``); truncates after the
    registered ``max_episode_steps`` = 300 steps (30 s) with ``is_success = False``.

    ## Info
    The keys of ``PlaceNav-v0`` plus ``goal`` (name), ``goal_id``, ``is_success`` and
    ``goal_distance`` (m).

    ## Arguments
    Those of ``PlaceNav-v0`` plus ``goal`` (a room name or ``None`` for a random goal per
    episode), ``goal_panorama`` (False), ``success_reward`` (10), ``step_cost`` (0.01) and
    ``shaping`` (1 per metre).

    ## Version History
    - v0: first version.
    """

    def __init__(self, goal: str | None = None, goal_panorama: bool = False,
                 success_reward: float = 10.0, step_cost: float = 0.01, shaping: float = 1.0,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        # a copy is rebuilt with this class's arguments too, not only PlaceNavEnv's
        gym.utils.EzPickle.__init__(self, goal=goal, goal_panorama=goal_panorama,
                                    success_reward=success_reward, step_cost=step_cost,
                                    shaping=shaping, **kwargs)
        self.fixed_goal = None if goal is None else self.plan.room_by_name(goal).id
        self.with_goal_panorama = goal_panorama
        if goal_panorama and (not self.with_panorama or self.camera != "panorama"):
            raise ValueError("goal_panorama=True needs the 360° panorama (panorama=True, "
                             "camera='panorama')")
        self.success_reward = success_reward
        self.step_cost = step_cost
        self.shaping = shaping
        self._to_goal = {r.id: door_distances(self.plan, r.id) for r in self.plan.rooms}
        self._goal_panoramas: dict[int, np.ndarray] = {}
        self.goal = 0
        self._distance = 0.0
        n = len(self.plan.rooms)
        extra = {"goal": spaces.Box(0.0, 1.0, (n,), np.float32)}
        if goal_panorama:
            extra["goal_panorama"] = self.observation_space["panorama"]
        self.observation_space = spaces.Dict({**self.observation_space.spaces, **extra})

    @property
    def goal_name(self) -> str:
        return self.plan.rooms[self.goal].name

    def goal_distance(self, x: float, y: float) -> float:
        """Ground-truth walking distance (m) from (x, y) to the goal room, 0 inside it."""
        return walking_distance(self.plan, self._to_goal[self.goal], self.goal, x, y)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        options = dict(options or {})
        goal = options.pop("goal", None)
        # draw the goal first, then a start room that is not the goal
        super(PlaceNavEnv, self).reset(seed=seed)
        if goal is not None:
            self.goal = self.plan.room_by_name(goal).id
        elif self.fixed_goal is not None:
            self.goal = self.fixed_goal
        else:
            self.goal = int(self.np_random.integers(len(self.plan.rooms)))
        if "pose" not in options and "room" not in options and len(self.plan.rooms) > 1:
            others = [r.name for r in self.plan.rooms if r.id != self.goal]
            options["room"] = others[int(self.np_random.integers(len(others)))]
        obs, info = super().reset(seed=None, options=options)
        self._distance = self.goal_distance(*info["pose"][:2])
        if not math.isfinite(self._distance):
            raise ValueError(f"the start pose {info['pose'].tolist()} has no path to the goal room")
        return self._with_goal(obs), self._goal_info(info, False)

    def step(self, action: np.ndarray
             ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        obs, _, _, truncated, info = super().step(action)
        distance = self.goal_distance(*info["pose"][:2])
        if not math.isfinite(distance):  # outside every room (pushed through a wall): no shaping
            distance = self._distance
        success = info["room_id"] == self.goal
        reward = self.shaping * (self._distance - distance) - self.step_cost
        if success:
            reward += self.success_reward
        self._distance = distance
        return self._with_goal(obs), float(reward), success, truncated, self._goal_info(info,
                                                                                       success)

    def _with_goal(self, obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        goal = np.zeros(len(self.plan.rooms), np.float32)
        goal[self.goal] = 1.0
        obs["goal"] = goal
        if self.with_goal_panorama:
            obs["goal_panorama"] = self.goal_panorama(self.goal).copy()  # callers may keep it
        return obs

    def goal_panorama(self, room: int) -> np.ndarray:
        """The panorama from ``room``'s centre facing +x (rendered once, then cached)."""
        if room not in self._goal_panoramas:
            data = mujoco.MjData(self.model)
            x, y = self.plan.rooms[room].center
            if not self.plan.is_free(x, y, 0.45):
                x, y = self.plan.free_point(room, np.random.default_rng(room))
            self.robot.place(data, x, y, 0.0)
            mujoco.mj_forward(self.model, data)
            self._goal_panoramas[room] = self.renderer.panorama(data).copy()
        return self._goal_panoramas[room]

    def _goal_info(self, info: dict[str, Any], success: bool) -> dict[str, Any]:
        info.update(goal=self.goal_name, goal_id=self.goal, is_success=bool(success),
                    goal_distance=self._distance)
        return info
