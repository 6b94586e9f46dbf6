"""Training across buildings: a new ``train``-split building every few episodes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the environments)
from envs.agents.learned import OBSERVE, observed
from envs.world.scene import LAYOUTS
from envs.world.splits import check_split


class TrainBuildings(gym.Env):
    """A new building every ``episodes_per_building`` episodes, drawn from ``scene_seeds``.

    Args:
        scene_seeds: ``train``-split scene seeds (a seed of another split is a ``ValueError``:
            agents never train where they are scored).
        episodes_per_building: episodes before the next building is built.
        observe: ``"hints"`` (:class:`~envs.agents.hints.PlannerHints`, the residual agent) or
            one of :data:`~envs.agents.tour_features.SENSES`
            (:class:`~envs.agents.tour_features.TourFeatures`, an agent on its own).
        n_rooms: the rooms of each building, or a list to draw each building's from.
        layout: the buildings' floor plan (:data:`~envs.world.scene.LAYOUTS`), or a list to
            draw each building's from: ``[grid, corridor]`` trains on both.
        repeat: env steps each action is held for (tour features only).
        **task: more ``PlaceNav-GuidedTour-v1`` arguments (``recognizer``, ``errand_start``...).
    """

    def __init__(self, scene_seeds: Sequence[int], episodes_per_building: int = 1,
                 observe: str = "hints", n_rooms: int | Sequence[int] = 6,
                 layout: str | Sequence[str] = "grid", repeat: int = 1, **task: Any) -> None:
        check_split("train", scene_seeds)
        if observe not in OBSERVE:
            raise ValueError(f"unknown observe {observe!r}; choose one of {OBSERVE}")
        self.scene_seeds = list(scene_seeds)
        self.episodes_per_building = episodes_per_building
        self.observe = observe
        self.repeat = repeat
        self.room_counts = [n_rooms] if isinstance(n_rooms, int) else list(n_rooms)
        self.layouts = [layout] if isinstance(layout, str) else list(layout)
        unknown = sorted(set(self.layouts) - set(LAYOUTS))
        if unknown or not self.layouts:
            raise ValueError(f"unknown layout {unknown or layout!r}; choose from {LAYOUTS}")
        self.task = task
        self._episodes = 0
        self._env = self._make(self.scene_seeds[0], self.room_counts[0], self.layouts[0])
        self.observation_space = self._env.observation_space
        self.action_space = self._env.action_space

    def _make(self, scene_seed: int, n_rooms: int, layout: str) -> gym.Env:
        self.scene_seed, self.layout = scene_seed, layout  # the current episode's building
        env = gym.make("PlaceNav-GuidedTour-v1", scene_seed=scene_seed, n_rooms=n_rooms,
                       layout=layout, **self.task)
        return observed(env, self.observe, self.repeat)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        if self._episodes and self._episodes % self.episodes_per_building == 0:
            self._env.close()
            scene = self.scene_seeds[int(self.np_random.integers(len(self.scene_seeds)))]
            rooms = self.room_counts[int(self.np_random.integers(len(self.room_counts)))]
            layout = self.layouts[int(self.np_random.integers(len(self.layouts)))]
            self._env = self._make(scene, rooms, layout)
        self._episodes += 1
        return self._env.reset(seed=int(self.np_random.integers(2**31)), options=options)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        return self._env.step(action)

    def close(self) -> None:
        self._env.close()
