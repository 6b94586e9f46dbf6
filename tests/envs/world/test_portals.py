"""Portal culling: which rooms a point of the floor plan sees through the doorways."""

import math

import numpy as np
import pytest

from envs.world.layout import DOOR_WIDTH, Door, FloorPlan, Room, Wall
from envs.world.portals import PortalCuller, box_corners


def _three_in_a_row() -> FloorPlan:
    """Rooms 0 | 1 | 2 along x, 4 m each, a door in each shared wall at y = 2; room 3 north of
    room 0 with no door at all."""
    rooms = (Room(0, "a", "kitchen", 0, 0, 4, 4), Room(1, "b", "toilet", 4, 0, 8, 4),
             Room(2, "c", "bathroom", 8, 0, 12, 4), Room(3, "d", "stairs area", 0, 4, 4, 8))
    doors = (Door((0, 1), 4.0, 2.0, "y"), Door((1, 2), 8.0, 2.0, "y"))
    walls = (Wall(4, 0, 4, 1.5, (0, 1)), Wall(4, 2.5, 4, 4, (0, 1)),
             Wall(8, 0, 8, 1.5, (1, 2)), Wall(8, 2.5, 8, 4, (1, 2)), Wall(0, 4, 4, 4, (0, 3)))
    return FloorPlan(rooms, doors, walls)


def _floors(plan: FloorPlan) -> tuple[np.ndarray, np.ndarray]:
    corners = np.array([[(r.x0, r.y0), (r.x1, r.y0), (r.x1, r.y1), (r.x0, r.y1)]
                        for r in plan.rooms], float)
    return corners, np.eye(len(plan.rooms), dtype=bool)


def test_a_point_sees_its_room_and_the_rooms_beyond_its_doors():
    plan = _three_in_a_row()
    culler = PortalCuller(plan, *_floors(plan))
    seen = culler.visible(2.0, 2.0)  # the middle of room 0, in line with both doors
    assert seen.tolist() == [True, True, True, False]  # room 3 has no door to room 0
    arcs = culler.arcs(2.0, 2.0)
    assert arcs[0] == [(0.0, math.pi)]
    mid, half = arcs[1][0]
    assert abs(mid) < 1e-9 and half == pytest.approx(math.atan((DOOR_WIDTH / 2 + 0.05) / 2))


def test_a_room_behind_a_wall_is_culled_when_no_doorway_lines_up():
    plan = _three_in_a_row()
    culler = PortalCuller(plan, *_floors(plan))
    # from the far corner of room 0, the doorway into room 1 is seen at a steep angle and room
    # 2's doorway, 4 m further on, is not in line with it
    arcs = culler.arcs(0.3, 3.7)
    assert 1 in arcs and 2 not in arcs
    assert culler.visible(0.3, 3.7).tolist() == [True, True, False, False]


def test_a_point_in_a_doorway_sees_both_rooms_whole():
    plan = _three_in_a_row()
    culler = PortalCuller(plan, *_floors(plan))
    arcs = culler.arcs(4.0, 2.0)
    assert arcs[0] == arcs[1] == [(0.0, math.pi)]
    assert culler.visible(4.0, 2.0)[:3].all()


def test_outside_the_building_nothing_is_ruled_out():
    plan = _three_in_a_row()
    culler = PortalCuller(plan, *_floors(plan))
    assert culler.arcs(-5.0, -5.0) is None
    assert culler.visible(-5.0, -5.0).all()


def test_geoms_of_no_room_are_always_kept():
    plan = _three_in_a_row()
    corners, rooms = _floors(plan)
    rooms[3] = False  # room 3's floor now belongs to no room
    assert PortalCuller(plan, corners, rooms).visible(0.3, 3.7)[3]


def test_bad_shapes_are_refused():
    plan = _three_in_a_row()
    corners, rooms = _floors(plan)
    with pytest.raises(ValueError, match="corners must be"):
        PortalCuller(plan, corners[:, :, :1], rooms)
    with pytest.raises(ValueError, match="columns for 4 rooms"):
        PortalCuller(plan, corners, rooms[:, :2])


def test_box_corners_of_a_rotated_box_and_a_vertical_plane():
    quarter = np.array([[0, -1, 0, 1, 0, 0, 0, 0, 1]], float)  # 90 degrees about z
    box = box_corners(np.array([[1.0, 2.0, 0.5]]), quarter, np.array([[0.5, 0.1, 0.5]]),
                      np.array([False]))[0]
    assert box.min(axis=0).tolist() == pytest.approx([0.9, 1.5])
    assert box.max(axis=0).tolist() == pytest.approx([1.1, 2.5])
    # a wall lining: a plane whose z (its normal) is horizontal; its extent is along x only
    upright = np.array([[1, 0, 0, 0, 0, -1, 0, 1, 0]], float)
    plane = box_corners(np.array([[0.0, 3.0, 1.1]]), upright, np.array([[2.0, 1.1, 1.0]]),
                        np.array([True]))[0]
    assert plane.min(axis=0).tolist() == pytest.approx([-2.0, 3.0])
    assert plane.max(axis=0).tolist() == pytest.approx([2.0, 3.0])
