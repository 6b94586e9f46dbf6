"""What a ``PlaceNav-GuidedTour-v1`` episode records: the guided tour the robot observed
(:class:`TourRecord`, all an agent may learn from), what the tour leaves for errands
(:class:`TourState`, so one tour serves several tracks) and each errand's outcome
(:class:`Errand`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from placeclust.metrics import score


@dataclass(eq=False)
class TourRecord:
    """What the robot observed on the guided tour, one row per step: all an agent may learn from.

    Attributes:
        place_id: (T,) int, the recognizer's place, as its map holds it after the tour (ids a
            recognizer merged are given as the place they became); -1 unknown.
        heard: (T,) str, the room name the guide said at that step, or "".
        odometry: (T, 2) float32, measured forward speed (m/s) and turn rate (rad/s).
        heading: (T, 2) float32, compass (cos, sin).
        control_dt: seconds per step.
        ranges: (T, 16) float32, the rangefinders' readings (m), or None where not recorded.
    """

    place_id: np.ndarray
    heard: np.ndarray
    odometry: np.ndarray
    heading: np.ndarray
    control_dt: float
    ranges: np.ndarray | None = None

    def heard_names(self) -> list[str]:
        """The room names the guide said, in the order said."""
        return [str(h) for h in self.heard if h]

    def map_scores(self, rooms: np.ndarray) -> dict[str, float]:
        """The tour map against ``rooms``, the true room of each step (-1 in a doorway, left
        out): ``precision``, ``nmi``, ``n_places`` and ``places_per_room``."""
        inside = rooms >= 0
        s = score(self.place_id[inside], rooms[inside])
        return {"precision": s["precision"], "nmi": s["nmi"], "n_places": s["n_places"],
                "places_per_room": s["n_places"] / max(s["n_rooms"], 1)}

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TourRecord):
            return NotImplemented
        return self.control_dt == other.control_dt and all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("place_id", "heard", "odometry", "heading")) and (
            (self.ranges is None) == (other.ranges is None)) and (
            self.ranges is None or np.array_equal(self.ranges, np.asarray(other.ranges)))


@dataclass(eq=False)
class TourState:
    """What a guided tour leaves behind, for errands to start from without driving it again
    (``reset(options={"tour": state})``): one tour serves every track of a building, and each
    track's errands are the ones a tour of its own would have given it.

    Attributes:
        record: the :class:`TourRecord`.
        recognizer: the recognizer with the tour's map (a copy; ``None`` for the true rooms).
        truth: the true rooms bound to the building (``None`` for a recognizer).
        rooms: (T,) the true room of each tour step, for scoring.
        pose: the robot's (x, y, heading) at the tour's end.
        room: the last room the robot was in.
        nav: the simulator where the tour left it
            (:class:`~envs.tasks.place_nav.NavSnapshot`: the robot in motion, the random
            streams), so that the errands go on as after the tour itself.
        observation, info: the tour's last frame, as the tour's world returned it.
        place: the raw place of that frame.
        poses: (T, 3) the robot's true pose at each tour step (None in a state kept before
            0.16.0), where image goals are drawn.
    """

    record: TourRecord
    recognizer: Any
    truth: Any
    rooms: np.ndarray
    pose: np.ndarray
    room: int
    nav: Any
    observation: dict[str, Any]
    info: dict[str, Any]
    place: int
    poses: np.ndarray | None = None


@dataclass
class Errand:
    """One errand's outcome: ``success``, ``steps``, ``path`` driven and ``shortest`` walking
    distance (m) from its start to the goal room, and ``spl`` (Anderson et al. 2018); ``extra``
    what the errand's kind of goal adds (an image goal: ``final_distance``, the walking
    distance (m) left when it ended, and the goal's place and tour step)."""

    goal: str
    success: bool = False
    steps: int = 0
    path: float = 0.0
    shortest: float = 0.0
    redrawn: bool = False
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def spl(self) -> float:
        return float(self.success) * self.shortest / max(self.shortest, self.path, 1e-9)

    def as_dict(self) -> dict[str, Any]:
        return {"goal": self.goal, "success": self.success, "steps": self.steps,
                "path": self.path, "shortest": self.shortest, "spl": self.spl,
                "redrawn": self.redrawn, **self.extra}
