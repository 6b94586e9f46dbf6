"""A second lap: a recorded drive's route driven again, a little to one side.

Real place-recognition sequences are two traversals of one route: the corridor data set's
reference and query drives, RTAB-Map's loop driven twice round. A scripted tour's second half
is not that: it revisits the rooms along other paths, so only the stretches where its path
crosses the first half's give a query a reference. :func:`drive_lap` repeats a recorded
drive instead, as a driver would: the same path, sampled every ``spacing`` metres into
waypoints, each pushed sideways by a smooth random offset (at most ``offset`` metres, where
the floor is free), followed by the tour's own controller
(:class:`~envs.tasks.tour.WaypointController`) from the drive's first pose. The robot never
retraces a pose exactly, so a query is near its references, not on them.

Examples:
    >>> import gymnasium as gym
    >>> import envs  # registers PlaceNav-v0
    >>> from envs.agents.lap import drive_lap
    >>> from envs.tasks.tour import drive_tour
    >>> env = gym.make("PlaceNav-v0", scene_seed=0, n_rooms=2, camera="forward",
    ...                image_width=32, image_height=24, max_episode_steps=None)
    >>> first = drive_tour(env, 60)
    >>> lap = drive_lap(env, first.pose, max_steps=120)
    >>> len(lap.pose) > 30, bool(abs(lap.pose[0] - first.pose[0]).max() < 0.5)
    (True, True)
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

from ..tasks.tour import Tour, WaypointController, building
from ..world.layout import FloorPlan

#: metres of path between two of the lap's waypoints
WAYPOINT_SPACING = 0.5
#: the largest sideways offset of the lap from the recorded path, metres: a driver repeating
#: a corridor route keeps to within a robot's width of it
MAX_OFFSET = 0.3
#: clearance a shifted waypoint must keep from walls and furniture, metres (the tour's)
CLEARANCE = 0.3


def lap_waypoints(plan: FloorPlan, poses: np.ndarray, rng: np.random.Generator,
                  spacing: float = WAYPOINT_SPACING, offset: float = MAX_OFFSET) -> list[tuple]:
    """``(x, y, tolerance)`` waypoints along the path of ``poses`` (``(T, 3)``: x, y,
    heading), one every ``spacing`` metres of it, each shifted across the path by a smoothly
    wandering offset within ``±offset`` (a shift that would leave the free floor is not
    made, as in doorways)."""
    xy = np.asarray(poses, float)[:, :2]
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    keep = np.searchsorted(along, np.arange(spacing, along[-1] + 1e-9, spacing))
    shift, points = 0.0, []
    for i in keep:
        j = min(i + 1, len(xy) - 1)
        dx, dy = xy[j] - xy[max(i - 1, 0)]
        norm = math.hypot(dx, dy) or 1.0
        shift = float(np.clip(shift + rng.normal(0.0, offset / 3), -offset, offset))
        x, y = xy[i] + shift * np.array([-dy, dx]) / norm
        if not plan.is_free(x, y, CLEARANCE):
            x, y = xy[i]
        points.append((float(x), float(y), 0.25))
    return points


def drive_lap(env: gym.Env, poses: np.ndarray, max_steps: int, seed: int = 1,
              spacing: float = WAYPOINT_SPACING, offset: float = MAX_OFFSET) -> Tour:
    """Drive the path of ``poses`` (a recorded drive of ``env``'s building) once more and
    record it: reset at its first pose, then the waypoints of :func:`lap_waypoints` until the
    last is reached or ``max_steps`` frames are recorded.

    Args:
        env: a ``PlaceNav-v0`` (wrapped or not): its lighting and appearance changes are the
            lap's own, so a lap can be another day's drive.
        poses: ``(T, 3)`` poses of the drive to repeat, in order.
        max_steps: the most frames recorded (the first is the reset's).
        seed: the reset's seed and the offsets' draw.
        spacing, offset: as :func:`lap_waypoints`.

    Returns:
        The lap's :class:`~envs.tasks.tour.Tour`, frame ``t`` after ``t`` steps.
    """
    if max_steps < 1:
        raise ValueError(f"max_steps must be a positive number of frames, got {max_steps}")
    poses = np.asarray(poses, float)
    rng = np.random.default_rng(seed)
    controller = WaypointController(lap_waypoints(building(env).plan, poses, rng, spacing,
                                                  offset))
    obs, info = env.reset(seed=seed, options={"pose": tuple(poses[0])})
    key = building(env).image_key
    frames, rooms, path = [], [], []
    for t in range(max_steps):
        frames.append(obs[key])
        rooms.append(info["room_id"])
        path.append(info["pose"])
        if controller.done or t == max_steps - 1:
            break
        obs, _, _, _, info = env.step(controller.action(info["pose"]).astype(np.float32))
    return Tour(np.stack(frames), np.array(rooms, np.int64), np.array(path),
                [r.name for r in building(env).plan.rooms])
