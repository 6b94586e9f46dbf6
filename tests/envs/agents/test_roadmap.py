import numpy as np
import pytest

from envs.agents.roadmap import Roadmap


def _there_and_back(gap: float = 0.1) -> np.ndarray:
    """2 m east along y = 0, then back west along y = ``gap`` (41 steps 0.1 m apart)."""
    east = np.stack([np.linspace(0, 2, 21), np.zeros(21)], axis=1)
    back = np.stack([np.linspace(2, 0, 21), np.full(21, gap)], axis=1)
    return np.concatenate([east, back])


def test_every_step_is_a_node_unless_a_spacing_is_asked():
    path = _there_and_back()
    assert len(Roadmap(path)) == len(path)
    sparse = Roadmap(path, spacing=0.25)
    assert sparse.steps[:7].tolist() == list(range(0, 19, 3))  # 0.3 m: first step >= 0.25 m
    assert (np.linalg.norm(np.diff(sparse.nodes, axis=0), axis=1) >= 0.25).all()
    assert sparse.node_of_step(4) == 1 and sparse.node_of_step(41) == len(sparse) - 1


def test_a_join_crosses_between_two_passes_and_nothing_else_does():
    near = Roadmap(_there_and_back(), join=0.15)
    assert near.route(0, 41) == [0, 41]  # step 41 lies 0.1 m from step 0
    # without the join the only way is the path itself, round the far end
    assert Roadmap(_there_and_back(), join=0.05).route(0, 41) == list(range(42))


def test_a_route_kept_within_some_nodes_is_none_where_they_do_not_connect():
    road = Roadmap(_there_and_back(), join=0.05)
    assert road.route(0, 41, within={*range(10), 41}) is None
    assert road.route(0, 5, within=set(range(10))) == [0, 1, 2, 3, 4, 5]


def test_nodes_of_one_place_are_joined_farther_than_the_rest():
    # two passes 0.6 m apart: too far for a join, near enough for one place
    path = _there_and_back(gap=0.6)
    one_place = np.zeros(len(path), int)
    assert Roadmap(path, join=0.15).route(0, 41) == list(range(42))
    road = Roadmap(path, join=0.15, places=one_place, same_place=1.0)
    assert road.route(0, 41) == [0, 41]
    # an unknown place (-1) is not a place: no join through it
    unknown = Roadmap(path, join=0.15, places=-np.ones(len(path), int), same_place=1.0)
    assert unknown.route(0, 41) == list(range(42))


def test_the_way_leads_along_the_map_to_the_goal_and_says_how_far():
    road = Roadmap(_there_and_back(), join=0.05)
    carrot, left = road.way(goal=41, position=np.array([1.0, 0.02]), ahead=0.5)
    # east toward the turn, not 0.1 m across to the goal's pass
    assert carrot == pytest.approx([1.5, 0.0])
    assert left == pytest.approx(0.02 + 1.0 + 0.1 + 2.0, abs=1e-4)
    # at the goal: nowhere further to go
    carrot, left = road.way(goal=41, position=np.array([0.0, 0.1]), ahead=0.5)
    assert carrot == pytest.approx([0.0, 0.1]) and left == pytest.approx(0.0)

