"""Gymnasium's own battery over every id this package registers: ``check_env``, two identically
seeded envs that match step for step (``check_environments_match``, ``info`` included), and a
pickle / deepcopy round trip (the copy is rebuilt from the constructor arguments)."""

import copy
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.utils.env_match import check_environments_match

import envs
from envs import PlaceIdWrapper

# small panoramas keep the battery fast; the code paths are those of the default size
SMALL = {"panorama_width": 64, "panorama_height": 16}
# and a short guided tour, with the cheaper of the recognizers that look at the panorama
TOUR = {"n_rooms": 3, "tour_steps_per_room": 40, "n_errands": 2, "recognizer": "panorama-orb"}


def small(env_id: str, **kwargs) -> dict:
    """The battery's arguments for ``env_id``."""
    return {**SMALL, **(TOUR if "GuidedTour" in env_id or "ImageGoal" in env_id else {}),
            **kwargs}
IDS = sorted(spec.id for spec in gym.registry.values()
             if str(spec.entry_point).startswith(f"{envs.__name__}."))


def test_the_package_registers_its_envs():
    assert IDS == ["PlaceNav-GuidedTour-v0", "PlaceNav-GuidedTour-v1", "PlaceNav-ImageGoal-v0",
                   "PlaceNav-ImageGoal-v1", "PlaceNav-ReachRoom-v0", "PlaceNav-v0"]


@pytest.mark.parametrize("env_id", IDS)
def test_check_env(env_id):
    env = gym.make(env_id, **small(env_id, render_mode="rgb_array"))
    check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize("env_id", IDS)
def test_identically_seeded_envs_match(env_id):
    a, b = gym.make(env_id, **small(env_id)), gym.make(env_id, **small(env_id))
    check_environments_match(a, b, num_steps=20, seed=3, info_comparison="equivalence")
    a.close()
    b.close()


@pytest.mark.parametrize("env_id", IDS)
@pytest.mark.parametrize("clone", [lambda e: pickle.loads(pickle.dumps(e)), copy.deepcopy],
                         ids=["pickle", "deepcopy"])
def test_copies_rebuild_the_same_env(env_id, clone):
    env = gym.make(env_id, **small(env_id, scene_seed=2, n_rooms=3, lighting="night"))
    env.reset(seed=1)
    twin = clone(env)
    assert twin.unwrapped is not env.unwrapped
    assert twin.unwrapped.world_id == env.unwrapped.world_id
    obs_a, _ = env.reset(seed=4)
    obs_b, _ = twin.reset(seed=4)
    for key in obs_a:
        np.testing.assert_array_equal(obs_a[key], obs_b[key])
    env.close()
    twin.close()


def test_the_place_id_wrapper_pickles_with_its_map():
    env = PlaceIdWrapper(gym.make("PlaceNav-v0"), max_places=8)
    env.reset(seed=0)
    for _ in range(3):
        env.step(np.zeros(2, np.float32))
    twin = pickle.loads(pickle.dumps(env))
    assert twin.recognizer.n_places == env.recognizer.n_places
    assert twin.observation_space == env.observation_space
    env.close()
    twin.close()
