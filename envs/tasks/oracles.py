"""The true rooms as a recognizer, and calibration recognizers with errors of a known size.

``oracle`` answers the room the robot is in: the upper bound of every closed-loop figure. The
calibration family degrades it by a controlled amount, so a track's success can be plotted
against the injected error and a benchmark's *resolution* measured: the smallest error whose
paired difference from ``oracle`` its sample can tell from zero (``docs/design.md``). Each is
deterministic from its seed and the building:

| name | what is wrong | places per room |
|---|---|---|
| ``oracle-noise:P`` | a fraction ``P`` of frames get another room's place, in bursts | 1 |
| ``oracle-split:K`` | every room cut across its long side into ``K`` places | ``K`` |
| ``oracle-merge:P`` | each door's two rooms are one place with probability ``P`` | below 1 |
| ``oracle-cells:K`` | every room cut into ``K`` compact cells, a near-square grid | ``K`` |
| ``oracle-door:D`` | after a doorway, the room left is reported for ``D`` m | 1 |
| ``oracle-revisit:P`` | a room entered again opens a new place with probability ``P`` | above 1 |
| ``oracle-pose`` | nothing: true rooms, and an image goal located at its tour step | 1 |

Bursts last ``hold`` frames (1 s); a fractional ``K`` gives rooms of ``floor(K)`` and
``ceil(K)`` places, ``K`` on average. ``split`` cuts strips (v2's calibration, kept so its
figures stand); ``cells`` cuts the compact places an image goal needs: a room of 4 cells is
2 x 2, so a place's spot lies nearer every point of it. ``door`` and ``revisit`` are shaped
like what real recognizers get wrong: a place that lags behind at a doorway, and a revisit
seen from another side that opens a place of its own. ``oracle-pose`` is the ceiling of
image-goal errands (``PlaceNav-ImageGoal-v0``): it knows the goal's pose, so it gives the
agent the tour step nearest the goal as well as its room.

Over-segmentation is what separates the project's recognizers (``PANORAMA`` 1.4 places per
room, ``PANORAMA_ORB`` 2.4): ``oracle-split:1.4`` and ``oracle-split:2.4`` are one place per
room apart and right about every boundary they keep.

Examples:
    >>> from envs.world.layout import generate_floor_plan
    >>> import numpy as np
    >>> plan = generate_floor_plan(4, np.random.default_rng(0))
    >>> truth = TrueRooms(split=2).bind(plan, seed=0)
    >>> room = plan.rooms[0]
    >>> ends = [(room.x0 + 0.1, room.y0 + 0.1), (room.x1 - 0.1, room.y1 - 0.1)]
    >>> [truth.place(0, (x, y, 0.0)) for x, y in ends]
    [0, 1]
    >>> parse_oracle("oracle-noise:0.1").name, parse_oracle("oracle-cells:4").cells
    ('oracle-noise:0.1', 4.0)
    >>> cells = TrueRooms(cells=4).bind(plan, seed=0)
    >>> sorted({cells.place(0, (x, y, 0.0)) for x in (room.x0 + 0.1, room.x1 - 0.1)
    ...         for y in (room.y0 + 0.1, room.y1 - 0.1)})
    [0, 1, 2, 3]
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import networkx as nx
import numpy as np

from ..world.layout import FloorPlan

#: the calibration family's kinds: ``oracle-<kind>:<value>``
KINDS = ("noise", "split", "merge", "cells", "door", "revisit")
_NAME = re.compile(r"^oracle(?:-(noise|split|merge|cells|door|revisit):([0-9]*\.?[0-9]+)"
                   r"|-(pose))?$")
#: each kind's value that means "no error"
_NO_ERROR = {"noise": 0.0, "split": 1.0, "merge": 0.0, "cells": 1.0, "door": 0.0,
             "revisit": 0.0}


@dataclass(frozen=True)
class TrueRooms:
    """The true room as the place id, degraded by one of the calibration errors.

    Args:
        noise: fraction of frames given a wrong place (another room's, drawn uniformly), in
            bursts of ``hold`` frames as a recognizer's aliasing lasts while the robot drives
            past what looks alike.
        split: places per room, each room cut into parallel strips across its longer side.
        merge: probability that a door's two rooms are reported as one place.
        hold: frames a wrong answer lasts (10 frames: 1 s of driving).
        cells: places per room, each room cut into a near-square grid of compact cells.
        door: metres after a doorway over which the room just left is still reported.
        revisit: probability that entering a room already seen opens a new place for the visit.
        pose: the ceiling of image goals: the goal's pose is known (:meth:`BoundTrueRooms.goal`).

    Call :meth:`bind` with a building to get the :class:`BoundTrueRooms` that answers.
    """

    noise: float = 0.0
    split: float = 1.0
    merge: float = 0.0
    hold: int = 10
    cells: float = 1.0
    door: float = 0.0
    revisit: float = 0.0
    pose: bool = False

    def __post_init__(self) -> None:
        if not (0.0 <= self.noise < 1.0 and 0.0 <= self.merge <= 1.0
                and 0.0 <= self.revisit <= 1.0):
            raise ValueError(f"noise must be in [0, 1), merge and revisit in [0, 1], got "
                             f"{self.noise}, {self.merge} and {self.revisit}")
        if not (1.0 <= self.split <= 16.0 and 1.0 <= self.cells <= 16.0) or self.hold < 1:
            raise ValueError(f"split and cells must be 1 to 16 places per room and hold at "
                             f"least 1, got {self.split}, {self.cells} and {self.hold}")
        if not 0.0 <= self.door <= 5.0:
            raise ValueError(f"door must be 0 to 5 metres, got {self.door}")

    @property
    def name(self) -> str:
        """The name that parses back to this oracle (:func:`parse_oracle`)."""
        for kind, default in _NO_ERROR.items():
            value = getattr(self, kind)
            if value != default:
                return f"oracle-{kind}:{value:g}"
        return "oracle-pose" if self.pose else "oracle"

    def bind(self, plan: FloorPlan, seed: int = 0) -> BoundTrueRooms:
        """The oracle for building ``plan``; ``seed`` (with the plan) fixes every draw."""
        rng = np.random.default_rng([seed, len(plan.rooms), 0x0AC1E])
        parts = _parts(len(plan.rooms), max(self.split, self.cells), rng)
        group = _merged_groups(plan, self.merge, rng)
        # places numbered room by room: a merged group's strips share its first room's numbers
        first: dict[int, int] = {}
        base: list[int] = []
        n = 0
        for room in plan.rooms:
            head = group[room.id]
            if head not in first:
                first[head] = n
                n += int(parts[head])
            base.append(first[head])
        return BoundTrueRooms(self, plan, parts[[group[r.id] for r in plan.rooms]],
                              np.array(base), n, rng)


@dataclass
class BoundTrueRooms:
    """A :class:`TrueRooms` bound to one building: :meth:`place` answers for each frame."""

    oracle: TrueRooms
    plan: FloorPlan
    parts: np.ndarray  # places of each room
    base: np.ndarray  # each room's first place
    n_places: int
    rng: np.random.Generator
    _wrong: int = field(default=-1, init=False)
    _left: int = field(default=0, init=False)
    _room: int = field(default=-1, init=False)  # the room of the last frame in one
    _lag: tuple[int, float, float] | None = field(default=None, init=False)  # room left, door
    _seen: set[int] = field(default_factory=set, init=False)  # rooms entered before
    _visit: int = field(default=-1, init=False)  # this visit's own place (revisit), or -1
    _opened: int = field(default=0, init=False)  # places revisits opened

    def place(self, room: int, pose: Sequence[float]) -> int:
        """The place reported at ``pose`` in true room ``room`` (-1, a doorway: unknown)."""
        if room < 0:
            return -1
        entered = room != self._room
        self._enter(room, pose, entered)
        truth = self._strip(room, pose)
        if self._lag is not None:
            left, x, y = self._lag
            if math.dist((x, y), pose[:2]) <= self.oracle.door:
                truth = self._strip(left, pose)
            else:
                self._lag = None
        elif self._visit >= 0:
            truth = self._visit
        if self.oracle.noise == 0.0 or self.n_places < 2:
            return truth
        if self._left == 0:  # a new burst: wrong with the probability that makes the fraction
            self._left = self.oracle.hold
            wrong = self.rng.random() < self.oracle.noise
            self._wrong = int(self.rng.integers(self.n_places - 1)) if wrong else -1
        self._left -= 1
        if self._wrong < 0:
            return truth
        return self._wrong + (self._wrong >= truth)  # any place but the true one

    def goal(self, room: int, pose: Sequence[float] | np.ndarray) -> int:
        """The place of a goal picture taken at ``pose`` in true room ``room``: a still
        image, so no doorway lag and no visit of its own; wrong with probability ``noise``."""
        if room < 0:
            return -1
        truth = self._strip(room, pose)
        if self.oracle.noise > 0.0 and self.n_places > 1 and self.rng.random() < self.oracle.noise:
            wrong = int(self.rng.integers(self.n_places - 1))
            return wrong + (wrong >= truth)
        return truth

    def reset_position(self) -> None:
        """The robot was carried: a burst of wrong answers, a doorway's lag and the visit do
        not follow it."""
        self._left = 0
        self._room, self._lag, self._visit = -1, None, -1

    def _enter(self, room: int, pose: Sequence[float], entered: bool) -> None:
        """Keep the doorway's lag and the revisit's place of a frame in ``room``."""
        if not entered:
            return
        left, self._room = self._room, room
        self._lag, self._visit = None, -1
        if self.oracle.door > 0.0 and left >= 0:
            doors = [d for d in self.plan.doors if set(d.rooms) == {left, room}]
            if doors:
                d = min(doors, key=lambda d: math.dist((d.x, d.y), pose[:2]))
                self._lag = (left, d.x, d.y)
        if self.oracle.revisit > 0.0:
            if room in self._seen and self.rng.random() < self.oracle.revisit:
                self._visit = self.n_places + self._opened
                self._opened += 1
            self._seen.add(room)

    def _strip(self, room: int, pose: Sequence[float] | np.ndarray) -> int:
        k = int(self.parts[room])
        if k == 1:
            return int(self.base[room])
        r = self.plan.rooms[room]
        if self.oracle.cells > 1.0:
            return int(self.base[room]) + _cell(k, r.x0, r.x1, r.y0, r.y1, pose)
        along_x = (r.x1 - r.x0) >= (r.y1 - r.y0)
        lo, hi, v = (r.x0, r.x1, pose[0]) if along_x else (r.y0, r.y1, pose[1])
        strip = min(max(int((v - lo) / (hi - lo) * k), 0), k - 1)
        return int(self.base[room]) + strip


def _cell(k: int, x0: float, x1: float, y0: float, y1: float,
          pose: Sequence[float] | np.ndarray) -> int:
    """The cell of ``pose`` in a room cut into ``k`` cells: the ``a x b = k`` grid whose cells
    are nearest square."""
    w, h = x1 - x0, y1 - y0
    a = min((a for a in range(1, k + 1) if k % a == 0),
            key=lambda a: abs(math.log((w / a) / (h / (k // a)))))
    b = k // a
    i = min(max(int((pose[0] - x0) / w * a), 0), a - 1)
    j = min(max(int((pose[1] - y0) / h * b), 0), b - 1)
    return i * b + j


def _parts(n_rooms: int, split: float, rng: np.random.Generator) -> np.ndarray:
    """Places per room: ``floor(split)`` or one more, the share of the latter the fraction."""
    whole = math.floor(split)
    extra = rng.random(n_rooms) < split - whole
    return whole + extra.astype(np.int64)


def _merged_groups(plan: FloorPlan, merge: float, rng: np.random.Generator) -> list[int]:
    """Each room's group head: rooms joined through the doors drawn to merge."""
    g = nx.Graph()
    g.add_nodes_from(r.id for r in plan.rooms)
    draws = rng.random(len(plan.doors))
    g.add_edges_from(d.rooms for d, u in zip(plan.doors, draws) if u < merge)
    head = [0] * len(plan.rooms)
    for component in nx.connected_components(g):
        for room in component:
            head[room] = min(component)
    return head


def is_oracle_name(name: str) -> bool:
    """Whether ``name`` names the true rooms or a calibration recognizer (``oracle-noise:0.1``),
    not a ``package.module:Class``."""
    return bool(_NAME.match(name))


def parse_oracle(name: str) -> TrueRooms:
    """The :class:`TrueRooms` named ``oracle``, ``oracle-pose`` or ``oracle-<kind>:<value>``
    (:data:`KINDS`).

    Raises:
        ValueError: a name of the family with a value out of range, or another name.
    """
    match = _NAME.match(name)
    if match is None:
        raise ValueError(f"{name!r} is not an oracle name: 'oracle', 'oracle-pose' or "
                         f"oracle-KIND:VALUE with KIND one of {KINDS}, e.g. oracle-noise:0.05")
    kind, value, pose = match.groups()
    if pose:
        return TrueRooms(pose=True)
    if kind is None:
        return TrueRooms()
    values: dict[str, Any] = {kind: float(value)}
    return TrueRooms(**values)


def error_of(name: str) -> tuple[str, float] | None:
    """The kind and size of a calibration recognizer's error, ``("noise", 0.05)`` for
    ``oracle-noise:0.05``; None for ``oracle``, ``oracle-pose`` and every other name."""
    if not is_oracle_name(name):
        return None
    oracle = parse_oracle(name)
    for kind, default in _NO_ERROR.items():
        if getattr(oracle, kind) != default:
            return kind, float(getattr(oracle, kind))
    return None
