"""Windows and lamps: light that falls where it would, the same fixtures under every light."""

import numpy as np
import pytest

import envs  # noqa: F401 - registers PlaceNav-v0
from envs.world.layout import generate_floor_plan
from envs.world.local_light import (
    LAMP_HEIGHT,
    NIGHT_FLOOR,
    Fixtures,
    Window,
    gain,
    place_fixtures,
    window_view,
)
from envs.world.scene import build_scene

UP = np.array([0.0, 0.0, 1.0])


def test_windows_hang_only_on_exterior_walls_and_fixtures_follow_the_seed():
    plan = generate_floor_plan(6, np.random.default_rng(4))
    fixtures = place_fixtures(plan, 4, posters={})
    assert fixtures == place_fixtures(plan, 4, posters={})
    assert fixtures.windows and {r for *_, r in fixtures.lamps} == {r.id for r in plan.rooms}
    for w in fixtures.windows:
        room = plan.rooms[w.room]
        # on the room's boundary, which is the building's: no room lies beyond it
        beyond = (w.x - 0.3 * w.normal[0], w.y - 0.3 * w.normal[1])
        assert plan.room_at(*beyond) < 0
        assert room.x0 - 0.1 <= w.x <= room.x1 + 0.1 and room.y0 - 0.1 <= w.y <= room.y1 + 0.1


def test_a_window_keeps_clear_of_a_poster_on_its_wall():
    plan = generate_floor_plan(4, np.random.default_rng(0))
    free = place_fixtures(plan, 0, posters={})
    w = free.windows[0]
    wall = next(i for i, wl in enumerate(plan.walls)
                if abs((w.x - (wl.x0 + wl.x1) / 2) * w.normal[0]
                       + (w.y - (wl.y0 + wl.y1) / 2) * w.normal[1]) < 0.1
                and w.room in wl.sides and -1 in wl.sides)
    side = plan.walls[wall].sides.index(w.room)
    blocked = place_fixtures(plan, 0, posters={f"poster{wall}_{side}_0": (w.x, w.y, 0.3)})
    assert all(abs(o.x - w.x) + abs(o.y - w.y) > 0.5 for o in blocked.windows
               if o.room == w.room)


def test_at_night_a_lamp_lights_the_floor_under_it_and_leaves_corners_dark():
    plan = generate_floor_plan(4, np.random.default_rng(0))
    room = plan.rooms[0]
    lamp = (*room.center, room.id)
    fixtures = Fixtures((), (lamp,))
    under = np.array([[*room.center, 0.0]])
    corner = np.array([[room.x0 + 0.05, room.y0 + 0.05, 0.0]])
    assert gain(under, UP, room.id, fixtures, "night")[0] > 1.0
    assert gain(corner, UP, room.id, fixtures, "night")[0] == pytest.approx(NIGHT_FLOOR)
    # another room's lamp lights nothing here
    assert gain(under, UP, 1, fixtures, "night")[0] == pytest.approx(NIGHT_FLOOR)
    # a wall right beside a lamp is brightest near the cone's edge: the scallop
    wall_points = np.array([[room.center[0] + 0.4, room.center[1], z] for z in (0.3, 1.5)])
    lit = gain(wall_points, np.array([-1.0, 0.0, 0.0]), room.id, fixtures, "night")
    assert lit[1] > lit[0] > NIGHT_FLOOR and LAMP_HEIGHT > 1.5


def test_the_day_sun_patches_the_floor_through_a_window_and_cloud_does_not():
    from envs.world.conditions import LIGHTS

    # the window's wall faces the sun: its normal into the room points the way the light goes
    sun = np.asarray(LIGHTS["day"]["sun"][0][0], float)
    normal = (float(np.sign(sun[0])), 0.0)
    window = Window(0, 0.0, 0.0, (0.0, 1.0), normal, 0.5, 0.85, 2.0, 0)
    fixtures = Fixtures((window,), ())
    # where the ray from the window's centre meets the floor
    to_sun = -sun / np.linalg.norm(sun)
    centre = np.array([0.0, 0.0, 1.4])
    patch = centre - to_sun * (centre[2] / to_sun[2])
    elsewhere = patch + [0.0, 2.0, 0.0]
    day = gain(np.array([patch, elsewhere]), UP, 0, fixtures, "day")
    cloudy = gain(np.array([patch, elsewhere]), UP, 0, fixtures, "cloudy")
    assert day[0] > day[1] + 0.5
    assert cloudy[0] < cloudy[1] + 0.3


def test_a_window_shows_one_skyline_bright_by_day_and_dark_at_night():
    day, cloudy, night = (window_view(7, light) for light in ("day", "cloudy", "night"))
    assert day.mean() > cloudy.std() and night.mean() < 0.3 * day.mean()
    assert day.std() > cloudy.std()  # cloud flattens the view
    np.testing.assert_array_equal(day, window_view(7, "day"))


def test_a_lit_building_is_the_same_building_with_windows():
    plain = build_scene(1000, 4, "night")
    lit = build_scene(1000, 4, "night", local_light=True)
    assert plain.plan == lit.plan
    added = set(lit.geom_rooms) - set(plain.geom_rooms)
    assert added and all(name.startswith("window") for name in added)
    assert lit.model.nbody == plain.model.nbody


def test_night_changes_a_lit_building_more_than_a_plain_one(make_env):
    """SIFT matches between day and night panoramas at the same poses: in a plain building
    only the level changes, and SIFT's normalized descriptors shrug it off; with windows and
    lamps, which parts are lit changes, and the matches go (issue 53's "conditions that
    bite")."""
    import cv2

    sift, matcher = cv2.SIFT_create(), cv2.BFMatcher()

    def descriptors(frame):
        return sift.detectAndCompute(cv2.cvtColor(frame, cv2.COLOR_RGB2GRAY), None)[1]

    def kept(**world):  # the share of day's self-matches that night keeps
        frames = {}
        for light in ("day", "night"):
            env = make_env(scene_seed=1001, n_rooms=4, lighting=light, **world).unwrapped
            poses = [(*room.center, 0.3) for room in env.plan.rooms]
            frames[light] = [env.reset(seed=0, options={"pose": p})[0]["panorama"]
                             for p in poses]
        good = {"day": 0, "night": 0}
        for day, other in zip(frames["day"], frames["night"]):
            for light, frame in (("day", day), ("night", other)):
                d = descriptors(frame)
                pairs = [] if d is None else matcher.knnMatch(descriptors(day), d, k=2)
                good[light] += sum(1 for p in pairs
                                   if len(p) == 2 and p[0].distance < 0.75 * p[1].distance)
        return good["night"] / good["day"]

    plain, lit = kept(), kept(local_light=True)
    assert plain > 0.25 and lit < 0.5 * plain
