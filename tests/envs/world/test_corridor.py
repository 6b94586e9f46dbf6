import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from envs.world.corridor import corridor_floor_plan
from envs.world.layout import CORRIDOR, DOOR_WIDTH


def offset(plan, k):
    """How far office k lies east of office 0."""
    return plan.rooms[k].x0 - plan.rooms[0].x0


@settings(max_examples=60, deadline=None)
@given(n=st.integers(2, 16), seed=st.integers(0, 10_000))
def test_offices_are_copies_of_one_another_along_one_corridor(n, seed):
    plan = corridor_floor_plan(n, np.random.default_rng(seed))
    assert len(plan.rooms) == n and len({r.name for r in plan.rooms}) == n
    corridor = plan.rooms[-1]
    assert corridor.kind == CORRIDOR
    # a star: every office has one door, into the corridor
    assert nx.is_isomorphic(plan.graph(), nx.star_graph(n - 1))
    first = [f for f in plan.furniture if f.room == 0]
    for k, office in enumerate(plan.rooms[:-1]):
        dx = offset(plan, k)
        assert (office.x1 - office.x0, office.y0, office.y1) == (
            plan.rooms[0].x1 - plan.rooms[0].x0, plan.rooms[0].y0, plan.rooms[0].y1)
        (door,) = [d for d in plan.doors if k in d.rooms]
        assert door.x - dx == pytest.approx(plan.doors[0].x) and door.y == corridor.y1
        mine = [f for f in plan.furniture if f.room == k]
        assert [f.kind for f in mine] == [f.kind for f in first]
        np.testing.assert_allclose([(f.x - dx, f.y, f.hx, f.hy, f.height) for f in mine],
                                   [(f.x, f.y, f.hx, f.hy, f.height) for f in first], atol=1e-3)
        assert plan.room_at(*office.center) == k
        assert plan.is_free(*office.center, clearance=0.3)
        assert plan.room_at(*door.approach(office, 0.5)) == k
        assert plan.room_at(*door.approach(corridor, 0.5)) == corridor.id
        for f in plan.furniture:
            assert abs(f.x - door.x) > f.hx + DOOR_WIDTH / 2 or abs(f.y - door.y) > f.hy + 0.5


@pytest.mark.parametrize("n", [0, 1, 33, 2.5])
def test_a_corridor_needs_an_office(n):
    with pytest.raises(ValueError, match="2 to 32 rooms"):
        corridor_floor_plan(n, np.random.default_rng(0))


def test_the_rangefinders_cannot_tell_the_middle_offices_apart(make_task):
    """What the layout is for: the same readings in two offices and before their doors."""
    env = make_task(layout="corridor", n_rooms=5)
    plan = env.unwrapped.plan
    width = offset(plan, 1)
    for x, y, heading in [(1.75, 3.0, 1.6), (1.2, 4.5, -2.0), (1.75, 1.0, 0.3)]:
        seen = []
        for k in (1, 2):
            obs, info = env.reset(options={"pose": (x + k * width, y, heading), "goal": "corridor"
                                           if y > 2 else plan.rooms[0].name})
            seen.append(obs["ranges"])
            assert info["room_id"] == (k if y > 2 else 4)
        np.testing.assert_allclose(seen[0], seen[1], atol=1e-4)
    # ...but the panoramas differ: each room has its own textures and posters
    pano = make_task(layout="corridor", n_rooms=5, panorama=True, panorama_width=128,
                     panorama_height=32)
    a = pano.reset(options={"pose": (1.75 + width, 4.0, 0.0)})[0]["panorama"]
    b = pano.reset(options={"pose": (1.75 + 2 * width, 4.0, 0.0)})[0]["panorama"]
    assert np.abs(a.astype(int) - b.astype(int)).mean() > 10


def test_layout_is_part_of_the_world_fingerprint_and_checked(make_env):
    grid = make_env(n_rooms=5).unwrapped.world_id
    corridor = make_env(n_rooms=5, layout="corridor").unwrapped.world_id
    assert "layout" not in grid  # maps saved before layouts existed still load
    assert corridor == grid + " layout=corridor"
    with pytest.raises(ValueError, match="unknown layout 'maze'"):
        make_env(layout="maze")
