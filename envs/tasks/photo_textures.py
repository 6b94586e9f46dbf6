"""Photographic statistics for a compiled building's surfaces: a realism lever (issue 72).

The procedural textures of :mod:`envs.world.textures` are clean: flat colour, crisp
high-contrast marks, one 256-pixel tile repeated every two metres. Real walls and floors are
soft, carry detail at every scale with a power spectrum falling as ``1/f^2`` (van der Schaaf
and van Hateren 1996) and are worn. :func:`retexture` gives a compiled model's walls, floors
and furniture those statistics, in place, before anything is drawn:

- ``detail``: how much of the crisp pattern survives (``0`` blurs it into its colour field,
  ``1`` keeps it): clean marks are where the rendered frames' surplus keypoints come from;
- ``grain``: the contrast of a ``1/f`` (amplitude) field multiplied into the luminance;
- ``stains``: soft dark blotches per texture (wear).

Posters stay as they are: they are the printed, distinctive things a real room has too.
Nothing calls it by default, so a building without it renders as before. It lives beside the
tasks, not in :mod:`envs.world`, because it edits a compiled model as the camera wrapper of
:mod:`envs.tasks.camera_sensor` edits frames: the world's code stays as it was, and a
default ``PlaceNav-v0`` keeps its render fingerprint.

Examples:
    >>> from envs.world.scene import build_scene
    >>> from envs.tasks.photo_textures import retexture
    >>> scene = build_scene(0, n_rooms=2)
    >>> before = scene.model.tex_data.copy()
    >>> retexture(scene.model, seed=0) > 0, bool((scene.model.tex_data != before).any())
    (True, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import cv2
import gymnasium as gym
import mujoco
import numpy as np
from scipy import ndimage

from ..world.sensor import Sensor
from .camera_sensor import CameraSensor
from .place_nav import PlaceNavEnv
from .tour import Tour, drive_tour

#: the textures :func:`retexture` changes, by name prefix (:mod:`envs.world.scene` names them)
SURFACES = ("wall_tex", "floor_tex", "furniture_tex")


@dataclass(frozen=True)
class Photo:
    """The settings of :func:`retexture`; the defaults are the lever as measured in
    ``docs/benchmarks.md`` ("Textures with photographic statistics")."""

    detail: float = 0.35
    grain: float = 0.12
    stains: int = 6

    def __post_init__(self) -> None:
        if not (0.0 <= self.detail <= 1.0 and 0.0 <= self.grain <= 1.0
                and 0 <= self.stains <= 100):
            raise ValueError(f"photo settings out of range: {self} (detail and grain in [0, 1], "
                             "stains 0-100)")


def pink_field(rng: np.random.Generator, height: int, width: int, slope: float = 1.0
               ) -> np.ndarray:
    """Zero-mean, unit-std noise whose amplitude spectrum falls as ``1/f**slope``
    (``slope=1``: the ``1/f^2`` power of photographs), periodic so a tile joins its copy."""
    fy = np.fft.fftfreq(height)[:, None]
    fx = np.fft.rfftfreq(width)[None, :]
    f = np.hypot(fy, fx)
    f[0, 0] = np.inf  # no mean
    spectrum = (rng.normal(size=f.shape) + 1j * rng.normal(size=f.shape)) / f**slope
    field = np.fft.irfft2(spectrum, s=(height, width))
    return (field / (field.std() + 1e-12)).astype(np.float32)


def photographic(img: np.ndarray, rng: np.random.Generator, photo: Photo = Photo()
                 ) -> np.ndarray:
    """``img`` (H, W, 3 uint8) with photographic statistics: its pattern softened to
    ``detail``, a ``1/f`` luminance field of contrast ``grain`` and ``stains`` blotches."""
    h, w = img.shape[:2]
    x = img.astype(np.float32)
    soft = ndimage.gaussian_filter(x, sigma=(6.0, 6.0, 0.0), mode="wrap")  # tiles join
    x = soft + photo.detail * (x - soft)
    light = 1.0 + photo.grain * pink_field(rng, h, w)
    for _ in range(photo.stains):
        shape = np.zeros((h, w), np.float32)
        axes = (int(rng.integers(4, w // 6)), int(rng.integers(4, h // 6)))
        cv2.ellipse(shape, (w // 2, h // 2), axes, float(rng.uniform(0, 180)), 0, 360, 1.0, -1)
        blot = cv2.GaussianBlur(shape, (0, 0), sigmaX=max(axes) / 2 + 1)
        # drawn in the middle, rolled into place: a blotch over the tile's edge wraps round
        shift = (int(rng.integers(h)), int(rng.integers(w)))
        light -= float(rng.uniform(0.05, 0.2)) * np.roll(blot, shift, axis=(0, 1))
    return np.clip(x * light[..., None], 0, 255).astype(np.uint8)


def retexture(model: mujoco.MjModel, seed: int, photo: Photo = Photo()) -> int:
    """Give the walls', floors' and furniture's textures of ``model`` (a compiled
    :func:`~envs.world.scene.build_scene` model) photographic statistics, in place; returns
    how many textures changed. Call it before the first render: a renderer uploads the
    textures when it is made. The same ``seed`` and ``photo`` give the same pixels."""
    rng = np.random.default_rng([seed, 0x9407])
    changed = 0
    for i in range(model.ntex):
        name = model.texture(i).name
        if not name.startswith(SURFACES):
            continue
        h, w, c = int(model.tex_height[i]), int(model.tex_width[i]), int(model.tex_nchannel[i])
        start = int(model.tex_adr[i])
        flat = model.tex_data[start:start + h * w * c]
        flat[:] = photographic(flat.reshape(h, w, c), rng, photo).ravel()
        changed += 1
    return changed


def retextured_env(scene_seed: int, n_rooms: int, photo: Photo | None = Photo(),
                   sensor: Sensor | None = None, **env_kwargs: Any) -> gym.Env:
    """The ``PlaceNav-v0`` of ``env_kwargs`` (its camera, lighting, appearance changes), its
    surfaces given ``photo``'s statistics (seeded by ``scene_seed``; None: as ``PlaceNav-v0``
    draws them) before the first frame, then ``sensor``'s effects on its frames."""
    env: gym.Env = gym.make("PlaceNav-v0", scene_seed=scene_seed, n_rooms=n_rooms,
                            max_episode_steps=None, **env_kwargs)
    if photo is not None:
        retexture(cast(PlaceNavEnv, env.unwrapped).model, scene_seed, photo)
    return CameraSensor(env, sensor) if sensor is not None and sensor.active else env


def record_photo_tour(scene_seed: int, n_rooms: int, steps: int, photo: Photo = Photo(),
                      seed: int = 0, sensor: Sensor | None = None, **env_kwargs: Any) -> Tour:
    """:func:`~envs.tasks.tour.record_tour`'s scripted tour of a retextured building
    (:func:`retextured_env`). The same arguments give the same frames."""
    env = retextured_env(scene_seed, n_rooms, photo, sensor, **env_kwargs)
    try:
        return drive_tour(env, steps, seed=seed)
    finally:
        env.close()
