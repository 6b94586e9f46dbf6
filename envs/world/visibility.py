"""Which rooms a forward camera sees: rays cast over the floor plan, walls only.

A frame's ground truth is the room the robot stands in, but through an open doorway a forward
camera can see mostly the next room. :func:`rooms_in_view` tells, for every pose of a tour, the
room whose wall each of ``n_rays`` rays across the field of view hits first, so a benchmark can
say how many frames look mostly into another room (``placeclust seed001``).

Rays are cast in the plane of the floor plan against the walls' centre lines (doorways are gaps
in them). Furniture is left out: it is lower than the walls, and the walls behind it stay in view
above it.
"""

from __future__ import annotations

import numpy as np

from .layout import WALL_THICKNESS, FloorPlan


def _segments(plan: FloorPlan) -> tuple[np.ndarray, np.ndarray]:
    """Walls split by axis: rows ``(x, y_lo, y_hi)`` of vertical walls and ``(y, x_lo, x_hi)``."""
    vertical = [(w.x0, min(w.y0, w.y1), max(w.y0, w.y1)) for w in plan.walls if w.axis == "y"]
    horizontal = [(w.y0, min(w.x0, w.x1), max(w.x0, w.x1)) for w in plan.walls if w.axis == "x"]
    return np.array(vertical, float).reshape(-1, 3), np.array(horizontal, float).reshape(-1, 3)


def _first_hit(origin: np.ndarray, direction: np.ndarray, fixed: np.ndarray, lo: np.ndarray,
               hi: np.ndarray) -> np.ndarray:
    """Distance along each ray to the nearest of the segments ``coord = fixed`` in [lo, hi].

    ``origin`` and ``direction`` are (N, 2) in (along, across) order for this axis.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (fixed[None, :] - origin[:, :1]) / direction[:, :1]
    across = origin[:, 1:] + t * direction[:, 1:]
    hit = (t > 1e-9) & (across >= lo[None, :]) & (across <= hi[None, :])
    return np.where(hit, t, np.inf).min(axis=1, initial=np.inf)


def rooms_in_view(plan: FloorPlan, poses: np.ndarray, fov_deg: float = 70.0, n_rays: int = 33
                  ) -> np.ndarray:
    """The room seen along each of ``n_rays`` rays spread over the horizontal field of view.

    Args:
        plan: the building.
        poses: (T, 3) robot poses ``(x, y, heading)``, heading in radians.
        fov_deg: the camera's horizontal field of view, degrees.
        n_rays: rays per pose, spread evenly from the left edge of the view to the right.

    Returns:
        (T, n_rays) int: the room on the near side of the first wall each ray hits, -1 where
        it leaves the building.

    Raises:
        ValueError: ``poses`` is not (T, 3) and finite, or ``fov_deg`` is outside (0, 180).

    Examples:
        >>> import numpy as np
        >>> from envs.world.layout import generate_floor_plan
        >>> from envs.world.visibility import rooms_in_view
        >>> plan = generate_floor_plan(2, np.random.default_rng(0))
        >>> room = plan.rooms[0]
        >>> seen = rooms_in_view(plan, np.array([[*room.center, 0.0]]), n_rays=5)
        >>> seen.shape, int((seen == room.id).sum()) >= 1
        ((1, 5), True)
    """
    poses = np.asarray(poses, float)
    if poses.ndim != 2 or poses.shape[1] != 3 or not np.isfinite(poses).all():
        raise ValueError(f"poses must be a finite (T, 3) array of (x, y, heading), "
                         f"got shape {poses.shape}")
    if not 0 < fov_deg < 180:
        raise ValueError(f"fov_deg must be in (0, 180), got {fov_deg}")
    half = np.radians(fov_deg) / 2
    angles = poses[:, 2:3] + np.linspace(half, -half, n_rays)[None, :]  # left to right
    origin = np.repeat(poses[:, :2], n_rays, axis=0)
    direction = np.stack([np.cos(angles).ravel(), np.sin(angles).ravel()], axis=1)
    vertical, horizontal = _segments(plan)
    t = np.minimum(
        _first_hit(origin, direction, *vertical.T),
        _first_hit(origin[:, ::-1], direction[:, ::-1], *horizontal.T),
    )
    # step back from the wall's centre line into the room the ray is in
    hit = np.isfinite(t)
    t = np.where(hit, np.maximum(t - WALL_THICKNESS, 0.0), 0.0)
    points = origin + direction * t[:, None]
    seen = np.array([plan.room_at(x, y) for x, y in points])
    seen[~hit] = -1
    return seen.reshape(len(poses), n_rays)


def own_room_share(plan: FloorPlan, poses: np.ndarray, rooms: np.ndarray, fov_deg: float = 70.0,
                   n_rays: int = 33) -> np.ndarray:
    """The share of the view, per pose, taken by the room the robot stands in.

    Args:
        plan, poses, fov_deg, n_rays: as for :func:`rooms_in_view`.
        rooms: (T,) the room of each pose (a tour's ``room``).

    Returns:
        (T,) floats in [0, 1]; below 0.5 the frame looks mostly into another room.
    """
    seen = rooms_in_view(plan, poses, fov_deg, n_rays)
    return (seen == np.asarray(rooms)[:, None]).mean(axis=1)
