"""What a learned errand agent observes: where the goal is, as each kind of agent can know it.

Place ids and room names mean something different in every building, so an agent that is to
work in buildings it has never seen cannot be given them as they are. :class:`TourFeatures`
turns ``PlaceNav-GuidedTour-v1``'s observation into a vector that means the same everywhere,
built from the guided tour: the tour's path is dead-reckoned from its odometry and compass
(:func:`~envs.agents.teach_repeat.dead_reckon`) and becomes a roadmap
(:class:`~envs.agents.roadmap.Roadmap`, a node every :data:`NODE_SPACING` metres), a
goal is the point where the guide named its room, and a place is the mean of the tour's
positions in it. From an estimate of where the robot is, the agent is told the way to the goal
along the tour's roadmap: a point :data:`AHEAD` metres on (the "carrot" of pure pursuit) and
how far the goal is by that way. Three kinds of agent, each seeing all that the one before
sees (``noplace`` ⊂ ``place`` ⊂ ``oracle``, but for ``oracle``'s corrected dead reckoning),
differing in where the estimate comes from:

- ``noplace``: rangefinders, odometry, compass, and the way from dead reckoning since the
  tour, while that is known (it is lost when the robot is carried to an errand's start);
- ``place``: also the way from the recognizer's place (the place's tour position, then dead
  reckoning since the place was entered), whether this is the goal's place, and whether
  the place just changed;
- ``oracle``: also the same from the true room instead of the place; and its dead reckoning
  since the tour is corrected by the truth: re-anchored where the tour crossed between two
  rooms whenever the robot moves between them.

The correction is what makes ``oracle`` the upper bound. Wheel odometry slips while the robot
pushes against a wall, so a learned policy's dead reckoning drifts errand after errand (metres
by the last of 20: ``python -m train.drift``), while re-anchored at each door it stays within
about 0.2 m (median). Uncorrected, ``oracle`` would see a drifting way block beside one that
does not drift, with nothing to say which to trust. ``place`` is not corrected by its places:
snapping to where the tour's reports changed placed the planner worse than the drift
(``docs/design.md``), so whether place ids can undo drift is left for the agent to learn. A
carry loses dead reckoning for every agent.

Each way block is the carrot's offset in the robot's frame (forward, left, in units of
:data:`AHEAD`), the distance left along the roadmap (units of :data:`SCALE` metres), all
clipped to [-2, 2], and how well the estimate is known: 1 from dead reckoning or anchored
where the tour crossed into the place, 0.5 at the place's mean position, zeros when not.
``place`` with a recognizer that is right about every room gives ``oracle``'s room block, so
the two agents differ only by what recognition gets wrong.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> from envs.agents.tour_features import TourFeatures, n_features
    >>> env = TourFeatures(gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3,
    ...                              n_errands=1, tour_steps_per_room=40), senses="place")
    >>> obs, info = env.reset(seed=0)
    >>> obs.shape == (n_features("place"),) and obs in env.observation_space
    True
    >>> env.close()
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from placeclust.protocol import resolve

from ..world.robot import MAX_RANGE, MAX_SPEED, MAX_TURN, N_RANGES
from .hints import unknown_place
from .roadmap import Roadmap
from .teach_repeat import dead_reckon

#: the kinds of agent, each seeing what the one before sees and more
SENSES = ("noplace", "place", "oracle")
#: metres per unit of a distance left (a 6-room building is about 15 m across)
SCALE = 10.0
#: metres from the robot's nearest roadmap point to the carrot, along the way to the goal
AHEAD = 1.0
#: metres between roadmap nodes, and the farthest two nodes are joined across (a door passed
#: twice); no place labels, so that every kind of agent sees the same roadmap
NODE_SPACING, JOIN = 0.2, 0.3
#: rangefinders, odometry (2), compass (2), the way from dead reckoning (4)
N_BASE = N_RANGES + 2 + 2 + 4
#: the way from a place (4), at the goal's place, the place just changed
N_PLACE = 6


def n_features(senses: str) -> int:
    """The length of :class:`TourFeatures`' observation for ``senses``."""
    return N_BASE + N_PLACE * SENSES.index(_check(senses))


def _check(senses: str) -> str:
    if senses not in SENSES:
        raise ValueError(f"unknown senses {senses!r}; choose one of {SENSES}")
    return senses


def way_block(route: Roadmap | None, goal: int | None, position: np.ndarray | None,
              yaw: float, known: float = 1.0) -> list[float]:
    """The carrot's offset from ``position`` in the robot's frame (forward, left; units of
    :data:`AHEAD`) and the distance left (units of :data:`SCALE`), clipped to [-2, 2], and
    ``known`` (how well the position is known); four zeros if the goal or the position is
    unknown."""
    if route is None or goal is None or position is None:
        return [0.0, 0.0, 0.0, 0.0]
    carrot, left = route.way(goal, position, AHEAD)
    dx, dy = (carrot - position) / AHEAD
    c, s = math.cos(yaw), math.sin(yaw)
    ahead, side = c * dx + s * dy, -s * dx + c * dy
    return [*np.clip([ahead, side, left / SCALE], -2.0, 2.0).tolist(), known]


class Anchored:
    """A position estimate re-anchored on labelled places, plus the odometry since: on moving
    from place ``a`` to ``b``, where the tour crossed between them (a door, for rooms); on
    the first place after being lost, or a crossing the tour never made, the mean of the
    tour's positions in ``b``. Unknown until a label with a tour position is seen.

    Args:
        centres: label -> the mean tour position (m) of the steps with that label.
        crossings: (a, b) with a < b -> the mean tour position where it went between them.
    """

    def __init__(self, centres: dict[int, np.ndarray],
                 crossings: dict[tuple[int, int], np.ndarray] | None = None) -> None:
        self.centres = centres
        self.crossings = crossings or {}
        self.label: int | None = None
        self.position: np.ndarray | None = None
        self.changed = False
        self.precise = False  # anchored at a crossing, not at a place's mean

    def lose(self) -> None:
        """Forget the label and the position (the robot was carried elsewhere)."""
        self.label, self.position, self.precise = None, None, False

    def update(self, label: int, moved: np.ndarray) -> None:
        """One step: the robot moved by ``moved`` (m) and is now in ``label`` (-1: none)."""
        self.changed = label >= 0 and label != self.label
        if self.changed:
            before, self.label = self.label, label
            pair = None if before is None else (min(before, label), max(before, label))
            anchor = None if pair is None else self.crossings.get(pair)
            self.precise = anchor is not None
            if anchor is None:
                anchor = self.centres.get(label)
            self.position = None if anchor is None else anchor.copy()
        elif self.position is not None:
            self.position = self.position + moved


class TourFeatures(gym.Wrapper):
    """``PlaceNav-GuidedTour-v1`` seen as a fixed-length vector that means the same in every
    building (the module's table), for an agent that acts by itself, without a planner.

    Args:
        env: a ``PlaceNav-GuidedTour-v1`` env (wrapped or not).
        senses: one of :data:`SENSES`. ``oracle`` reads the true room from ``info``: it is the
            upper bound, not an agent a robot could run.
        repeat: env steps each action is held for (the recognizer still sees every frame);
            fewer decisions per metre make the credit for a turn easier to assign. An errand's
            end, or the episode's, ends the repeat early.

    The observation is ``Box(-2, 2, (n_features(senses),))``; the action, reward and episode
    are the env's.
    """

    def __init__(self, env: gym.Env, senses: str = "place", repeat: int = 1) -> None:
        super().__init__(env)
        self.senses = _check(senses)
        if repeat < 1:
            raise ValueError(f"repeat must be at least 1 step, got {repeat}")
        self.repeat = repeat
        self.unknown = unknown_place(env)
        self.observation_space = spaces.Box(-2.0, 2.0, (n_features(senses),), np.float32)
        self._route: Roadmap | None = None
        self._goals: dict[str, int] = {}
        self._tour_labels: dict[str, dict[str, int]] = {}
        self._trackers: dict[str, Anchored] = {}
        self._position: np.ndarray | None = None
        self._heading = np.array([1.0, 0.0])
        self._dt = 0.1  # the tour's seconds per step, read at reset
        self._errand = 0
        self._room = -1

    @property
    def position(self) -> np.ndarray | None:
        """The agent's dead reckoning (m, in the frame of the tour's path): since the tour,
        re-anchored at the doors for ``oracle``; ``None`` once a carry has lost it."""
        return self._position

    def reset(self, **kwargs: Any) -> tuple[np.ndarray, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        tour = info["tour"]
        path = dead_reckon(tour.odometry, tour.heading, tour.control_dt)
        self._dt = tour.control_dt
        said = [(t, str(name)) for t, name in enumerate(tour.heard) if name]
        self._route = Roadmap(path, spacing=NODE_SPACING, join=JOIN)
        self._goals = {name: self._route.node_of_step(t) for t, name in said}
        kinds = ("place", "room")[:SENSES.index(self.senses)]
        labels = {"place": np.asarray(tour.place_id)}
        if "room" in kinds:  # the oracle's ground truth, never in the observation
            task: Any = self.env.unwrapped  # PlaceNav-GuidedTour-v1
            labels["room"] = np.asarray(task.tour_rooms)
        self._tour_labels = {k: {name: int(labels[k][t]) for t, name in said} for k in kinds}
        self._trackers = {k: Anchored(_centres(labels[k], path), _crossings(labels[k], path))
                          for k in kinds}
        self._position, self._heading = path[-1].copy(), np.asarray(obs["heading"], float)
        self._errand, self._room = 0, int(info["room_id"])
        self._new_errand()
        return self._features(obs, info, np.zeros(2)), info

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        total = 0.0
        for _ in range(self.repeat):
            features, reward, terminated, truncated, info = self._one_step(action)
            total += reward
            if terminated or truncated or "errand_result" in info:
                break
        return features, total, terminated, truncated, info

    def _one_step(self, action: np.ndarray
                  ) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        heading = np.asarray(obs["heading"], float)
        # this step's displacement, integrated as the tour's path was
        moved = dead_reckon(np.stack([np.zeros(2), obs["odometry"]]),
                            np.stack([self._heading, heading]), self._dt)[1]
        self._heading = heading
        if info["errand"] != self._errand:
            self._errand = info["errand"]
            if self._new_errand():
                moved = np.zeros(2)  # the odometry does not span the carry
        if self._position is not None:
            self._position = self._position + moved
        return self._features(obs, info, moved), float(reward), terminated, truncated, info

    def _new_errand(self) -> bool:
        """Whether the robot was carried to the errand's start; if so, all is lost."""
        carried = getattr(self.env.unwrapped, "errand_start", "continue") == "carried"
        if carried:
            self._position = None
            for tracker in self._trackers.values():
                tracker.lose()
        return carried

    def _labels(self, info: dict[str, Any]) -> dict[str, int]:
        out = {}
        if "place" in self._trackers:
            raw = int(info["place_id"])
            recognizer = getattr(self.env.unwrapped, "recognizer", None)
            if raw >= 0 and recognizer is not None:  # the tour's ids are resolved ones
                raw = int(resolve(recognizer, np.array([raw]))[0])
            out["place"] = raw if 0 <= raw < self.unknown else -1
        if "room" in self._trackers:
            if info["room_id"] >= 0:  # a doorway belongs to the room being left
                self._room = int(info["room_id"])
            out["room"] = self._room
        return out

    def _features(self, obs: dict[str, Any], info: dict[str, Any], moved: np.ndarray
                  ) -> np.ndarray:
        goal_name = str(obs["goal"])
        goal = self._goals.get(goal_name)
        yaw = math.atan2(float(obs["heading"][1]), float(obs["heading"][0]))
        odometry = np.clip(np.asarray(obs["odometry"], float) / (MAX_SPEED, MAX_TURN), -2, 2)
        labels = self._labels(info)
        for kind, label in labels.items():
            self._trackers[kind].update(label, moved)
        room = self._trackers.get("room")  # the oracle's: the truth corrects its drift
        if (self._position is not None and room is not None and room.changed and room.precise
                and room.position is not None):
            self._position = room.position.copy()  # where the tour crossed between the rooms
        parts: list[Any] = [np.asarray(obs["ranges"], float) / MAX_RANGE, odometry,
                 np.asarray(obs["heading"], float),
                 way_block(self._route, goal, self._position, yaw)]
        for kind, label in labels.items():
            tracker = self._trackers[kind]
            target = self._tour_labels[kind].get(goal_name, -2)
            # known: 1 anchored where the tour crossed into this place, 0.5 at its mean
            parts.append(way_block(self._route, goal, tracker.position, yaw,
                                   1.0 if tracker.precise else 0.5))
            parts.append([float(label >= 0 and label == target), float(tracker.changed)])
        return np.concatenate(parts).astype(np.float32)


def _centres(labels: np.ndarray, path: np.ndarray) -> dict[int, np.ndarray]:
    """The mean tour position of each label's steps (labels below 0 are none)."""
    return {int(k): path[labels == k].mean(axis=0) for k in np.unique(labels) if k >= 0}


def _crossings(labels: np.ndarray, path: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """Where the tour went from one label to another (labels below 0, a doorway, skipped):
    the mean, over its crossings either way, of the midpoint between the last step of one
    and the first of the other."""
    points: dict[tuple[int, int], list[np.ndarray]] = {}
    last, at = -1, 0
    for t, label in enumerate(labels):
        if label < 0:
            continue
        if last >= 0 and label != last:
            pair = (min(last, label), max(last, label))
            points.setdefault(pair, []).append((path[at] + path[t]) / 2)
        last, at = int(label), t
    return {pair: np.mean(p, axis=0) for pair, p in points.items()}
