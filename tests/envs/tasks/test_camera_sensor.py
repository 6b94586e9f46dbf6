"""The camera-sensor wrapper: the env renders as before, the agent sees the sensor's frame."""

import gymnasium as gym
import numpy as np
import pytest

from envs.tasks.camera_sensor import CameraSensor, focal_length
from envs.world.sensor import Sensor

FORWARD = {"camera": "forward", "image_width": 48, "image_height": 32, "panorama": True}


def _pair(make_env, sensor, **kwargs):
    bare = make_env(**{**FORWARD, **kwargs})
    wrapped = CameraSensor(make_env(**{**FORWARD, **kwargs}), sensor)
    return bare, wrapped


def test_the_wrapper_keeps_the_space_and_degrades_the_image(make_env):
    bare, wrapped = _pair(make_env, Sensor(grey=True, read_noise=4))
    assert wrapped.observation_space == bare.observation_space
    b, _ = bare.reset(seed=3)
    w, _ = wrapped.reset(seed=3)
    assert w["image"].shape == b["image"].shape == (32, 48, 3)
    assert (w["image"][..., 0] == w["image"][..., 1]).all()
    assert not (w["image"] == b["image"]).all()
    assert np.array_equal(w["ranges"], b["ranges"])  # only the camera changes


def test_the_same_seed_gives_the_same_frames(make_env):
    _, wrapped = _pair(make_env, Sensor(shot_noise=2.0))
    first = wrapped.reset(seed=5)[0]["image"]
    again = wrapped.reset(seed=5)[0]["image"]
    other = wrapped.reset(seed=6)[0]["image"]
    assert np.array_equal(first, again) and not np.array_equal(first, other)


def test_motion_blur_follows_the_turn(make_env):
    bare, wrapped = _pair(make_env, Sensor(motion_blur=0.3))  # a long exposure
    bare.reset(seed=0)
    wrapped.reset(seed=0)
    straight = np.array([0.5, 0.0], np.float32)
    turn = np.array([0.0, 1.0], np.float32)
    b, w = bare.step(straight)[0]["image"], wrapped.step(straight)[0]["image"]
    assert np.array_equal(b, w)  # no turn: no smear
    for _ in range(3):  # up to turning speed
        b, w = bare.step(turn)[0]["image"], wrapped.step(turn)[0]["image"]
    rough = [np.abs(np.diff(x.astype(float), axis=1)).mean() for x in (b, w)]
    assert rough[1] < 0.8 * rough[0]  # smeared sideways: fewer sharp columns


def test_focal_length_reads_the_camera(make_env):
    forward = make_env(**{**FORWARD, "image_fov": 90.0})
    assert focal_length(forward) == pytest.approx(24.0)  # 48 / (2 tan 45°)
    panorama = make_env()
    assert focal_length(panorama) == pytest.approx(256 / (2 * np.pi))
    with pytest.raises(TypeError, match="no image_key"):
        focal_length(gym.make("CartPole-v1"))
