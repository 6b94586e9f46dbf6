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

Bursts last ``hold`` frames (1 s); a fractional ``K`` gives rooms of ``floor(K)`` and
``ceil(K)`` places, ``K`` on average.

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
    >>> parse_oracle("oracle-noise:0.1")
    TrueRooms(noise=0.1, split=1.0, merge=0.0, hold=10)
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import networkx as nx
import numpy as np

from ..world.layout import FloorPlan

#: the calibration family's kinds: ``oracle-<kind>:<value>``
KINDS = ("noise", "split", "merge")
_NAME = re.compile(r"^oracle(?:-(noise|split|merge):([0-9]*\.?[0-9]+))?$")


@dataclass(frozen=True)
class TrueRooms:
    """The true room as the place id, degraded by ``noise``, ``split`` and ``merge``.

    Args:
        noise: fraction of frames given a wrong place (another room's, drawn uniformly), in
            bursts of ``hold`` frames as a recognizer's aliasing lasts while the robot drives
            past what looks alike.
        split: places per room, each room cut into parallel strips across its longer side.
        merge: probability that a door's two rooms are reported as one place.
        hold: frames a wrong answer lasts (10 frames: 1 s of driving).

    Call :meth:`bind` with a building to get the :class:`BoundTrueRooms` that answers.
    """

    noise: float = 0.0
    split: float = 1.0
    merge: float = 0.0
    hold: int = 10

    def __post_init__(self) -> None:
        if not (0.0 <= self.noise < 1.0 and 0.0 <= self.merge <= 1.0):
            raise ValueError(f"noise must be in [0, 1) and merge in [0, 1], got {self.noise} "
                             f"and {self.merge}")
        if not 1.0 <= self.split <= 16.0 or self.hold < 1:
            raise ValueError(f"split must be 1 to 16 places per room and hold at least 1, got "
                             f"{self.split} and {self.hold}")

    @property
    def name(self) -> str:
        """The name that parses back to this oracle (:func:`parse_oracle`)."""
        for kind, default in (("noise", 0.0), ("split", 1.0), ("merge", 0.0)):
            value = getattr(self, kind)
            if value != default:
                return f"oracle-{kind}:{value:g}"
        return "oracle"

    def bind(self, plan: FloorPlan, seed: int = 0) -> BoundTrueRooms:
        """The oracle for building ``plan``; ``seed`` (with the plan) fixes every draw."""
        rng = np.random.default_rng([seed, len(plan.rooms), 0x0AC1E])
        parts = _parts(len(plan.rooms), self.split, rng)
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

    def place(self, room: int, pose: Sequence[float]) -> int:
        """The place reported at ``pose`` in true room ``room`` (-1, a doorway: unknown)."""
        if room < 0:
            return -1
        truth = self._strip(room, pose)
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

    def reset_position(self) -> None:
        """The robot was carried: a burst of wrong answers does not follow it."""
        self._left = 0

    def _strip(self, room: int, pose: Sequence[float]) -> int:
        k = int(self.parts[room])
        if k == 1:
            return int(self.base[room])
        r = self.plan.rooms[room]
        along_x = (r.x1 - r.x0) >= (r.y1 - r.y0)
        lo, hi, v = (r.x0, r.x1, pose[0]) if along_x else (r.y0, r.y1, pose[1])
        strip = min(max(int((v - lo) / (hi - lo) * k), 0), k - 1)
        return int(self.base[room]) + strip


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
    """The :class:`TrueRooms` named ``oracle`` or ``oracle-<kind>:<value>`` (:data:`KINDS`).

    Raises:
        ValueError: a name of the family with a value out of range, or another name.
    """
    match = _NAME.match(name)
    if match is None:
        raise ValueError(f"{name!r} is not an oracle name: 'oracle' or oracle-KIND:VALUE with "
                         f"KIND one of {KINDS}, e.g. oracle-noise:0.05")
    kind, value = match.groups()
    if kind is None:
        return TrueRooms()
    return TrueRooms(noise=float(value)) if kind == "noise" else (
        TrueRooms(split=float(value)) if kind == "split" else TrueRooms(merge=float(value)))


def error_of(name: str) -> tuple[str, float] | None:
    """The kind and size of a calibration recognizer's error, ``("noise", 0.05)`` for
    ``oracle-noise:0.05``; None for ``oracle`` and every other name."""
    if name == "oracle" or not is_oracle_name(name):
        return None
    kind, value = name.removeprefix("oracle-").split(":")
    return kind, float(value)
