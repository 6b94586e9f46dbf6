import gymnasium as gym
import pytest

import envs  # noqa: F401 - registers the PlaceNav envs


@pytest.fixture
def made():
    """Envs made by a test, closed after it."""
    envs_made = []
    yield envs_made
    for env in envs_made:
        env.close()


@pytest.fixture
def make_env(made):
    """``PlaceNav-v0`` at 256x64 unless told otherwise."""

    def _make(**kwargs):
        kwargs.setdefault("panorama_width", 256)
        kwargs.setdefault("panorama_height", 64)
        made.append(gym.make("PlaceNav-v0", **kwargs))
        return made[-1]

    return _make


@pytest.fixture
def make_task(made):
    """``PlaceNav-ReachRoom-v0`` without the panorama unless told otherwise."""

    def _make(**kwargs):
        kwargs.setdefault("panorama", False)
        made.append(gym.make("PlaceNav-ReachRoom-v0", **kwargs))
        return made[-1]

    return _make
