"""A second lap: the recorded path driven again, near it and never on it."""

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401  (registers PlaceNav-v0)
from envs.agents.lap import MAX_OFFSET, drive_lap, lap_waypoints
from envs.tasks.tour import drive_tour


@pytest.fixture(scope="module")
def env():
    made = gym.make("PlaceNav-v0", scene_seed=1000, n_rooms=3, camera="forward",
                    image_width=24, image_height=16, max_episode_steps=None)
    yield made
    made.close()


def _distance_to(path, points):
    return np.array([np.linalg.norm(path[:, :2] - p[:2], axis=1).min() for p in points])


def test_a_lap_follows_the_recorded_path_to_its_end_a_little_to_one_side(env):
    """Fault caught: a lap along another route (its poses far from the path), one that stops
    early (its end far from the path's), or one that retraces the path exactly (a query would
    then see its reference's very image)."""
    first = drive_tour(env, 300)
    lap = drive_lap(env, first.pose, max_steps=600)
    near = _distance_to(first.pose, lap.pose)
    assert near.max() < MAX_OFFSET + 0.3
    assert np.linalg.norm(lap.pose[-1, :2] - first.pose[-1, :2]) < 0.6
    assert np.median(_distance_to(lap.pose, first.pose)) < MAX_OFFSET + 0.1  # the whole path
    assert np.median(near) > 0.03
    assert set(np.unique(lap.room[lap.room >= 0])) == set(np.unique(first.room[first.room >= 0]))


def test_the_same_seed_drives_the_same_lap_and_another_seed_another(env):
    first = drive_tour(env, 120)
    a, b = (drive_lap(env, first.pose, 200, seed=s) for s in (1, 1))
    c = drive_lap(env, first.pose, 200, seed=2)
    assert np.array_equal(a.pose, b.pose) and np.array_equal(a.frames, b.frames)
    assert not np.array_equal(a.pose[: len(c.pose)], c.pose[: len(a.pose)])


def test_waypoints_keep_off_walls_and_within_the_offset(env):
    """Fault caught: a shift that puts a waypoint in a wall or a doorway's jamb."""
    plan = env.unwrapped.plan
    first = drive_tour(env, 300)
    points = lap_waypoints(plan, first.pose, np.random.default_rng(0))
    assert len(points) > 5
    assert (_distance_to(first.pose, np.array(points)) <= MAX_OFFSET + 1e-6).all()
    free = [plan.is_free(x, y, 0.3) for x, y, _ in points]
    on_path = _distance_to(first.pose, np.array(points)) < 1e-6
    assert all(f or o for f, o in zip(free, on_path))


def test_a_lap_of_no_frames_is_refused(env):
    with pytest.raises(ValueError, match="max_steps must be a positive"):
        drive_lap(env, np.zeros((3, 3)), 0)
