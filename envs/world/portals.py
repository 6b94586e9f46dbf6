"""Which parts of a building a camera can see through its doorways: portal culling.

Rendering cost in Mesa's software rasterizer grows with every geom drawn, visible or not, and a
camera's view frustum keeps the rooms behind a wall. A building of :mod:`envs.world.layout` is a set
of rectangular rooms whose walls are taller than the cameras (:data:`envs.world.scene.WALL_HEIGHT`
against :data:`envs.world.scene.CAMERA_HEIGHT`) and whose contents are no taller than the walls, so
whatever the camera sees lies along a straight line in the floor plan that leaves its room only
through doorways. :class:`PortalCuller` walks those doorways (Luebke and Georges, "Portals and
mirrors", 1995): from the camera's room, each doorway narrows the arc of directions through
which the next room can be seen, and a geom is kept when its footprint meets an arc of its room.

The test is conservative: doorways count as their full width (the jambs narrow them), arcs get a
small margin, and a camera standing within a wall's thickness of another room sees all of it. So
the rendered pixels are those of drawing every geom; ``tests/envs/world/test_rendering.py``
checks that from room centres, doorways and spots beside walls of several buildings.
"""

from __future__ import annotations

import math

import numpy as np

from .layout import DOOR_WIDTH, WALL_THICKNESS, FloorPlan

#: metres added to each side of a doorway and to a room's rectangle, and radians to each arc:
#: the test only ever keeps more
MARGIN = 0.05
_ARC_MARGIN = 1e-3
_FULL = math.pi  # half-width of the arc of a room seen from inside: every direction


def _wrap(angle):  # float or array: angles wrapped to [-pi, pi)
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _intersect(arc: tuple[float, float], other: tuple[float, float]
               ) -> tuple[float, float] | None:
    """The arc common to two arcs ``(mid, half)``, or ``None``; ``half = pi`` is every direction.

    A doorway seen from outside its wall subtends less than pi, so two arcs that are not the
    full circle have halves summing below pi and meet in one piece at most.
    """
    if arc[1] >= _FULL:
        return other
    if other[1] >= _FULL:
        return arc
    (m1, h1), (m2, h2) = arc, other
    delta = _wrap(m2 - m1)
    lo, hi = max(-h1, delta - h2), min(h1, delta + h2)
    if hi <= lo:
        return None
    return (_wrap(m1 + (lo + hi) / 2), (hi - lo) / 2)


class PortalCuller:
    """The geoms a camera at a point of the floor plan may see, through the doorways.

    Args:
        plan: the building.
        corners: (G, K, 2) the corners of each geom's footprint on the floor plan (its convex
            hull: the 8 corners of a box, the 4 of a plane, projected).
        rooms: (G, R) bool, the rooms each geom belongs to: the room it lines, stands or lies in
            (a door jamb belongs to the rooms on both sides of its wall). A geom of no room is
            always kept.

    Examples:
        >>> import numpy as np
        >>> from envs.world.layout import generate_floor_plan
        >>> plan = generate_floor_plan(4, np.random.default_rng(0))
        >>> floors = np.array([[(r.x0, r.y0), (r.x1, r.y0), (r.x1, r.y1), (r.x0, r.y1)]
        ...                    for r in plan.rooms])
        >>> culler = PortalCuller(plan, floors, np.eye(4, dtype=bool))
        >>> seen = culler.visible(*plan.rooms[0].center)
        >>> bool(seen[0]), int(seen.sum()) < 4  # its own floor; not every room's
        (True, True)
    """

    def __init__(self, plan: FloorPlan, corners: np.ndarray, rooms: np.ndarray) -> None:
        corners = np.asarray(corners, float)
        rooms = np.asarray(rooms, bool)
        if corners.ndim != 3 or corners.shape[2] != 2 or len(corners) != len(rooms):
            raise ValueError(f"corners must be (G, K, 2) and rooms (G, R) with the same G, got "
                             f"{corners.shape} and {rooms.shape}")
        if rooms.shape[1] != len(plan.rooms):
            raise ValueError(f"rooms has {rooms.shape[1]} columns for {len(plan.rooms)} rooms")
        self.plan = plan
        self._corners = corners
        self._rooms = rooms
        self._roomless = ~rooms.any(axis=1)
        self._members = [np.flatnonzero(rooms[:, r]) for r in range(len(plan.rooms))]
        # each room's doorways: (the room beyond, its two ends), widened by MARGIN
        self._doors: list[list[tuple[int, float, float, float, float]]] = [[] for _ in plan.rooms]
        half = DOOR_WIDTH / 2 + MARGIN
        for d in plan.doors:
            ends = ((d.x - half, d.y, d.x + half, d.y) if d.axis == "x"
                    else (d.x, d.y - half, d.x, d.y + half))
            a, b = d.rooms
            self._doors[a].append((b, *ends))
            self._doors[b].append((a, *ends))
        pad = WALL_THICKNESS / 2 + MARGIN
        self._boxes = [(r.x0 - pad, r.y0 - pad, r.x1 + pad, r.y1 + pad) for r in plan.rooms]

    def arcs(self, x: float, y: float) -> dict[int, list[tuple[float, float]]] | None:
        """The rooms seen from (x, y), each with the arcs ``(mid, half)`` (radians, CCW from +x)
        of the directions through which; ``half = pi`` for the rooms the point is in (or within a
        wall's thickness of). ``None`` outside the building: no room can be ruled out."""
        start = frozenset(r for r, (x0, y0, x1, y1) in enumerate(self._boxes)
                          if x0 <= x <= x1 and y0 <= y <= y1)
        if not start:
            return None
        seen: dict[int, list[tuple[float, float]]] = {r: [(0.0, _FULL)] for r in start}
        # a line of sight enters each (convex) room once: a path never revisits a room
        stack = [(r, (0.0, _FULL), start) for r in sorted(start)]
        while stack:
            room, arc, path = stack.pop()
            for other, ax, ay, bx, by in self._doors[room]:
                if other in path:
                    continue
                a = math.atan2(ay - y, ax - x)
                span = _wrap(math.atan2(by - y, bx - x) - a)
                through = _intersect(arc, (_wrap(a + span / 2), abs(span) / 2))
                if through is None:
                    continue
                seen.setdefault(other, []).append(through)
                stack.append((other, through, path | {other}))
        return seen

    def visible(self, x: float, y: float) -> np.ndarray:
        """(G,) bool: the geoms a camera at (x, y), looking any way, may see."""
        arcs = self.arcs(x, y)
        if arcs is None:
            return np.ones(len(self._corners), bool)
        keep = self._roomless.copy()
        seen_through = [(room, mid, half) for room, room_arcs in arcs.items()
                        for mid, half in room_arcs if half < _FULL]
        for room, room_arcs in arcs.items():
            if room_arcs[0][1] >= _FULL:
                keep[self._members[room]] = True
        if not seen_through:
            return keep
        # every (geom, arc of one of its rooms) pair at once
        rooms, mids, halves = (np.array(v) for v in zip(*seen_through))
        geom, arc = np.nonzero(self._rooms[:, rooms] & ~keep[:, None])
        c = self._corners[geom]
        rel = _wrap(np.arctan2(c[..., 1] - y, c[..., 0] - x) - mids[arc, None])
        lo, hi = rel.min(axis=1), rel.max(axis=1)
        # a footprint spanning more than pi straddles the back direction: keep it
        reach = halves[arc] + _ARC_MARGIN
        keep[geom[(hi - lo > math.pi) | ((hi >= -reach) & (lo <= reach))]] = True
        return keep


def box_corners(pos: np.ndarray, mat: np.ndarray, size: np.ndarray, plane: np.ndarray
                ) -> np.ndarray:
    """(G, 8, 2): the floor-plan corners of boxes and planes.

    Args:
        pos: (G, 3) centres; mat: (G, 9) rotation matrices, row-major (MuJoCo's ``geom_xmat``);
            size: (G, 3) half sizes; plane: (G,) bool, planes (flat in their z, their third
            size a grid spacing).
    """
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
    half = np.where(np.asarray(plane)[:, None], size * [1.0, 1.0, 0.0], size)
    local = signs[None, :, :] * half[:, None, :]  # (G, 8, 3) in the geom's frame
    rot = np.asarray(mat).reshape(-1, 3, 3)
    world = np.einsum("gij,gkj->gki", rot, local) + np.asarray(pos)[:, None, :]
    return world[..., :2]
