"""Identical offices along a corridor: a building only appearance can tell apart.

In :func:`envs.world.layout.generate_floor_plan`'s buildings every room has its own size and door
pattern, so a ring of rangefinders and a compass already say which room the robot is in. Here
the offices are copies of one another (same size, one door in the same place, the same
furniture in the same spots), and with the default 3.5 m offices neither end of the corridor
is within the rangefinders' 4 m of any door but the two end offices'. Only what the rooms look like
(their textures and posters, drawn per room as in every world) tells them apart: the setting
in which a place recognizer earns its keep, as on the COLD database's corridors of offices.

Room ids: offices 0 to n-2 from west to east (x grows), the corridor last (n-1), south of
them (y from 0 to ``corridor_width``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .layout import (
    CORRIDOR,
    MAX_ROOMS,
    ROOM_KINDS,
    Door,
    FloorPlan,
    Room,
    Wall,
    cut_doors,
    furnish_room,
)


def corridor_floor_plan(
    n_rooms: int,
    rng: np.random.Generator,
    office_size: tuple[float, float] = (3.5, 4.0),
    corridor_width: float = 2.0,
    furniture: int = 3,
) -> FloorPlan:
    """Draw a corridor with ``n_rooms - 1`` identical offices along its north side.

    Args:
        n_rooms: rooms in all, the corridor included: 2 to :data:`~envs.world.layout.MAX_ROOMS`.
        rng: the only source of randomness (office names and the one furniture layout).
        office_size: (width along the corridor, depth), metres; every office is the same.
        corridor_width: metres.
        furniture: pieces of furniture per office, placed once and copied into every office.

    Returns:
        A :class:`~envs.world.layout.FloorPlan` whose offices each have one door, in the middle of
        their corridor wall; the corridor has no furniture. (The env's ``furniture_moved`` and
        ``furniture_removed`` change each office on its own, so they break the likeness.)
    """
    if not isinstance(n_rooms, (int, np.integer)) or not 2 <= n_rooms <= MAX_ROOMS:
        raise ValueError(f"a corridor building has 2 to {MAX_ROOMS} rooms (the corridor and at "
                         f"least one office), got {n_rooms!r}")
    width, depth = office_size
    if width < 2.5 or depth < 2.5 or corridor_width < 1.5:
        raise ValueError(f"offices need sides of at least 2.5 m and the corridor 1.5 m, got "
                         f"office_size={office_size!r}, corridor_width={corridor_width!r}")
    n_offices = n_rooms - 1
    corridor_id = n_offices
    kinds = [str(k) for k in rng.permutation(ROOM_KINDS)]
    offices = [
        Room(k, _name(kinds, k), kinds[k % len(kinds)], k * width, corridor_width,
             (k + 1) * width, corridor_width + depth)
        for k in range(n_offices)
    ]
    length = n_offices * width
    corridor = Room(corridor_id, CORRIDOR, CORRIDOR, 0.0, 0.0, length, corridor_width)
    doors = [Door((corridor_id, k), (k + 0.5) * width, corridor_width, "x")
             for k in range(n_offices)]
    walls = cut_doors(_wall_pieces(offices, corridor), doors)
    # one furniture layout, drawn in the first office, copied into the others
    template = furnish_room(offices[0], doors[:1], furniture, rng)
    items = tuple(replace(f, room=k, x=round(f.x + k * width, 3))
                  for k in range(n_offices) for f in template)
    return FloorPlan((*offices, corridor), tuple(doors), tuple(walls), items)


def _name(kinds: list[str], k: int) -> str:
    """COLD room kinds in the drawn order, numbered when they repeat (more offices than kinds)."""
    kind = kinds[k % len(kinds)]
    return kind if k < len(kinds) else f"{kind} {k // len(kinds) + 1}"


def _wall_pieces(offices: list[Room], corridor: Room) -> list[Wall]:
    """Every wall before the doors are cut; ``sides`` = (room on the low side, on the high side).
    """
    c = corridor.id
    x1, y0, y1 = corridor.x1, corridor.y1, offices[0].y1
    pieces = [
        Wall(0.0, 0.0, x1, 0.0, (-1, c)),  # the corridor's south wall
        Wall(0.0, 0.0, 0.0, y0, (-1, c)),  # its west end
        Wall(x1, 0.0, x1, y0, (c, -1)),  # its east end
    ]
    for o in offices:
        pieces += [
            Wall(o.x0, y0, o.x1, y0, (c, o.id)),  # the office's corridor wall, door to be cut
            Wall(o.x0, y1, o.x1, y1, (o.id, -1)),  # its north wall
            Wall(o.x0, y0, o.x0, y1, (o.id - 1, o.id)),  # its west wall (-1: outside)
        ]
    pieces.append(Wall(x1, y0, x1, y1, (offices[-1].id, -1)))  # the last office's east wall
    return pieces
