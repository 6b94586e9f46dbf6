"""What the tasks share: the walk to a goal room, its shaped reward and success, and the
recognizer names of the closed loop."""

import math

import numpy as np
import pytest

from envs.tasks.goals import GoalRoom
from envs.tasks.oracles import TrueRooms
from envs.tasks.recognizers import check_recognizer_name, make_recognizer
from envs.world.layout import generate_floor_plan


@pytest.fixture
def plan():
    return generate_floor_plan(4, np.random.default_rng(3))


def test_walking_towards_the_goal_pays_its_metres_and_entering_it_succeeds(plan):
    goal = GoalRoom(plan, success_reward=10.0, step_cost=0.01, shaping=1.0)
    start = plan.rooms[1].center
    far = goal.start(0, start)
    door = next(d for d in plan.doors if 1 in d.rooms)
    reward, success = goal.step((door.x, door.y), 1)
    assert not success and reward == pytest.approx(far - goal.distance - 0.01)
    reward, success = goal.step(plan.rooms[0].center, 0)
    assert success and goal.distance == 0.0 and reward >= 10.0 - 0.01


def test_outside_every_room_the_last_distance_stands(plan):
    goal = GoalRoom(plan)
    d = goal.start(0, plan.rooms[1].center)
    x0, y0, _, _ = plan.bounds
    reward, success = goal.step((x0 - 5.0, y0 - 5.0), -1)
    assert math.isfinite(goal.distance) and goal.distance == d and not success
    assert reward == pytest.approx(-goal.step_cost)


def test_a_room_named_for_the_distance_is_where_it_is_measured_from(plan):
    goal = GoalRoom(plan)
    door = next(d for d in plan.doors if 1 in d.rooms and 0 not in d.rooms)
    here = goal.start(0, (door.x, door.y), room=1)
    assert here == goal.distance_from(door.x, door.y, room=1) > 0.0


def test_the_closed_loops_recognizers_have_one_name_each():
    with pytest.raises(ValueError, match="'online' was renamed 'panorama'"):
        check_recognizer_name("online")
    with pytest.raises(ValueError, match="unknown recognizer 'psychic'"):
        make_recognizer("psychic", n_rooms=4)
    assert make_recognizer("oracle", n_rooms=4) == TrueRooms()  # the env binds it to a building
    panorama = make_recognizer("panorama", n_rooms=4)
    assert panorama.features == "sift" and panorama.scene_change == 0.25
