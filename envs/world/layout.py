"""Procedural floor plans as plain data: rooms, doors, walls and furniture.

This module is pure geometry (numpy and networkx, no MuJoCo), so it can be property-tested on
thousands of random plans; :mod:`envs.world.scene` turns a :class:`FloorPlan` into a MuJoCo model.

The generator lays a grid of cells with random column widths and row heights, merges a few
horizontally adjacent cells into long rooms (these become corridors), connects the rooms by a
random spanning tree of doors, and adds doors on a fraction of the remaining shared walls so the
room graph has loops. Room kinds follow the COLD database the seed papers use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import networkx as nx
import numpy as np

#: Room kinds of the COLD database (Pronobis et al.), minus the corridor, which is given to
#: merged, elongated rooms.
ROOM_KINDS: tuple[str, ...] = (
    "kitchen",
    "printer area",
    "meeting room",
    "small office",
    "large office",
    "recycle area",
    "toilet",
    "one-person office",
    "two-person office",
    "stairs area",
    "bathroom",
)
CORRIDOR = "corridor"

WALL_THICKNESS = 0.1
DOOR_WIDTH = 1.0
MAX_ROOMS = 32


@dataclass(frozen=True)
class Room:
    """An axis-aligned rectangular room, in metres."""

    id: int
    name: str
    kind: str
    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def center(self) -> tuple[float, float]:
        return (0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1))

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        return (self.x0 + margin <= x <= self.x1 - margin) and (
            self.y0 + margin <= y <= self.y1 - margin
        )


@dataclass(frozen=True)
class Door:
    """A doorway of width ``width`` centred at (x, y) in the wall between ``rooms``.

    ``axis`` is the axis the wall runs along: ``"x"`` for a wall at constant y, ``"y"`` for a wall
    at constant x. ``leaf``: the doorway has a door that shuts it while the robot is away
    (:mod:`envs.world.doors`).
    """

    rooms: tuple[int, int]
    x: float
    y: float
    axis: str
    width: float = DOOR_WIDTH
    leaf: bool = False

    def approach(self, room: Room, distance: float = 0.8) -> tuple[float, float]:
        """Point ``distance`` metres in front of the door on ``room``'s side."""
        cx, cy = room.center
        if self.axis == "x":
            return (self.x, self.y + math.copysign(distance, cy - self.y))
        return (self.x + math.copysign(distance, cx - self.x), self.y)


@dataclass(frozen=True)
class Wall:
    """An axis-aligned wall segment (centre line) from (x0, y0) to (x1, y1).

    ``sides`` holds the room id on the low side (smaller x or y) and on the high side; -1 is
    outside the building.
    """

    x0: float
    y0: float
    x1: float
    y1: float
    sides: tuple[int, int]

    @property
    def axis(self) -> str:
        return "x" if self.y0 == self.y1 else "y"

    @property
    def length(self) -> float:
        return abs(self.x1 - self.x0) + abs(self.y1 - self.y0)


@dataclass(frozen=True)
class Furniture:
    """A box of furniture standing on the floor: centre (x, y), half sizes, height."""

    room: int
    kind: str
    x: float
    y: float
    hx: float
    hy: float
    height: float


@dataclass(frozen=True)
class FloorPlan:
    """A building: rooms, doors between them, wall segments and furniture."""

    rooms: tuple[Room, ...]
    doors: tuple[Door, ...]
    walls: tuple[Wall, ...]
    furniture: tuple[Furniture, ...] = field(default=())

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) of the whole building."""
        return (
            min(r.x0 for r in self.rooms),
            min(r.y0 for r in self.rooms),
            max(r.x1 for r in self.rooms),
            max(r.y1 for r in self.rooms),
        )

    def graph(self) -> nx.Graph:
        """The room adjacency graph: a node per room (attribute ``name``), an edge per door."""
        g = nx.Graph()
        for r in self.rooms:
            g.add_node(r.id, name=r.name, kind=r.kind)
        for d in self.doors:
            g.add_edge(*d.rooms, door=d)
        return g

    def room_at(self, x: float, y: float) -> int:
        """Id of the room containing (x, y), or -1 outside the building.

        A point inside a doorway or wall belongs to the room whose rectangle it is nearest to the
        inside of, so every point of the walkable area has exactly one room.
        """
        best, best_depth = -1, -math.inf
        for r in self.rooms:
            depth = min(x - r.x0, r.x1 - x, y - r.y0, r.y1 - y)
            if depth > best_depth:
                best, best_depth = r.id, depth
        return best if best_depth >= -WALL_THICKNESS else -1

    def room_by_name(self, name: str) -> Room:
        """The room called ``name``; ``KeyError`` listing the known names otherwise."""
        for r in self.rooms:
            if r.name == name:
                return r
        raise KeyError(f"unknown room {name!r}; this world has {[r.name for r in self.rooms]}")

    def is_free(self, x: float, y: float, clearance: float) -> bool:
        """True where a disc of radius ``clearance`` fits inside a room and off the furniture."""
        rid = self.room_at(x, y)
        if rid < 0 or not self.rooms[rid].contains(x, y, WALL_THICKNESS / 2 + clearance):
            return False
        return all(
            abs(x - f.x) > f.hx + clearance or abs(y - f.y) > f.hy + clearance
            for f in self.furniture
            if f.room == rid
        )

    def free_point(
        self, room: int, rng: np.random.Generator, clearance: float = 0.45
    ) -> tuple[float, float]:
        """A uniformly drawn point of ``room`` where a disc of radius ``clearance`` is free."""
        r = self.rooms[room]
        for _ in range(1000):
            x = rng.uniform(r.x0, r.x1)
            y = rng.uniform(r.y0, r.y1)
            if self.is_free(x, y, clearance):
                return (float(x), float(y))
        return r.center  # centres are kept free of furniture by construction


def room_count(text: str) -> int:
    """An argparse ``type`` for ``--rooms``: an integer in 1 to :data:`MAX_ROOMS`, refused
    while the options are parsed, before any job starts or any folder is made.

    >>> room_count("6")
    6
    """
    import argparse

    try:
        n = int(text)
    except ValueError:
        n = 0
    if not 1 <= n <= MAX_ROOMS:
        raise argparse.ArgumentTypeError(f"a building has 1 to {MAX_ROOMS} rooms, got {text!r}")
    return n


def generate_floor_plan(
    n_rooms: int,
    rng: np.random.Generator,
    extra_doors: float = 0.5,
    room_size: tuple[float, float] = (3.5, 5.5),
    furniture_per_room: tuple[int, int] = (2, 4),
) -> FloorPlan:
    """Draw a random building.

    Args:
        n_rooms: number of rooms, 1 to :data:`MAX_ROOMS`.
        rng: the only source of randomness.
        extra_doors: fraction (0 to 1) of the shared walls outside the spanning tree that also get
            a door; 0 gives a tree of rooms, larger values give more loops.
        room_size: range of a grid cell's side, metres.
        furniture_per_room: inclusive range of furniture items per room.

    Returns:
        A :class:`FloorPlan` whose room graph is connected.
    """
    if not isinstance(n_rooms, (int, np.integer)) or not 1 <= n_rooms <= MAX_ROOMS:
        raise ValueError(f"n_rooms must be an integer in [1, {MAX_ROOMS}], got {n_rooms!r}")
    if not 0.0 <= extra_doors <= 1.0:
        raise ValueError(f"extra_doors must be in [0, 1], got {extra_doors!r}")
    if room_size[0] < 2.5 or room_size[1] < room_size[0]:
        raise ValueError(f"room_size must be (lo, hi) with 2.5 <= lo <= hi, got {room_size!r}")
    cols = math.ceil(math.sqrt(n_rooms))
    rows = math.ceil(n_rooms / cols)
    xs = np.concatenate([[0.0], np.cumsum(np.round(rng.uniform(*room_size, cols), 1))])
    ys = np.concatenate([[0.0], np.cumsum(np.round(rng.uniform(*room_size, rows), 1))])
    region = _merge_cells(rows, cols, rows * cols - n_rooms, rng)
    rooms = _name_rooms(region, xs, ys, rng)
    pieces = _wall_pieces(region, xs, ys)
    doors = _place_doors(pieces, len(rooms), extra_doors, rng)
    walls = cut_doors(pieces, doors)
    furniture = _place_furniture(rooms, doors, furniture_per_room, rng)
    return FloorPlan(tuple(rooms), tuple(doors), tuple(walls), tuple(furniture))


def _merge_cells(rows: int, cols: int, surplus: int, rng: np.random.Generator) -> np.ndarray:
    """Region label per grid cell after ``surplus`` merges of horizontal neighbours."""
    region = np.arange(rows * cols).reshape(rows, cols)
    for _ in range(surplus):
        # surplus < cols, so some row always still has two distinct regions side by side
        candidates = [
            (r, c)
            for r in range(rows)
            for c in range(cols - 1)
            if region[r, c] != region[r, c + 1]
        ]
        r, c = candidates[rng.integers(len(candidates))]
        region[region == region[r, c + 1]] = region[r, c]
    _, relabelled = np.unique(region, return_inverse=True)
    return relabelled.reshape(rows, cols)


def _name_rooms(
    region: np.ndarray, xs: np.ndarray, ys: np.ndarray, rng: np.random.Generator
) -> list[Room]:
    """Rooms from region labels: merged (elongated) regions are corridors, the others take COLD
    kinds in a random order, cycling when there are more rooms than kinds."""
    kinds = [str(k) for k in rng.permutation(ROOM_KINDS)]
    rooms: list[Room] = []
    counts: dict[str, int] = {}
    n_plain = 0
    for rid in range(int(region.max()) + 1):
        rr, cc = np.nonzero(region == rid)
        if len(rr) > 1:
            kind = CORRIDOR
        else:
            kind = kinds[n_plain % len(kinds)]
            n_plain += 1
        counts[kind] = counts.get(kind, 0) + 1
        name = kind if counts[kind] == 1 else f"{kind} {counts[kind]}"
        rooms.append(
            Room(rid, name, kind, float(xs[cc.min()]), float(ys[rr.min()]),
                 float(xs[cc.max() + 1]), float(ys[rr.max() + 1]))
        )
    return rooms


def _wall_pieces(region: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> list[Wall]:
    """Every cell edge whose two sides differ, collinear pieces of one room pair joined."""
    rows, cols = region.shape
    padded = np.full((rows + 2, cols + 2), -1)
    padded[1:-1, 1:-1] = region
    pieces: list[Wall] = []
    for c in range(cols + 1):  # walls at constant x: between padded[:, c] and padded[:, c+1]
        for r in range(rows):
            lo, hi = int(padded[r + 1, c]), int(padded[r + 1, c + 1])
            if lo != hi:
                pieces.append(Wall(float(xs[c]), float(ys[r]), float(xs[c]), float(ys[r + 1]),
                                   (lo, hi)))
    for r in range(rows + 1):
        for c in range(cols):
            lo, hi = int(padded[r, c + 1]), int(padded[r + 1, c + 1])
            if lo != hi:
                pieces.append(Wall(float(xs[c]), float(ys[r]), float(xs[c + 1]), float(ys[r]),
                                   (lo, hi)))
    return _join_collinear(pieces)


def _join_collinear(pieces: list[Wall]) -> list[Wall]:
    out: list[Wall] = []
    for p in pieces:
        last = out[-1] if out else None
        if (
            last is not None
            and last.sides == p.sides
            and last.axis == p.axis
            and (last.x1, last.y1) == (p.x0, p.y0)
        ):
            out[-1] = Wall(last.x0, last.y0, p.x1, p.y1, p.sides)
        else:
            out.append(p)
    return out


def _place_doors(
    pieces: list[Wall], n_rooms: int, extra: float, rng: np.random.Generator
) -> list[Door]:
    shared = [p for p in pieces if min(p.sides) >= 0]
    g = nx.Graph()
    g.add_nodes_from(range(n_rooms))
    for i, p in enumerate(shared):
        g.add_edge(*p.sides, weight=float(rng.random()), piece=i)
    tree = nx.minimum_spanning_tree(g)  # random weights: a uniform-ish random spanning tree
    chosen = [tree.edges[e]["piece"] for e in sorted(tree.edges)]
    others = [g.edges[e]["piece"] for e in sorted(g.edges) if not tree.has_edge(*e)]
    n_extra = math.ceil(extra * len(others))  # any positive fraction gives at least one loop
    chosen += [others[i] for i in sorted(rng.permutation(len(others))[:n_extra])]
    doors = []
    for i in chosen:
        p = shared[i]
        margin = DOOR_WIDTH / 2 + 0.6
        t = round(float(rng.uniform(margin, p.length - margin)), 2)
        if p.axis == "x":
            doors.append(Door(p.sides, min(p.x0, p.x1) + t, p.y0, "x"))
        else:
            doors.append(Door(p.sides, p.x0, min(p.y0, p.y1) + t, "y"))
    return doors


def cut_doors(pieces: list[Wall], doors: list[Door]) -> list[Wall]:
    """The wall segments left of ``pieces`` once each door's opening is cut out of its wall."""
    walls = []
    for p in pieces:
        gaps = sorted(
            (d.x if p.axis == "x" else d.y) for d in doors
            if d.axis == p.axis and set(d.rooms) == set(p.sides)
            and (d.y == p.y0 if p.axis == "x" else d.x == p.x0)
            and (min(p.x0, p.x1) <= d.x <= max(p.x0, p.x1))
            and (min(p.y0, p.y1) <= d.y <= max(p.y0, p.y1))
        )
        start = p.x0 if p.axis == "x" else p.y0
        end = p.x1 if p.axis == "x" else p.y1
        for g in gaps + [None]:
            stop = end if g is None else g - DOOR_WIDTH / 2
            if stop - start > 1e-6:
                if p.axis == "x":
                    walls.append(Wall(start, p.y0, stop, p.y0, p.sides))
                else:
                    walls.append(Wall(p.x0, start, p.x0, stop, p.sides))
            if g is not None:
                start = g + DOOR_WIDTH / 2
    return walls


_FURNITURE = {  # kind: (length along wall, depth, height) ranges
    "table": ((1.0, 1.6), (0.5, 0.7), (0.72, 0.76)),
    "shelf": ((0.8, 1.4), (0.3, 0.4), (1.4, 2.0)),
    "cabinet": ((0.6, 1.0), (0.4, 0.5), (0.9, 1.3)),
    "sofa": ((1.4, 1.9), (0.6, 0.7), (0.5, 0.8)),
    "machine": ((0.6, 0.9), (0.5, 0.6), (0.9, 1.2)),
}


def _place_furniture(
    rooms: list[Room], doors: list[Door], per_room: tuple[int, int], rng: np.random.Generator
) -> list[Furniture]:
    """Furniture along the walls, clear of doorways, so the room centre stays free."""
    items: list[Furniture] = []
    for room in rooms:
        items += furnish_room(room, doors, int(rng.integers(per_room[0], per_room[1] + 1)), rng)
    return items


def furnish_room(room: Room, doors: list[Door], n_items: int, rng: np.random.Generator
                 ) -> list[Furniture]:
    """Up to ``n_items`` pieces of furniture along ``room``'s walls, clear of ``doors`` and of
    each other (an item that finds no free spot in 20 draws is left out)."""
    kinds = sorted(_FURNITURE)
    placed: list[Furniture] = []
    for _ in range(n_items):
        for _attempt in range(20):
            f = draw_item(room, kinds[rng.integers(len(kinds))], rng)
            if clear_of(f, placed, doors):
                placed.append(f)
                break
    return placed


def draw_item(room: Room, kind: str, rng: np.random.Generator) -> Furniture:
    """A furniture item of ``kind`` against a random wall of ``room`` (may overlap others)."""
    (l0, l1), (d0, d1), (h0, h1) = _FURNITURE[kind]
    length, depth = rng.uniform(l0, l1), rng.uniform(d0, d1)
    height = rng.uniform(h0, h1)
    side = int(rng.integers(4))  # 0: low y, 1: high y, 2: low x, 3: high x
    inset = WALL_THICKNESS / 2 + 0.02
    if side < 2:
        x = rng.uniform(room.x0 + length / 2 + 0.1, room.x1 - length / 2 - 0.1)
        y = room.y0 + inset + depth / 2 if side == 0 else room.y1 - inset - depth / 2
        hx, hy = length / 2, depth / 2
    else:
        y = rng.uniform(room.y0 + length / 2 + 0.1, room.y1 - length / 2 - 0.1)
        x = room.x0 + inset + depth / 2 if side == 2 else room.x1 - inset - depth / 2
        hx, hy = depth / 2, length / 2
    r = lambda v: round(float(v), 3)  # noqa: E731 - keeps plans readable when printed
    return Furniture(room.id, kind, r(x), r(y), r(hx), r(hy), r(height))


def clear_of(f: Furniture, placed: list[Furniture], doors: list[Door]) -> bool:
    """True when ``f`` keeps a gap to every ``placed`` item and leaves the doorways free."""
    gap = 0.5
    for o in placed:
        if abs(f.x - o.x) < f.hx + o.hx + gap and abs(f.y - o.y) < f.hy + o.hy + gap:
            return False
    keep = DOOR_WIDTH / 2 + 0.9  # the robot needs room to line up with a doorway
    return all(abs(f.x - d.x) > f.hx + keep or abs(f.y - d.y) > f.hy + keep for d in doors)
