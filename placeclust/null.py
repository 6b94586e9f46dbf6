"""Null recognizers: place ids that carry no information about where the robot is.

They set the floor of every benchmark that scores a recognizer, open loop (what precision does
chance reach with as many places?) or closed loop (how often does an agent reach a named room
when its place ids mean nothing?). Both follow the recognizer protocol
(:mod:`placeclust.checks`), so they go wherever a recognizer goes.

Examples:
    >>> import numpy as np
    >>> from placeclust.null import NoPlaces, RandomPlaces
    >>> frame = np.random.default_rng(0).integers(0, 255, (32, 32), np.uint8)
    >>> model = RandomPlaces(n_ids=4, hold=2, seed=1)
    >>> [model.learn_predict_one(frame) for _ in range(8)]
    [0, 0, 1, 1, 2, 2, 2, 2]
    >>> NoPlaces().learn_predict_one(frame)
    -1
"""

from __future__ import annotations

import networkx as nx
import numpy as np

from placeclust.frames import to_gray
from placeclust.online import UNKNOWN


class RandomPlaces:
    """A new uniformly drawn place id every ``hold`` frames, whatever the frames show.

    Ids are numbered in the order they are first drawn (``0, 1, ...``), as for every recognizer.

    Holding an id for a while gives the output the rhythm of a recognizer's (ids that change
    every second or so, not every frame) while it says nothing about the place: an agent that
    acts on it can only do as well as one that ignores it.

    Args:
        n_ids: ids are drawn from ``0 .. n_ids - 1``.
        hold: frames each draw lasts (10 frames is 1 s of driving at ``control_dt`` = 0.1 s).
        seed: seeds the draws; the same seed gives the same ids.

    A blank frame is :data:`~placeclust.online.UNKNOWN`, as for every recognizer; consecutive
    frames with different ids join the two in :attr:`graph`. It never looks at a frame beyond
    that, so it says ``reads_images = False`` and takes ``None`` for "no image": a simulator
    need not render for it (the ids are the same).
    """

    reads_images = False

    def __init__(self, n_ids: int = 8, hold: int = 10, seed: int = 0) -> None:
        if n_ids < 1 or hold < 1:
            raise ValueError(f"n_ids and hold must be at least 1, got {n_ids} and {hold}")
        self.n_ids = n_ids
        self.hold = hold
        self.seed = seed
        self._rng = np.random.default_rng(seed)
        self._frames = 0
        self._id = UNKNOWN
        self._last = UNKNOWN
        self._number: dict[int, int] = {}
        self.graph = nx.Graph()

    @property
    def n_places(self) -> int:
        """Ids given so far."""
        return self.graph.number_of_nodes()

    def learn_predict_one(self, frame: np.ndarray | None) -> int:
        """The id of this stretch of frames, drawn when the stretch began."""
        if frame is not None and not to_gray(frame).any():
            return UNKNOWN
        if self._frames % self.hold == 0:
            draw = int(self._rng.integers(self.n_ids))
            # numbered in the order they first appear, as the protocol numbers places
            self._id = self._number.setdefault(draw, len(self._number))
        self._frames += 1
        self.graph.add_node(self._id)
        if self._last != UNKNOWN and self._last != self._id:
            self.graph.add_edge(self._last, self._id)
        self._last = self._id
        return self._id

    def predict_one(self, frame: np.ndarray) -> int:
        """The current id, without drawing a new one."""
        return UNKNOWN if not to_gray(frame).any() else self._id

    def reset_position(self) -> None:
        """Forget the last id, so no edge joins it to the next (the robot was carried away)."""
        self._last = UNKNOWN


class NoPlaces:
    """Answers :data:`~placeclust.online.UNKNOWN` for every frame: the recognizer that is not
    there. An agent given its ids must find its way without them. Like :class:`RandomPlaces`
    it does not read images (``reads_images = False``; ``None`` for a frame is allowed)."""

    reads_images = False

    def __init__(self) -> None:
        self.graph = nx.Graph()

    @property
    def n_places(self) -> int:
        """Always 0."""
        return 0

    def learn_predict_one(self, frame: np.ndarray | None) -> int:
        """:data:`~placeclust.online.UNKNOWN`, after checking ``frame`` like any recognizer."""
        if frame is not None:
            to_gray(frame)
        return UNKNOWN

    def predict_one(self, frame: np.ndarray) -> int:
        """:data:`~placeclust.online.UNKNOWN`."""
        return self.learn_predict_one(frame)
