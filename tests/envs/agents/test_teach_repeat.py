import math
from collections import deque

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401
from envs.agents.teach_repeat import TourPlanner, dead_reckon, guard
from envs.runs.tour_errands import run_scene
from envs.tasks.records import TourRecord
from envs.world.robot import MAX_RANGE, N_RANGES

SMALL = {"n_rooms": 3, "tour_steps_per_room": 40}


def test_dead_reckoning_integrates_speed_along_the_compass():
    heading = np.array([[1.0, 0.0]] * 11 + [[0.0, 1.0]] * 10, np.float32)
    odometry = np.array([[0.5, 0.0]] * 21, np.float32)
    path = dead_reckon(odometry, heading, 0.1)
    assert path[0] == pytest.approx([0.0, 0.0])
    assert path[10] == pytest.approx([0.5, 0.0])  # 10 steps east at 0.5 m/s
    turn = 0.05 * math.cos(math.pi / 4)  # the step that turns goes at the mean heading
    assert path[-1] == pytest.approx([0.5 + turn, turn + 0.45], abs=1e-6)  # then north


def test_guard_stops_the_robot_short_of_a_wall_but_lets_it_turn():
    ranges = np.full(N_RANGES, MAX_RANGE, np.float32)
    assert guard(np.array([0.8, 0.3]), ranges) == pytest.approx([0.8, 0.3])
    ranges[0] = 0.1
    assert guard(np.array([0.8, 0.3]), ranges) == pytest.approx([0.0, 0.3])
    assert guard(np.array([-0.5, 0.0]), ranges)[0] == pytest.approx(-0.5)  # free behind


def test_the_planner_runs_errands_on_true_rooms():
    row = run_scene(3, recognizer="oracle", n_errands=3, seed=0, **SMALL)
    assert row["success_rate"] == 1.0 and row["precision"] == 1.0
    assert 0.3 < row["spl"] <= 1.0


def test_without_place_ids_the_planner_explores():
    """Fault caught: a planner that stands still (or turns on the spot) when no place is
    known; it must set off and cover ground, its actions within the action space."""
    env = gym.make("PlaceNav-GuidedTour-v1", recognizer="none", n_errands=1, errand_steps=60,
                   panorama_width=64, panorama_height=16, **SMALL)
    try:
        obs, info = env.reset(seed=0)
        nav = env.unwrapped.nav
        start = nav.robot.pose(nav.data)[:2].copy()
        planner = TourPlanner(unknown=env.unwrapped.max_places)
        planner.reset(info["tour"], obs)
        assert planner.names == {n: -1 for n in info["named"]}  # names attach to nothing
        farthest, done = 0.0, False
        while not done:
            action = planner.act(obs)
            assert action in env.action_space
            assert planner.exploring
            obs, _, done, _, info = env.step(action)
            farthest = max(farthest, float(np.linalg.norm(nav.robot.pose(nav.data)[:2] - start)))
    finally:
        env.close()
    assert farthest > 0.5  # 60 steps of 0.1 s: moving, not standing or spinning in place


def test_a_hop_replays_the_tour_where_it_crossed():
    env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_errands=1, **SMALL)
    try:
        obs, info = env.reset(seed=2)
    finally:
        env.close()
    planner = TourPlanner(unknown=64)
    planner.reset(info["tour"], obs)
    places = info["tour"].place_id
    a, b = int(places[0]), int(places[places != places[0]][0])  # the tour's first crossing
    assert planner.graph.has_edge(a, b) and (a, b) in planner.stretches
    t = int(np.argmax(places == b))
    stretch = planner.stretches[(a, b)][0]  # tour steps, in driving order
    assert t - 1 in stretch and t in stretch and np.all(np.diff(stretch) == 1)
    back = planner.stretches[(b, a)][0]  # the same crossing, driven the other way
    assert t - 1 in back and t in back and np.all(np.diff(back) == -1)


def _u_tour() -> TourRecord:
    """2 m east and 2 m back west, 3 m apart: place 0 on both legs, place 1 on the 3 m north
    between them, so place 0's own steps do not join its two legs."""
    heading = np.array([[1.0, 0.0]] * 20 + [[0.0, 1.0]] * 30 + [[-1.0, 0.0]] * 20, np.float32)
    places = np.array([0] * 20 + [1] * 30 + [0] * 20)
    heard = np.array([""] * 70, dtype=object)
    heard[5], heard[35] = "east", "north"
    return TourRecord(places, heard, np.tile(np.float32([0.5, 0.0]), (70, 1)), heading, 0.2)


def _obs(place: int, goal: str) -> dict:
    return {"place_id": np.int64(place), "goal": goal, "heading": np.float32([-1.0, 0.0]),
            "odometry": np.zeros(2, np.float32), "ranges": np.full(N_RANGES, MAX_RANGE)}


def test_the_approach_keeps_to_the_tour_where_the_place_does_not_lead():
    planner = TourPlanner(unknown=64)
    planner.reset(_u_tour(), _obs(0, ""))  # at the end of the west leg
    way = planner._approach(0, 5)  # to the east leg: along the U, not across the gap
    assert way[0] == 69 and np.all(np.diff(way) < 0)  # the tour's path, driven backwards
    assert (planner.places[way] == 1).any()  # through the north leg
    assert np.linalg.norm(np.diff(planner.path[way], axis=0), axis=1).max() < 1.5


def test_a_planner_that_believes_it_arrived_trusts_the_next_report():
    planner = TourPlanner(unknown=64)
    planner.reset(_u_tour(), _obs(0, ""))
    assert planner.names == {"east": 0, "north": 1}
    planner.act(_obs(0, "east"))  # believed at the goal, yet the errand goes on
    assert planner.exploring
    planner._passed = deque([1])  # a place just left, whose reports are otherwise ignored
    planner.act(_obs(1, "east"))
    assert planner.place == 1 and not planner.exploring  # so it replans from the report
