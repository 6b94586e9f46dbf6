"""Doors: leaves that close doorways until the robot comes near, and narrower openings.

A world option (``PlaceNav-v0(doors=F)``, off by default). Without doors every doorway is a
1 m opening in a 2.2 m wall, and the next room is in view long before the robot enters it, so
seed 001's nested mapper, whose new location opens when a key frame shares fewer than 25
matches with the current one, keeps one location per building. Real buildings have doors,
frames and narrower openings. With ``doors=F``:

- every doorway's width is drawn from :data:`WIDTHS` (the walls beside it grow to meet it), and
  gets a frame: a head (lintel) from :data:`HEAD` to the wall's top;
- a fraction ``F`` of the doorways get a leaf: an automatic door, as in offices and hospitals,
  shut until the robot is within :data:`OPEN_RADIUS` of the doorway, then out of the way. The
  robot needs no arm and no policy to get through, a scripted tour or an errand agent drives
  as before, and a room stays out of view until the robot is at its door. An open leaf is
  moved under the floor (the floor hides it, nothing collides with it): what a camera sees of
  a sliding door that has slid into its wall.

Everything is drawn from its own random stream (``[scene_seed, 1]``), so the building's rooms,
doorways' places, textures and furniture are those of the building without doors, and a
building without doors is built exactly as before.

Examples:
    >>> import numpy as np
    >>> from envs.world.doors import hang_doors
    >>> from envs.world.layout import generate_floor_plan
    >>> plan = generate_floor_plan(4, np.random.default_rng(0))
    >>> doors = hang_doors(plan, 1.0, scene_seed=0)
    >>> [d.leaf for d in doors.doors] == [True] * len(plan.doors)
    True
    >>> all(0.8 <= d.width <= 1.0 for d in doors.doors)
    True
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np

from .layout import DOOR_WIDTH, Door, FloorPlan, Wall

#: the range doorway widths are drawn from, metres
WIDTHS = (0.8, 1.0)
#: a leaf opens when the robot's centre is this close to its doorway's centre, metres: late
#: enough that the robot sees little of the next room before it is in it (chosen on `val`,
#: docs/design.md "Doors"), early enough that a robot heading through it (its centre 0.22 m
#: from the leaf when touching) never touches a shut leaf
OPEN_RADIUS = 0.5
#: a doorway's height: the frame's head fills the wall above it
HEAD = 2.0
LEAF_THICKNESS = 0.04
#: where an open leaf goes: under the floor
_STOWED = -3.0


def hang_doors(plan: FloorPlan, fraction: float, scene_seed: int) -> FloorPlan:
    """``plan`` with every doorway narrowed to a width drawn from :data:`WIDTHS` and a leaf
    on a ``fraction`` of them (``Door.leaf``); the walls beside each doorway lengthened to
    meet it.

    Raises:
        ValueError: ``fraction`` outside [0, 1].
    """
    if not 0.0 <= fraction <= 1.0:
        raise ValueError(f"doors must be a fraction in [0, 1], got {fraction!r}")
    rng = np.random.default_rng([scene_seed, 1])
    doors = tuple(replace(d, width=round(float(rng.uniform(*WIDTHS)), 2),
                          leaf=bool(rng.random() < fraction)) for d in plan.doors)
    walls = list(plan.walls)
    for door in doors:
        walls = _narrow(walls, door)
    return replace(plan, doors=doors, walls=tuple(walls))


def _narrow(walls: list[Wall], door: Door) -> list[Wall]:
    """``walls`` with the two segments that end at ``door``'s 1 m opening extended to its
    width."""
    centre = door.x if door.axis == "x" else door.y
    line = door.y if door.axis == "x" else door.x
    grow = (DOOR_WIDTH - door.width) / 2
    out = []
    for w in walls:
        lo, hi = (w.x0, w.x1) if w.axis == "x" else (w.y0, w.y1)
        on_line = w.axis == door.axis and abs((w.y0 if w.axis == "x" else w.x0) - line) < 1e-6
        if on_line and abs(hi - (centre - DOOR_WIDTH / 2)) < 1e-6:
            hi += grow
        elif on_line and abs(lo - (centre + DOOR_WIDTH / 2)) < 1e-6:
            lo -= grow
        out.append(Wall(lo, w.y0, hi, w.y1, w.sides) if w.axis == "x"
                   else Wall(w.x0, lo, w.x1, hi, w.sides))
    return out


def add_doors(spec: mujoco.MjSpec, plan: FloorPlan, wall_height: float,
              rooms: dict[str, tuple[int, ...]]) -> None:
    """Each doorway's head, which belongs to the rooms on either side (``rooms``, for the
    portal culling), and, where ``Door.leaf``, its leaf: a mocap body ``door{i}`` holding a box
    shut in the opening (:class:`DoorOpener` moves it)."""
    frame = spec.add_material(name="door_frame", rgba=[0.42, 0.40, 0.38, 1]).name
    leaf = spec.add_material(name="door_leaf", rgba=[0.55, 0.36, 0.20, 1]).name
    for i, d in enumerate(plan.doors):
        along = [d.width / 2, LEAF_THICKNESS, 0.0] if d.axis == "x" \
            else [LEAF_THICKNESS, d.width / 2, 0.0]
        head = (wall_height - HEAD) / 2
        spec.worldbody.add_geom(name=f"door_head{i}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                size=[along[0], along[1], head], pos=[d.x, d.y, HEAD + head],
                                material=frame, contype=0, conaffinity=0)
        rooms[f"door_head{i}"] = d.rooms
        if d.leaf:
            body = spec.worldbody.add_body(name=f"door{i}", mocap=True, pos=[d.x, d.y, HEAD / 2])
            # a moving geom: the renderer never culls it (only the world body's are culled)
            body.add_geom(name=f"door_leaf{i}", type=mujoco.mjtGeom.mjGEOM_BOX,
                          size=[along[0], along[1], HEAD / 2], material=leaf)


class DoorOpener:
    """Opens each leaf while the robot is within :data:`OPEN_RADIUS` of its doorway and shuts
    it otherwise; :meth:`update` before each physics step (and before the first frame)."""

    def __init__(self, model: mujoco.MjModel, plan: FloorPlan) -> None:
        self.doors = [(model.body(f"door{i}").mocapid[0], d) for i, d in enumerate(plan.doors)
                      if d.leaf]

    def update(self, data: mujoco.MjData, x: float, y: float) -> None:
        for mocap, d in self.doors:
            near = (x - d.x) ** 2 + (y - d.y) ** 2 < OPEN_RADIUS ** 2
            data.mocap_pos[mocap] = (d.x, d.y, _STOWED if near else HEAD / 2)
