import math

import gymnasium as gym
import numpy as np
import pytest

from envs.tasks.errand_goals import PointWalk
from envs.world.layout import generate_floor_plan

SMALL = {"n_rooms": 4, "n_errands": 3, "tour_steps_per_room": 50, "errand_steps": 80}


@pytest.fixture
def make_goals(made):
    def _make(**kwargs):
        made.append(gym.make("PlaceNav-ImageGoal-v0", **{**SMALL, **kwargs}))
        return made[-1]

    return _make


def test_walking_distance_is_straight_in_a_room_and_through_doors_between():
    plan = generate_floor_plan(5, np.random.default_rng(2))
    walk = PointWalk(plan)
    room = plan.rooms[0]
    a, b = (room.x0 + 0.2, room.y0 + 0.2), (room.x1 - 0.2, room.y1 - 0.2)
    assert walk(a, b) == pytest.approx(math.dist(a, b))
    for other in plan.rooms[1:]:
        d = walk(room.center, other.center)
        assert math.isfinite(d) and d >= math.dist(room.center, other.center) - 1e-9
        assert d == pytest.approx(walk(other.center, room.center))


def test_goals_are_tour_spots_far_enough_and_only_the_ceiling_knows_the_step(make_goals):
    env = make_goals(recognizer="oracle")
    obs, info = env.reset(seed=3)
    tour = env.unwrapped
    assert obs in env.observation_space and "goal" not in obs
    assert env.action_space.shape == (3,)
    unknown_step = env.observation_space["goal_step"].n - 1
    assert obs["goal_step"] == unknown_step and obs["goal_place"] < tour.max_places
    goal = tour.goals.goal
    assert tour.tour_rooms[goal.step] == goal.room == obs["goal_place"]  # the true room
    assert math.dist(goal.pose[:2], tour.tour_poses[goal.step][:2]) < 2.0
    assert tour.errands[0].shortest >= 2 * tour.goals.radius  # not reachable by a stop
    ceiling = make_goals(recognizer="oracle-pose")
    obs, _ = ceiling.reset(seed=3)
    assert obs["goal_step"] == ceiling.unwrapped.goals.goal.step


def test_a_stop_ends_the_errand_and_scores_the_distance_left(make_goals):
    env = make_goals(recognizer="oracle")
    obs, info = env.reset(seed=0)
    obs, reward, done, _, info = env.step(np.array([0.0, 0.0, 1.0], np.float32))
    result = info["errand_result"]
    assert result["steps"] == 1 and not result["success"] and result["spl"] == 0.0
    assert result["final_distance"] >= 2 * env.unwrapped.goals.radius - 0.2
    assert obs["errand"] == 1  # the next errand began
    with pytest.raises(ValueError, match=r"shape \(3,\) = \(forward, turn, stop\)"):
        env.step(np.zeros(2, np.float32))
    with pytest.raises(ValueError, match="NaN"):  # the stop entry is checked like the others
        env.step(np.array([0.0, 0.0, np.nan], np.float32))


def test_localizing_the_goal_moves_neither_the_robot_nor_its_tracking(make_goals):
    env = make_goals(recognizer="panorama-orb", panorama_width=128, panorama_height=32,
                     n_errands=2)
    env.reset(seed=1)
    tour = env.unwrapped
    model = tour.recognizer
    before = (model.current, tour.nav.data.qpos.copy())
    goal = tour.goals.draw(tour, 1, {"pose": tour.nav.robot.pose(tour.nav.data)}, 0,
                           tour._named, [])
    assert tour.goals.image is not None and tour.goals.image.shape == (32, 128, 3)
    assert model.current == before[0] and np.array_equal(tour.nav.data.qpos, before[1])
    assert -1 <= goal.place < model.n_places


def test_the_room_errands_still_take_two_actions(made):
    env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3, n_errands=1,
                   tour_steps_per_room=40)
    made.append(env)
    obs, _ = env.reset(seed=0)
    assert env.action_space.shape == (2,) and "goal" in obs and "goal_place" not in obs
