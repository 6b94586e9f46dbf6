import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from envs.world.layout import DOOR_WIDTH, generate_floor_plan


@settings(max_examples=150, deadline=None)
@given(n=st.integers(1, 16), seed=st.integers(0, 10_000), extra=st.floats(0, 1))
def test_plans_are_connected_named_and_walkable(n, seed, extra):
    plan = generate_floor_plan(n, np.random.default_rng(seed), extra_doors=extra)
    assert len(plan.rooms) == n
    assert len({r.name for r in plan.rooms}) == n  # names are unique
    g = plan.graph()
    assert nx.is_connected(g)
    for r in plan.rooms:
        assert plan.room_at(*r.center) == r.id
        assert plan.is_free(*r.center, clearance=0.3)  # furniture keeps the centre clear
    for d in plan.doors:
        a, b = (plan.rooms[i] for i in d.rooms)
        # the door lies on the two rooms' shared wall
        assert plan.room_at(*d.approach(a, 0.5)) == a.id
        assert plan.room_at(*d.approach(b, 0.5)) == b.id
        for f in plan.furniture:  # nothing blocks a doorway
            assert abs(f.x - d.x) > f.hx + DOOR_WIDTH / 2 or abs(f.y - d.y) > f.hy + DOOR_WIDTH / 2


def test_same_seed_same_plan_and_tree_without_extra_doors():
    a = generate_floor_plan(9, np.random.default_rng(3))
    assert a == generate_floor_plan(9, np.random.default_rng(3))
    tree = generate_floor_plan(9, np.random.default_rng(3), extra_doors=0.0)
    assert nx.is_tree(tree.graph())


def test_loops_when_asked_for():
    plan = generate_floor_plan(4, np.random.default_rng(0), extra_doors=1.0)
    assert len(nx.cycle_basis(plan.graph())) >= 1


@pytest.mark.parametrize("n", [0, -1, 33, 2.5])
def test_impossible_layouts_are_refused(n):
    with pytest.raises(ValueError, match="n_rooms"):
        generate_floor_plan(n, np.random.default_rng(0))


def test_unknown_room_name_lists_the_known_ones():
    plan = generate_floor_plan(4, np.random.default_rng(0))
    with pytest.raises(KeyError, match="unknown room 'ballroom'"):
        plan.room_by_name("ballroom")
