"""A Gymnasium wrapper that puts a real camera's effects on an env's camera image.

:class:`CameraSensor` wraps ``PlaceNav-v0`` (or a task around it) and passes every
observation's image (``panorama`` or ``image``, whichever the env renders) through a
:class:`envs.world.sensor.Sensor`. The env itself renders as before, so its render
fingerprint, its maps and every figure made without the wrapper stay what they were. Motion
blur follows the robot: the turn between two steps over the step's duration gives the yaw
rate, and the rate times the exposure times the camera's focal length the smear in pixels.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> from envs.tasks.camera_sensor import CameraSensor
    >>> from envs.world.sensor import Sensor
    >>> env = CameraSensor(gym.make("PlaceNav-v0", camera="forward", image_width=64,
    ...                             image_height=48), Sensor(grey=True, jpeg=80))
    >>> obs, _ = env.reset(seed=0)
    >>> image = obs["image"]
    >>> image.shape, bool((image[..., 0] == image[..., 1]).all())
    ((48, 64, 3), True)
    >>> env.close()
"""

from __future__ import annotations

import math
from typing import Any, SupportsFloat

import gymnasium as gym
import numpy as np

from ..world.sensor import Sensor


def focal_length(env: gym.Env) -> float:
    """The focal length in pixels of the camera ``env`` renders: the forward camera's from its
    width and horizontal field of view, the panorama's one column per ``2π / width`` radian."""
    base = env.unwrapped
    key = getattr(base, "image_key", None)
    if key is None:
        raise TypeError(f"{type(base).__name__} renders no camera image (no image_key): wrap "
                        "a PlaceNav-v0 env")
    if key != "image":
        return float(base.geometry.focal)  # type: ignore[attr-defined]
    # EzPickle keeps the constructor's arguments: the one record of the field of view
    kwargs: dict[str, Any] = getattr(base, "_ezpickle_kwargs", {})
    width = kwargs.get("image_width", 320)
    return width / (2 * math.tan(math.radians(kwargs.get("image_fov", 70.0)) / 2))


class CameraSensor(gym.Wrapper):
    """``env`` with its camera image as :class:`Sensor` ``sensor`` would take it.

    Args:
        env: a ``PlaceNav-v0`` env, or a wrapper or task around one, that renders its image.
        sensor: the effects; with none on, observations pass through untouched.

    The noise follows ``reset(seed=...)``: the same seed gives the same frames.
    """

    def __init__(self, env: gym.Env, sensor: Sensor) -> None:
        super().__init__(env)
        self.sensor = sensor
        self._key = env.unwrapped.image_key  # type: ignore[attr-defined]
        self._focal = focal_length(env)
        # seconds a step lasts, from the constructor's arguments as the focal length is
        self._dt = float(getattr(env.unwrapped, "_ezpickle_kwargs", {}).get("control_dt", 0.1))
        self._rng = np.random.default_rng(0)
        self._heading: float | None = None

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[Any, dict[str, Any]]:
        obs, info = self.env.reset(seed=seed, options=options)
        if seed is not None:  # a seeded episode: its noise is the seed's, apart from the env's
            self._rng = np.random.default_rng([seed, 0x5E45])
        self._heading = _heading(info)
        return self._degrade(obs, 0.0), info

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        heading = _heading(info)
        turn = 0.0
        if heading is not None and self._heading is not None:
            turn = abs(math.remainder(heading - self._heading, 2 * math.pi))
        self._heading = heading
        blur = turn / self._dt * self.sensor.motion_blur * self._focal
        return self._degrade(obs, blur), reward, terminated, truncated, info

    def _degrade(self, obs: Any, blur_px: float) -> Any:
        if not self.sensor.active or not isinstance(obs, dict) or self._key not in obs:
            return obs
        return {**obs, self._key: self.sensor.apply(obs[self._key], self._rng, blur_px)}


def _heading(info: dict[str, Any]) -> float | None:
    pose = info.get("pose")
    return None if pose is None else float(pose[2])
