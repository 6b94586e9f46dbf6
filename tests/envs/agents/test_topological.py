import math

import numpy as np
import pytest

from envs.agents.topological import TopologicalPlanner, steer
from envs.world.robot import MAX_RANGE, N_RANGES
from placeclust import UNKNOWN, OnlinePlaceClustering
from train.mapping import edge_headings

OPEN = np.full(N_RANGES, MAX_RANGE, np.float32)
EAST = np.array([1.0, 0.0], np.float32)


@pytest.fixture
def planner():
    model = OnlinePlaceClustering("orb")
    model.graph.add_edges_from([(0, 1), (1, 2), (2, 3)])
    p = TopologicalPlanner(model, [(0, 1, 0.0), (1, 2, math.pi / 2), (3, 2, 0.0)])
    p.goal_place = 3
    return p


def test_follows_the_first_edge_of_the_shortest_path(planner):
    assert planner.next_heading(0) == 0.0
    assert planner.next_heading(1) == pytest.approx(math.pi / 2)
    # 2 -> 3 was only driven as 3 -> 2 heading east: go back west
    assert abs(planner.next_heading(2)) == pytest.approx(math.pi)
    assert planner.next_heading(3) is None and planner.next_heading(UNKNOWN) is None


def test_steering_turns_towards_the_target_and_stops_at_walls():
    rng = np.random.default_rng(0)
    forward, turn = steer(EAST, OPEN, 0.0, rng)
    assert forward == pytest.approx(1.0) and turn == pytest.approx(0.0)
    _, turn = steer(EAST, OPEN, math.pi / 4, rng)
    assert turn > 0  # target to the left: turn counter-clockwise
    wall = OPEN.copy()
    wall[[0, 1, -1]] = 0.3
    forward, _ = steer(EAST, wall, 0.0, rng)
    assert forward == pytest.approx(0.0, abs=1e-6)  # float32 ranges: NumPy 1 and 2 round apart


def test_edge_headings_average_the_heading_before_each_transition():
    places = np.array([0, 0, 0, 1, 1, -1, 2, 2, 1])
    headings = np.array([0.1, 0.1, 0.1, 0.5, 0.5, 0.5, -0.3, -0.3, -0.3])
    edges = {(a, b): h for a, b, h in edge_headings(places, headings, window=2)}
    assert set(edges) == {(0, 1), (1, 2), (2, 1)}
    assert edges[(0, 1)] == pytest.approx(0.1)
    assert edges[(2, 1)] == pytest.approx(-0.3)
