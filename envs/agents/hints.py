"""The learned errand agent: PPO acting on what transfers between buildings.

A policy that saw place ids or room names directly would learn one building. This one sees
what means the same in every building: the tour planner's suggested action
(:mod:`envs.agents.teach_repeat`, itself built from the recognizer's map of the building at hand),
whether the planner has a route, whether the recognizer says the goal place is reached, whether
the place id just changed, and the robot's rangefinders and odometry. PPO is trained on
``train``-split buildings (``python -m train.train --agent errands --config
train/hyperparams/ppo_errands.yml``) and evaluated on ``test`` buildings, with any recognizer,
through ``placeclust errands --agent ppo``.

Examples:
    >>> import gymnasium as gym
    >>> from envs.agents.hints import PlannerHints, N_FEATURES
    >>> env = PlannerHints(gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3,
    ...                             n_errands=1, tour_steps_per_room=40))
    >>> obs, info = env.reset(seed=0)
    >>> obs.shape == (N_FEATURES,) and obs in env.observation_space
    True
    >>> env.close()
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..world.robot import MAX_RANGE, MAX_SPEED, MAX_TURN, N_RANGES
from .teach_repeat import TourPlanner

#: planner action (2), route / at-goal / place-changed flags (3), ranges, odometry (2)
N_FEATURES = 2 + 3 + N_RANGES + 2


@runtime_checkable
class _PlaceTask(Protocol):
    """A task whose ``place_id`` names ``max_places`` places, ``max_places`` being "unknown"
    (:class:`~envs.tasks.guided_tour.GuidedTourEnv`)."""

    max_places: int


def unknown_place(env: gym.Env) -> int:
    """The ``place_id`` that ``env``, ``PlaceNav-GuidedTour-v1`` wrapped or not, gives for
    "unknown": its ``max_places``."""
    task = env.unwrapped
    # by attribute, not class: a process may load this package as both envs and placeclust_envs,
    # and gym.make gives the class of whichever registered the id first
    assert isinstance(task, _PlaceTask), f"{type(task).__name__} has no max_places"
    return task.max_places


class HintFeatures:
    """The feature vector of one step, from a :class:`TourPlanner` learnt on the episode's tour.

    Args:
        unknown: the env's ``place_id`` value for "unknown".
        seed: the planner's seed.
    """

    def __init__(self, unknown: int, seed: int = 0) -> None:
        self.planner = TourPlanner(unknown, seed)
        self.unknown = unknown
        self._place = unknown

    def reset(self, tour, obs: dict[str, Any]) -> np.ndarray:
        """Learn the tour; the features of the first errand step."""
        self.planner.reset(tour, obs)
        self._place = int(obs["place_id"])
        return self(obs)

    def __call__(self, obs: dict[str, Any]) -> np.ndarray:
        action = self.planner.act(obs)
        place = int(obs["place_id"])
        changed = place != self._place
        self._place = place
        goal = self.planner.names.get(str(obs["goal"]), -1)
        flags = [float(not self.planner.exploring), float(goal >= 0 and self.planner.place == goal),
                 float(changed)]
        odometry = np.asarray(obs["odometry"], np.float32) / np.array([MAX_SPEED, MAX_TURN])
        return np.concatenate([action, flags, np.asarray(obs["ranges"]) / MAX_RANGE,
                               np.clip(odometry, -2, 2)]).astype(np.float32)


def residual(features: np.ndarray, action: np.ndarray) -> np.ndarray:
    """The action the robot takes: the planner's (``features[:2]``) plus the policy's
    correction, clipped to the action space (residual policy learning, Silver et al. 2018)."""
    return np.clip(features[:2] + np.asarray(action, np.float32), -1.0, 1.0).astype(np.float32)


class PlannerHints(gym.Wrapper):
    """``PlaceNav-GuidedTour-v1`` seen through :class:`HintFeatures`, acted on as a residual.

    The observation is the feature vector; the action is a correction added to the planner's
    own action (:func:`residual`), so a policy that outputs zeros is the planner, and PPO
    starts from it instead of from a random walk.
    """

    def __init__(self, env: gym.Env, seed: int = 0) -> None:
        super().__init__(env)
        self.features = HintFeatures(unknown_place(env), seed)
        self.observation_space = spaces.Box(-2.0, 2.0, (N_FEATURES,), np.float32)
        self._last: np.ndarray = np.zeros(N_FEATURES, np.float32)

    def reset(self, **kwargs: Any) -> tuple[np.ndarray, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        self._last = self.features.reset(info["tour"], obs)
        return self._last, info

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(residual(self._last, action))
        if not terminated:
            self._last = self.features(obs)
        return self._last, float(reward), terminated, truncated, info
