"""Doors: a world option that leaves buildings without doors as they were."""

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401 - registers PlaceNav-v0
from envs.world.doors import HEAD, OPEN_RADIUS, WIDTHS, hang_doors
from envs.world.layout import DOOR_WIDTH, generate_floor_plan


def _plan(seed=3, rooms=6):
    return generate_floor_plan(rooms, np.random.default_rng(seed))


def test_doors_keep_the_building_and_narrow_its_doorways():
    plan = _plan()
    doored = hang_doors(plan, 0.5, scene_seed=3)
    assert doored.rooms == plan.rooms and doored.furniture == plan.furniture
    assert [(d.x, d.y, d.rooms) for d in doored.doors] == [(d.x, d.y, d.rooms) for d in plan.doors]
    assert all(WIDTHS[0] <= d.width <= WIDTHS[1] for d in doored.doors)
    assert 0 < sum(d.leaf for d in doored.doors) < len(doored.doors)
    # the walls beside each doorway grow by what the doorway lost
    grown = sum(w.length for w in doored.walls) - sum(w.length for w in plan.walls)
    assert grown == pytest.approx(sum(DOOR_WIDTH - d.width for d in doored.doors))
    assert hang_doors(plan, 0.5, scene_seed=3) == doored  # its own seeded stream
    assert not any(d.leaf for d in hang_doors(plan, 0.0, scene_seed=3).doors)
    with pytest.raises(ValueError, match="fraction in"):
        hang_doors(plan, 1.5, scene_seed=3)


def _leaf_height(env, i):
    return env.data.mocap_pos[env.model.body(f"door{i}").mocapid[0]][2]


def test_a_door_is_shut_until_the_robot_comes_near():
    env = gym.make("PlaceNav-v0", scene_seed=1000, n_rooms=4, doors=1.0, panorama=False)
    nav = env.unwrapped
    door = nav.plan.doors[0]
    room = nav.plan.rooms[door.rooms[0]]
    far = room.center
    assert np.hypot(far[0] - door.x, far[1] - door.y) > OPEN_RADIUS
    nav.reset(options={"pose": (*far, 0.0)})
    assert _leaf_height(nav, 0) == pytest.approx(HEAD / 2)
    near = door.approach(room, OPEN_RADIUS / 2)
    nav.reset(options={"pose": (*near, 0.0)})
    assert _leaf_height(nav, 0) < 0  # out of the way: under the floor
    assert "doors=1.0" in nav.world_id
    env.close()


def test_a_shut_door_is_seen_and_felt():
    """The rangefinder that looks through a doorway from 1.6 m sees the leaf when it is shut."""
    env = gym.make("PlaceNav-v0", scene_seed=1000, n_rooms=4, doors=1.0, panorama=False)
    nav = env.unwrapped
    door = nav.plan.doors[0]
    room = nav.plan.rooms[door.rooms[0]]
    x, y = door.approach(room, 1.6)
    heading = float(np.arctan2(door.y - y, door.x - x))
    obs, _ = nav.reset(options={"pose": (x, y, heading)})
    assert obs["ranges"][0] < 1.6  # ray 0 looks ahead: the leaf, less the robot's radius
    open_env = gym.make("PlaceNav-v0", scene_seed=1000, n_rooms=4, panorama=False).unwrapped
    obs, _ = open_env.reset(options={"pose": (x, y, heading)})
    assert obs["ranges"][0] > 2.0  # through the open doorway
    env.close()
    open_env.close()


def test_the_tour_drives_through_doors():
    from envs.tasks.tour import record_tour

    rooms = {}
    for doors in (None, 1.0):
        tour, plan = record_tour(1000, 4, 400, 0, 64, 16, progress=False, doors=doors)
        rooms[doors] = set(tour.room.tolist())
    assert rooms[1.0] == rooms[None] and len(rooms[None]) >= 3
