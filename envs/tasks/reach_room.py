"""``PlaceNav-ReachRoom-v0``: drive to the room named in the observation."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces

from .goals import GoalRoom, NavTask
from .place_nav import PlaceNavEnv


class ReachRoomEnv(NavTask, gym.utils.EzPickle):
    """Reach a named room of the building: ``PlaceNav-v0`` with a goal room.

    Each episode names a goal room (drawn from the episode's seed, or fixed by ``goal`` or by
    ``reset(options={"goal": name})``) and starts the robot in another room.

    ## Action Space
    ``PlaceNav-v0``'s: ``Box(-1, 1, (2,))``, normalised forward speed and turn rate.

    ## Observation Space
    The keys of ``PlaceNav-v0`` plus ``goal``, ``Box(0, 1, (n_rooms,), float32)``: the goal
    room as a one-hot vector over ``plan.rooms``; with ``goal_panorama=True`` also
    ``goal_panorama``, the panorama seen from the goal room's centre facing +x.

    ## Rewards
    ``shaping * (d_before - d_after) - step_cost`` per step, where ``d`` is the ground-truth
    walking distance (m) to the goal room through doorways
    (:class:`~envs.tasks.goals.GoalRoom`): potential-based shaping, so it does not change which
    policies are optimal. ``success_reward`` on entering the goal room.

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
    - v0: first version. Since placeclust 0.13.0 the task owns its ``PlaceNav-v0`` (``nav``)
      instead of subclassing it; episodes are the same.
    """

    def __init__(self, goal: str | None = None, goal_panorama: bool = False,
                 success_reward: float = 10.0, step_cost: float = 0.01, shaping: float = 1.0,
                 render_mode: str | None = None, **world: Any) -> None:
        # pickle and deepcopy rebuild the env from its arguments, as PlaceNav-v0 does
        gym.utils.EzPickle.__init__(self, goal=goal, goal_panorama=goal_panorama,
                                    success_reward=success_reward, step_cost=step_cost,
                                    shaping=shaping, render_mode=render_mode, **world)
        self.nav = PlaceNavEnv(render_mode=render_mode, **world)
        self.render_mode = render_mode
        self.fixed_goal = None if goal is None else self.plan.room_by_name(goal).id
        self.with_goal_panorama = goal_panorama
        if goal_panorama and (not self.nav.with_panorama or self.nav.camera != "panorama"):
            raise ValueError("goal_panorama=True needs the 360° panorama (panorama=True, "
                             "camera='panorama')")
        self.goal_room = GoalRoom(self.plan, success_reward, step_cost, shaping)
        self._goal_panoramas: dict[int, np.ndarray] = {}
        n = len(self.plan.rooms)
        extra: dict[str, spaces.Space] = {"goal": spaces.Box(0.0, 1.0, (n,), np.float32)}
        if goal_panorama:
            extra["goal_panorama"] = self.nav.observation_space["panorama"]
        self.observation_space = spaces.Dict({**self.nav.observation_space.spaces, **extra})
        self.action_space = self.nav.action_space

    @property
    def goal(self) -> int:
        """The goal room's id."""
        return self.goal_room.goal

    @property
    def goal_name(self) -> str:
        return self.plan.rooms[self.goal].name

    def goal_distance(self, x: float, y: float) -> float:
        """Ground-truth walking distance (m) from (x, y) to the goal room, 0 inside it."""
        return self.goal_room.distance_from(x, y)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        self.share_rng()
        options = dict(options or {})
        goal = options.pop("goal", None)
        # draw the goal first, then a start room that is not the goal
        if goal is not None:
            goal_id = self.plan.room_by_name(goal).id
        elif self.fixed_goal is not None:
            goal_id = self.fixed_goal
        else:
            goal_id = int(self.np_random.integers(len(self.plan.rooms)))
        if "pose" not in options and "room" not in options and len(self.plan.rooms) > 1:
            others = [r.name for r in self.plan.rooms if r.id != goal_id]
            options["room"] = others[int(self.np_random.integers(len(others)))]
        obs, info = self.nav.reset(options=options)
        distance = self.goal_room.start(goal_id, info["pose"])
        if not math.isfinite(distance):
            raise ValueError(f"the start pose {info['pose'].tolist()} has no path to the goal room")
        return self._with_goal(obs), self._goal_info(info, False)

    def step(self, action: np.ndarray
             ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        obs, _, _, truncated, info = self.nav.step(action)
        reward, success = self.goal_room.step(info["pose"], info["room_id"])
        return self._with_goal(obs), reward, success, truncated, self._goal_info(info, success)

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
            nav = self.nav
            data = mujoco.MjData(nav.model)
            x, y = self.plan.rooms[room].center
            if not self.plan.is_free(x, y, 0.45):
                x, y = self.plan.free_point(room, np.random.default_rng(room))
            nav.robot.place(data, x, y, 0.0)
            mujoco.mj_forward(nav.model, data)
            self._goal_panoramas[room] = nav.renderer.panorama(data).copy()
        return self._goal_panoramas[room]

    def _goal_info(self, info: dict[str, Any], success: bool) -> dict[str, Any]:
        info.update(goal=self.goal_name, goal_id=self.goal, is_success=bool(success),
                    goal_distance=self.goal_room.distance)
        return info
