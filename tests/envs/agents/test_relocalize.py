import math

import gymnasium as gym
import numpy as np
import pytest

from envs.agents.relocalize import RESIDUAL, RelocalizingPlanner, ScanMap, endpoints
from envs.agents.teach_repeat import TourPlanner
from envs.world.robot import MAX_RANGE, N_RANGES, RADIUS

# an L-shaped room: a 6 x 4 m box with a 2 x 1.5 m block in one corner, so no two spots alike
BOXES = [((0.0, 0.0), (6.0, 4.0))]
BLOCK = ((4.0, 2.5), (6.0, 4.0))


def _scan(x, y, yaw):
    """What the ring reads at (x, y, yaw) in the room: rays cast against its walls."""
    out = np.full(N_RANGES, MAX_RANGE)
    for k in range(N_RANGES):
        a = yaw + 2 * math.pi * k / N_RANGES
        dx, dy = math.cos(a), math.sin(a)
        hits = []
        (x0, y0), (x1, y1) = BOXES[0]
        for wall, d in ((x0, dx), (x1, dx)):
            if abs(d) > 1e-9 and (t := (wall - x) / d) > 0:
                hits.append(t)
        for wall, d in ((y0, dy), (y1, dy)):
            if abs(d) > 1e-9 and (t := (wall - y) / d) > 0:
                hits.append(t)
        (bx0, by0), (bx1, by1) = BLOCK
        for t in np.linspace(0, 8, 1601)[1:]:  # the block, by marching
            px, py = x + t * dx, y + t * dy
            if bx0 <= px <= bx1 and by0 <= py <= by1:
                hits.append(t)
                break
        r = min(hits) - RADIUS
        out[k] = r if r < MAX_RANGE else MAX_RANGE
    return out


@pytest.fixture(scope="module")
def room():
    # the tour: a loop through the room's free part, heading along the way
    t = np.linspace(0, 2 * math.pi, 120, endpoint=False)
    path = np.stack([2.5 + 1.6 * np.cos(t), 1.8 + 1.1 * np.sin(t)], axis=1)
    yaw = t + math.pi / 2
    ranges = np.array([_scan(x, y, a) for (x, y), a in zip(path, yaw)])
    return ScanMap(path, yaw, ranges)


def test_endpoints_are_where_the_beams_hit():
    ends = endpoints(np.array([1.0, 1.0]), 0.0, np.full(N_RANGES, 0.8))
    assert ends.shape == (N_RANGES, 2)
    assert np.allclose(ends[0], [1.0 + 0.8 + RADIUS, 1.0])  # beam 0 looks ahead
    assert np.isnan(endpoints(np.zeros(2), 0.0, np.full(N_RANGES, MAX_RANGE))).all()


@pytest.mark.parametrize("x, y, yaw", [(1.0, 1.0, 0.3), (4.5, 1.2, -2.0), (1.5, 3.2, 1.0)])
def test_a_scan_fits_where_it_was_taken_and_is_found_there(room, x, y, yaw):
    scan = _scan(x, y, yaw)
    assert room.residual(np.array([x, y]), yaw, scan) < 0.06
    assert room.residual(np.array([x + 1.0, y]), yaw, scan) > 0.1
    position, fit = room.locate(yaw, scan, np.arange(len(room.path)))
    assert np.linalg.norm(position - [x, y]) < 0.15 and fit < 0.06


@pytest.mark.parametrize("x, y, yaw", [(1.0, 1.0, 0.3), (4.5, 1.2, -2.0), (5.5, 3.5, 2.5)])
def test_the_pruned_search_gives_every_positions_answer(room, x, y, yaw):
    # a grid over the room and beyond it, scans taken in and out of the room (beams that hit
    # nothing: the costly ones), and ties (a grid with repeated positions): the index and the
    # value are those of the plain argmin over every position's every beam
    grid = np.stack(np.meshgrid(np.arange(-1, 7, 0.2), np.arange(-1, 5, 0.2)), -1).reshape(-1, 2)
    grid = np.concatenate([grid, grid[::7]])
    for scan in (_scan(x, y, yaw), np.minimum(_scan(x, y, yaw) + 1.5, MAX_RANGE)):
        fit = room.misfits(grid, yaw, scan).mean(axis=1)
        k, value = room.best_fit(grid, yaw, scan)
        assert (k, value) == (int(np.argmin(fit)), float(fit.min()))
    k, value = room.best_fit(grid, yaw, np.full(N_RANGES, MAX_RANGE))  # nothing hit: no fit
    assert k == 0 and value == math.inf


def test_a_wall_the_robot_stands_at_gives_it_away(room):
    scan = _scan(0.5, 2.0, math.pi)  # facing the west wall, 0.5 m from it
    assert room.near_misfit(np.array([0.5, 2.0]), math.pi, scan) < 0.1
    assert room.near_misfit(np.array([2.5, 2.0]), math.pi, scan) > 0.3


def _errands(make_planner, start):
    env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", scene_seed=1003, n_rooms=4,
                   n_errands=4, tour_steps_per_room=100, errand_start=start)
    try:
        obs, info = env.reset(seed=0)
        planner = make_planner(unknown=env.unwrapped.max_places)
        planner.reset(info["tour"], obs)
        done = False
        while not done:
            obs, _, done, _, info = env.step(planner.act(obs))
    finally:
        env.close()
    return [e["success"] for e in info["errands"]]


def test_the_kidnapped_robot_finds_its_way_where_the_plain_planner_is_lost():
    assert all(_errands(RelocalizingPlanner, "carried"))
    assert not all(_errands(TourPlanner, "carried"))


def test_errands_continued_from_the_tour_still_succeed():
    assert all(_errands(RelocalizingPlanner, "continue"))


def test_a_small_correction_keeps_the_route_and_a_large_one_replans():
    env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", scene_seed=1003, n_rooms=4,
                   n_errands=2, tour_steps_per_room=100)
    try:
        obs, info = env.reset(seed=0)
        planner = RelocalizingPlanner(unknown=env.unwrapped.max_places)
        planner.reset(info["tour"], obs)
        for _ in range(200):  # under way, with a route, where the scan fits the tour's well
            obs, *_ = env.step(planner.act(obs))
            ranges = np.asarray(obs["ranges"], float)
            if planner._hop and planner.scans.residual(planner.pos, planner.yaw,
                                                       ranges) < RESIDUAL / 2:
                break
        truth, hop = planner.pos.copy(), planner._hop
        assert hop is not None
        # drift under a metre, enough that the scan misfits there
        drift = next(d for d in ([0.5, 0], [0, 0.5], [0.7, 0.3], [-0.5, 0.5], [0.8, 0])
                     if planner.scans.residual(truth + d, planner.yaw, ranges) > RESIDUAL)
        planner.pos = truth + drift
        for _ in range(4):
            planner._check_pose(obs)
        assert np.linalg.norm(planner.pos - truth) < 0.15  # mended
        assert planner._hop == hop and planner.relocalized == 0  # the route stands
        planner.pos = truth + [3.0, 3.0]  # far off: a new start
        for _ in range(4):
            planner._check_pose(obs)
        assert np.linalg.norm(planner.pos - truth) < 0.15 and planner.relocalized == 1
    finally:
        env.close()
