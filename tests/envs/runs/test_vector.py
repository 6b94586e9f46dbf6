"""Vector envs in single-threaded workers: the same pictures as one env, settings restored."""

import os

import gymnasium as gym
import numpy as np
import pytest

from envs.runs.vector import WORKER_THREADS, make_vector_env, single_threaded_workers


def test_single_threaded_workers_see_what_one_env_sees():
    kwargs = dict(panorama_width=128, panorama_height=32, n_rooms=3)
    vec = make_vector_env(2, **kwargs)
    try:
        obs, _ = vec.reset(seed=[0, 1])
        actions = np.tile(np.array([[0.5, 0.3]], np.float32), (2, 1))
        for _ in range(3):
            obs, *_ = vec.step(actions)
    finally:
        vec.close()
    for k, seed in enumerate((0, 1)):
        env = gym.make("PlaceNav-v0", **kwargs)
        env.reset(seed=seed)
        for _ in range(3):
            alone, *_ = env.step(actions[k])
        env.close()
        np.testing.assert_array_equal(obs["panorama"][k], alone["panorama"])


def test_worker_settings_are_set_inside_and_restored_after(monkeypatch):
    monkeypatch.delenv("LP_NUM_THREADS", raising=False)
    monkeypatch.setenv("OMP_NUM_THREADS", "3")  # the user's own choice wins
    with single_threaded_workers():
        assert os.environ["LP_NUM_THREADS"] == WORKER_THREADS["LP_NUM_THREADS"]
        assert os.environ["OMP_NUM_THREADS"] == "3"
    assert "LP_NUM_THREADS" not in os.environ
    assert os.environ["OMP_NUM_THREADS"] == "3"


def test_no_workers_is_refused():
    with pytest.raises(ValueError, match="num_envs must be at least 1"):
        make_vector_env(0)
