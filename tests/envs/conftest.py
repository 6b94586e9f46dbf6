import gymnasium as gym
import pytest

import envs  # noqa: F401 - registers PlaceNav-v0


@pytest.fixture
def make_env():
    made = []

    def _make(**kwargs):
        kwargs.setdefault("panorama_width", 256)
        kwargs.setdefault("panorama_height", 64)
        env = gym.make("PlaceNav-v0", **kwargs)
        made.append(env)
        return env

    yield _make
    for env in made:
        env.close()
