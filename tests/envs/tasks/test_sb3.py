"""Every registered id works with stable-baselines3 as its users would use it: SB3's own
``check_env`` passes (the guided tour through :class:`~envs.tasks.goals.HeardGoal`, its
documented wrapper), and PPO's ``MultiInputPolicy`` trains on it through ``make_vec_env``."""

import gymnasium as gym
import pytest

import envs  # noqa: F401 - registers the ids
from envs.tasks.goals import HeardGoal

sb3 = pytest.importorskip("stable_baselines3")
from stable_baselines3.common.env_checker import check_env  # noqa: E402
from stable_baselines3.common.env_util import make_vec_env  # noqa: E402

SMALL = {"panorama_width": 64, "panorama_height": 16}
TOUR = {"recognizer": "oracle", "n_rooms": 3, "n_errands": 1, "tour_steps_per_room": 30,
        "errand_steps": 30}
#: each registered id with the arguments that make it small, and the wrapper SB3 needs
IDS = {"PlaceNav-v0": (SMALL, None), "PlaceNav-ReachRoom-v0": (SMALL, None),
       "PlaceNav-GuidedTour-v1": (TOUR, HeardGoal), "PlaceNav-GuidedTour-v0": (TOUR, HeardGoal),
       "PlaceNav-ImageGoal-v0": (TOUR, None), "PlaceNav-ImageGoal-v1": (TOUR, None)}


def test_every_registered_id_is_listed_here():
    assert {i for i in gym.registry if i.startswith("PlaceNav")} == set(IDS)


@pytest.mark.parametrize("env_id", sorted(IDS))
def test_sb3_check_env_passes(env_id):
    kwargs, wrapper = IDS[env_id]
    env = gym.make(env_id, **kwargs)
    env = wrapper(env) if wrapper else env
    try:
        check_env(env, warn=True)
    finally:
        env.close()


def test_ppo_trains_on_the_guided_tour_with_its_goal_heard():
    vec = make_vec_env("PlaceNav-GuidedTour-v1", n_envs=1, env_kwargs=TOUR,
                       wrapper_class=HeardGoal, seed=0)
    try:
        model = sb3.PPO("MultiInputPolicy", vec, n_steps=32, batch_size=16, n_epochs=1, seed=0,
                        device="cpu")
        model.learn(64)
    finally:
        vec.close()
    assert model.num_timesteps >= 64
