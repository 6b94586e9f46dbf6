import pytest

import envs  # noqa: F401
from train.buildings import TrainBuildings
from train.make import make_env

TASK = {"recognizer": "oracle", "n_rooms": 3, "n_errands": 1, "tour_steps_per_room": 40,
        "errand_steps": 80}


def test_training_buildings_come_from_the_train_split_and_change():
    with pytest.raises(ValueError, match="not in the 'train' split"):
        TrainBuildings([0, 2000], **TASK)
    env = make_env("errands", scene_seeds=[0, 1, 2], episodes_per_building=1, **TASK)
    try:
        seen = set()
        for seed in range(6):
            env.reset(seed=seed)
            seen.add(env.scene_seed)
        assert len(seen) > 1 and seen <= {0, 1, 2}  # not one building over and over
    finally:
        env.close()


def test_buildings_draw_their_room_counts_and_observe_tour_features():
    with pytest.raises(ValueError, match="unknown observe 'eyes'"):
        TrainBuildings([0], observe="eyes", **TASK)
    task = {k: v for k, v in TASK.items() if k != "n_rooms"}
    env = TrainBuildings([0, 1, 2], observe="noplace", n_rooms=[2, 3], **task)
    try:
        counts = set()
        for seed in range(6):
            obs, _ = env.reset(seed=seed)
            assert obs in env.observation_space
            counts.add(len(env._env.unwrapped.plan.rooms))
        assert counts == {2, 3}
    finally:
        env.close()


def test_buildings_draw_their_layouts():
    with pytest.raises(ValueError, match="unknown layout"):
        TrainBuildings([0], observe="noplace", layout=["grid", "maze"], **TASK)
    env = TrainBuildings([0, 1], observe="noplace", layout=["grid", "corridor"], **TASK)
    try:
        layouts = set()
        for seed in range(8):
            obs, _ = env.reset(seed=seed)
            assert obs in env.observation_space  # the same features in either layout
            layouts.add(env.layout)
        assert layouts == {"grid", "corridor"}
    finally:
        env.close()
