import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from envs.tasks.goals import door_distances
from envs.world.robot import N_RANGES

STILL = np.zeros(2, np.float32)


def _inside(env, room_name):
    plan = env.unwrapped.plan
    x, y = plan.free_point(plan.room_by_name(room_name).id, np.random.default_rng(0))
    return (x, y, 0.0)


def test_check_env_gymnasium_and_sb3(make_task):
    env = make_task(panorama=True, panorama_width=256, panorama_height=64, goal_panorama=True)
    check_env(env.unwrapped, skip_render_check=True)
    sb3 = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3.check_env(make_task(), warn=True)


def test_goal_is_in_the_observation_and_start_is_elsewhere(make_task):
    env = make_task()
    for seed in range(6):
        obs, info = env.reset(seed=seed)
        assert obs["goal"].argmax() == info["goal_id"] and obs["goal"].sum() == 1
        assert info["room_id"] != info["goal_id"]
        assert info["goal"] == env.unwrapped.plan.rooms[info["goal_id"]].name
        assert info["goal_distance"] > 0 and not info["is_success"]


def test_success_and_reward_at_known_poses(make_task):
    env = make_task(max_episode_steps=50)
    names = [r.name for r in env.unwrapped.plan.rooms]
    env.reset(seed=0, options={"goal": names[0], "pose": _inside(env, names[0])})
    _, reward, terminated, truncated, info = env.step(STILL)
    assert terminated and info["is_success"] and not truncated
    assert reward == pytest.approx(10.0 - 0.01, abs=0.05)

    env.reset(seed=0, options={"goal": names[0], "pose": _inside(env, names[1])})
    _, reward, terminated, _, info = env.step(STILL)
    assert not terminated and not info["is_success"]
    assert reward == pytest.approx(-0.01, abs=0.02)  # standing still: no shaping


def test_truncates_after_budget_without_success(make_task):
    env = make_task(max_episode_steps=5)
    env.reset(seed=3)
    for _ in range(5):
        _, _, terminated, truncated, info = env.step(STILL)
    assert truncated and not terminated and not info["is_success"]


def test_goal_distance_shrinks_towards_the_goal(make_task):
    env = make_task().unwrapped
    env.reset(seed=0)
    plan, goal = env.plan, env.goal
    gx, gy = plan.rooms[goal].center
    assert env.goal_distance(gx, gy) == 0.0
    door = next(d for d in plan.doors if goal in d.rooms)
    other = next(r for r in door.rooms if r != goal)
    ox, oy = plan.rooms[other].center
    far = env.goal_distance(ox, oy)
    mid = env.goal_distance((ox + door.x) / 2, (oy + door.y) / 2)
    assert 0 < mid < far
    assert far == pytest.approx(math.dist((ox, oy), (door.x, door.y)), abs=1e-6) or far < \
        math.dist((ox, oy), (door.x, door.y))
    assert all(v >= 0 for v in door_distances(plan, goal).values())


def test_unknown_goal_names_the_rooms(make_task):
    env = make_task()
    with pytest.raises(KeyError, match="unknown room 'ballroom'"):
        env.reset(seed=0, options={"goal": "ballroom"})
    with pytest.raises(KeyError, match="this world has"):
        gym.make("PlaceNav-ReachRoom-v0", goal="ballroom", panorama=False)


def test_range_ring_turns_with_the_robot(make_task):
    env = make_task()
    x, y, _ = _inside(env, env.unwrapped.plan.rooms[0].name)
    a, _ = env.reset(seed=0, options={"pose": (x, y, 0.0)})
    b, _ = env.reset(seed=0, options={"pose": (x, y, math.pi / 2)})
    quarter = N_RANGES // 4
    # the ray that looked left (+y) at heading 0 looks ahead at heading pi/2
    np.testing.assert_allclose(b["ranges"], np.roll(a["ranges"], -quarter), atol=0.03)
    assert a["ranges"].min() > 0.1 and a["ranges"].max() <= 4.0
    np.testing.assert_allclose(b["heading"], [0.0, 1.0], atol=1e-5)
    assert "panorama" not in a
