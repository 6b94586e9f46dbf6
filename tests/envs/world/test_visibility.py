import numpy as np
import pytest

from envs.world.layout import generate_floor_plan
from envs.world.visibility import own_room_share, rooms_in_view


@pytest.fixture(scope="module")
def plan():
    return generate_floor_plan(3, np.random.default_rng(4))


def _facing(point, target):
    return float(np.arctan2(target[1] - point[1], target[0] - point[0]))


def test_a_camera_looking_through_a_door_sees_the_next_room(plan):
    door = plan.doors[0]
    a, b = (plan.rooms[i] for i in door.rooms)
    near, far = door.approach(a, 0.5), door.approach(a, 2.5)
    poses = np.array([[*p, _facing(p, (door.x, door.y))] for p in (near, far)])
    seen = rooms_in_view(plan, poses)
    assert seen[0, len(seen[0]) // 2] == b.id
    assert a.id not in seen[0]  # 0.5 m from a 1 m door: it fills the 70° view
    assert seen[1, len(seen[1]) // 2] == b.id and a.id in seen[1]  # the door in its wall


def test_a_camera_facing_away_from_the_door_sees_its_own_room(plan):
    door = plan.doors[0]
    a = plan.rooms[door.rooms[0]]
    x, y = door.approach(a, 0.7)
    away = _facing((door.x, door.y), (x, y))
    share = own_room_share(plan, np.array([[x, y, away]]), np.array([a.id]), fov_deg=40.0)
    assert share[0] == 1.0


def test_bad_poses_are_refused(plan):
    with pytest.raises(ValueError, match=r"\(T, 3\)"):
        rooms_in_view(plan, np.zeros((4, 2)))
    with pytest.raises(ValueError, match="finite"):
        rooms_in_view(plan, np.array([[0.0, np.nan, 0.0]]))
    with pytest.raises(ValueError, match="fov_deg"):
        rooms_in_view(plan, np.zeros((1, 3)), fov_deg=180.0)
