"""Wrappers that tell an agent where it is: a live recognizer's place id, or the true room."""

from __future__ import annotations

import copy
import time
from typing import Any, SupportsFloat

import gymnasium as gym
import networkx as nx
import numpy as np
from gymnasium import spaces

from placeclust import OnlinePlaceClustering
from placeclust.protocol import (
    Localizer,
    OnlineRecognizer,
    can_localize,
    map_full,
    reads_images,
    view,
)
from placeclust.protocol import reset_position as forget_position

from .tour import building

#: what :class:`PlaceIdWrapper` needs of a recognizer: any online one (the protocol's
#: optional parts, :mod:`placeclust.protocol`, are used where present)
Recognizer = OnlineRecognizer


def _place_space(n: int, one_hot: bool) -> spaces.Space:
    return spaces.Box(0.0, 1.0, (n,), np.float32) if one_hot else spaces.Discrete(n)


def _encode(value: int, n: int, one_hot: bool) -> np.ndarray | np.int64:
    if not one_hot:
        return np.int64(value)
    v = np.zeros(n, np.float32)
    v[value] = 1.0
    return v


class PlaceIdWrapper(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """Runs an online place recognizer on every panorama and adds ``place_id`` to the observation.

    ``place_id`` is ``Discrete(max_places + 1)`` (or its one-hot ``Box`` with ``one_hot=True``):
    places ``0 .. max_places - 1`` as the recognizer numbers them, and the reserved value
    ``max_places`` for "unknown": a featureless frame, a frame that matches no place of a fixed
    map, or a place a recognizer of your own opened after ``max_places`` were taken (the map is
    full; ``info["map_full"]`` says so, and such a recognizer keeps mapping). The default
    recognizer is capped at ``max_places`` (``OnlinePlaceClustering(max_places=...)``): once
    full it localizes frames on its map instead of opening places no observation could name.

    The map persists across episodes by default, so place ids stay stable while an agent learns.
    Because ``reset`` carries the robot away, the recognizer forgets where it was and searches the
    whole map for the first frame of an episode.

    Args:
        env: an env whose observation is a ``Dict`` with a ``panorama``.
        recognizer: the recognizer; default a fresh :class:`~placeclust.OnlinePlaceClustering`
            with ORB features (fast enough for training) and at most ``max_places`` places.
            Pass a loaded map (``OnlinePlaceClustering.load``) to start from it.
        max_places: places the observation can name.
        one_hot: one-hot ``Box`` instead of ``Discrete``.
        learn: update the map from each frame; ``False`` localizes on a fixed map (needs the
            recognizer's ``localize_one``).
        reset_map: start every episode from the map the wrapper was given (a copy of it)
            instead of keeping what was learned.

    ``info`` gains ``place_id`` (the recognizer's raw answer, -1 for unknown), ``n_places`` and
    ``map_full``: all deterministic, so two identically seeded envs give identical ``info``.
    The recognizer's time on the last step (ms) is :attr:`place_ms`, kept out of ``info``
    because it differs from run to run. The topological graph is :attr:`graph`.
    """

    def __init__(self, env: gym.Env, recognizer: Recognizer | None = None, max_places: int = 64,
                 one_hot: bool = False, learn: bool = True, reset_map: bool = False) -> None:
        gym.utils.RecordConstructorArgs.__init__(
            self, recognizer=recognizer, max_places=max_places, one_hot=one_hot, learn=learn,
            reset_map=reset_map)
        gym.ObservationWrapper.__init__(self, env)
        space = env.observation_space
        key = getattr(env.unwrapped, "image_key", "panorama")
        # a recognizer that says it reads no images (placeclust.null's) is given None instead
        self.reads_images = reads_images(recognizer)
        if not isinstance(space, spaces.Dict) or (self.reads_images and key not in space.spaces):
            raise ValueError(f"PlaceIdWrapper needs a Dict observation with an {key!r} image "
                             "(create the env with panorama=True)")
        self.image_key = key
        if key != "panorama" and view(recognizer) == "sides":
            raise ValueError("the recognizer keeps the side views of a 360° panorama "
                             "(view='sides'), but this env's camera looks forward")
        if max_places < 1:
            raise ValueError(f"max_places must be at least 1, got {max_places}")
        if recognizer is None:
            recognizer = OnlinePlaceClustering("orb", max_places=max_places)
        self.recognizer = recognizer
        if not learn:
            self.check_localizes()
        self._initial = copy.deepcopy(recognizer) if reset_map else None
        self.max_places = max_places
        self.unknown = max_places
        self.one_hot = one_hot
        self.learn = learn
        self.place_ms = 0.0
        self.observation_space = spaces.Dict(
            {**space.spaces, "place_id": _place_space(max_places + 1, one_hot)})
        self._last: dict[str, Any] = {}

    @property
    def graph(self) -> nx.Graph:
        """The recognizer's topological graph of places."""
        return self.recognizer.graph

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        if self._initial is not None:
            self.recognizer = copy.deepcopy(self._initial)
        forget_position(self.recognizer)
        obs, info = super().reset(seed=seed, options=options)  # calls observation()
        return obs, {**info, **self._last}

    def step(self, action: Any
             ) -> tuple[dict[str, Any], SupportsFloat, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = super().step(action)
        return obs, reward, terminated, truncated, {**info, **self._last}

    @property
    def last_info(self) -> dict[str, Any]:
        """What the last observation added to ``info``: ``place_id``, ``n_places``,
        ``map_full``."""
        return dict(self._last)

    def check_localizes(self) -> None:
        """A ``ValueError`` unless the recognizer can localize on a fixed map
        (``localize_one``), as ``learn = False`` needs."""
        if not can_localize(self.recognizer):
            raise ValueError(f"learn=False needs a recognizer with localize_one(); "
                             f"{type(self.recognizer).__name__} has none")

    def relocated(self, observation: dict[str, Any], info: dict[str, Any]
                  ) -> tuple[dict[str, Any], dict[str, Any]]:
        """``observation`` and ``info`` of a robot the task put down elsewhere mid-episode
        (``PlaceNav-GuidedTour-v1``'s carried errands), with ``place_id``: the recognizer
        forgets where it was, keeps its map, and answers for the new frame."""
        forget_position(self.recognizer)
        observation = self.observation(observation)
        return observation, {**info, **self._last}

    def observation(self, observation: dict[str, Any]) -> dict[str, Any]:
        """``observation`` with ``place_id`` from one step of the recognizer."""
        start = time.perf_counter()
        frame = observation[self.image_key] if self.reads_images else None
        recognizer = self.recognizer
        if self.learn:  # frame is None only for a recognizer that reads no images
            raw = recognizer.learn_predict_one(frame)  # type: ignore[arg-type]
        else:
            assert isinstance(recognizer, Localizer)  # __init__ refuses learn=False without
            raw = recognizer.localize_one(frame)  # type: ignore[arg-type]
        value = raw if 0 <= raw < self.max_places else self.unknown
        self._last = {"place_id": int(raw), "n_places": self.recognizer.n_places,
                      "map_full": bool(raw >= self.max_places
                                       or map_full(self.recognizer))}
        self.place_ms = 1000.0 * (time.perf_counter() - start)
        return {**observation, "place_id": _encode(value, self.max_places + 1, self.one_hot)}


class TrueRoomWrapper(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Adds the ground-truth room as ``place_id``: the upper bound a recognizer can reach.

    ``place_id`` is ``Discrete(n_rooms + 1)`` (one-hot with ``one_hot=True``); ``n_rooms`` means
    outside the building. The env's ``info`` must carry ``room_id``.
    """

    def __init__(self, env: gym.Env, one_hot: bool = False) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, one_hot=one_hot)
        gym.Wrapper.__init__(self, env)
        self.n = len(building(env).plan.rooms) + 1
        self.one_hot = one_hot
        space = env.observation_space
        if not isinstance(space, spaces.Dict):
            raise ValueError(f"TrueRoomWrapper needs a Dict observation, got {space}")
        self.observation_space = spaces.Dict(
            {**space.spaces, "place_id": _place_space(self.n, one_hot)})

    def reset(self, **kwargs: Any) -> tuple[dict[str, Any], dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        return self._add(obs, info), info

    def step(self, action: Any
             ) -> tuple[dict[str, Any], SupportsFloat, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        return self._add(obs, info), reward, terminated, truncated, info

    def _add(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        room = info["room_id"] if info["room_id"] >= 0 else self.n - 1
        return {**obs, "place_id": _encode(room, self.n, self.one_hot)}
