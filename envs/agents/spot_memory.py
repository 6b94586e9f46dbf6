"""The spot agent with a memory of its errands: every place it has seen has a spot (placenav-v5).

:class:`~envs.agents.spot.SpotPlanner` knows a place only from the tour: a goal picture that the
recognizer puts in a place the map opened during the errands (a night frame's place, on a
learning map) has no tour step, so that agent has nowhere to go and declares arrival where it
stands. :class:`SpotMemoryPlanner` also remembers where it was at every step of every errand,
by its own dead reckoning and scan matching (the tour's frame), with the place the recognizer
reported there. A place's spot is the medoid of its tour steps, as before, or, for a place
the tour never reported, the medoid of the positions where the errands did. A goal place it
has never seen at all it looks for, wandering, until the recognizer reports it. So it declares
arrival only where it believes a spot is: on an errand's first step only if it already stands
there. With no goal place (a recognizer that cannot rank and did not know the picture) it
stops at once, as an ImageNav agent gives up; ``placenav-v5`` counts those as unknown.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> env = gym.make("PlaceNav-ImageGoal-v1", recognizer="oracle-pose", n_rooms=3,
    ...                n_errands=2, tour_steps_per_room=60)
    >>> obs, info = env.reset(seed=0)
    >>> agent = SpotMemoryPlanner(unknown=env.unwrapped.max_places)
    >>> agent.reset(info["tour"], obs)
    >>> done = False
    >>> while not done:
    ...     obs, reward, done, _, info = env.step(agent.act(obs))
    >>> [e["success"] for e in info["errands"]]
    [True, True]
    >>> env.close()
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..tasks.image_goal import medoid
from ..tasks.tour import WaypointController
from .relocalize import RelocalizingPlanner
from .spot import ARRIVE, STOP_AT
from .teach_repeat import WAYPOINT_SPACING, _resample, guard


class SpotMemoryPlanner(RelocalizingPlanner):
    """Drives to the spot of the goal's place, from the tour or from its own errands, and
    stops there (the module's rules).

    Args:
        unknown: the ``place_id`` (and ``goal_place``) observations' value for "unknown".
        seed: for the exploration's random turns.
    """

    def reset(self, tour, obs: dict[str, np.ndarray]) -> None:
        super().reset(tour, obs)
        self._errand_index = -1
        self.target: np.ndarray | None = None  # the point (x, y) it drives to
        self._way: WaypointController | None = None
        self._jumps = 0
        self._tour_spots: dict[int, np.ndarray] = {}
        #: place -> where it was (its belief) at the errand steps where that place was reported
        self.memory: dict[int, list[tuple[float, float]]] = {}

    def spot(self, place: int) -> np.ndarray | None:
        """The spot of ``place``: the medoid of its tour steps, else of the errand positions
        where it was reported; None where it was never reported."""
        if place not in self._tour_spots:
            steps = np.flatnonzero(self.places == place)
            if steps.size:
                self._tour_spots[place] = self.path[steps[medoid(self.path[steps])]]
        if place in self._tour_spots:
            return self._tour_spots[place]
        if place not in self.memory:
            return None
        seen = np.array(self.memory[place])
        return seen[medoid(seen)]

    def act(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The action for one step of an errand: (forward, turn, arrive)."""
        k, place = int(obs["errand"]), int(obs["goal_place"])
        if k != self._errand_index:  # a new errand: its target is decided below
            self._errand_index, self._way, self.target = k, None, None
        goal = f"errand {k}"  # the planner's goal: the goal's place, under a name of its own
        self.names[goal] = place if place in self.graph else -1
        seen: dict[str, Any] = {**obs, "goal": goal}
        action = super().act(seen)  # dead reckoning, scan matching, hops
        if not self.lost and int(obs["place_id"]) != self.unknown:
            self.memory.setdefault(int(obs["place_id"]), []).append(
                (float(self.pos[0]), float(self.pos[1])))
        if place == self.unknown or place < 0:
            return ARRIVE  # no goal place: nowhere to go
        if self.target is None:
            self.target = self._target(place, int(obs["goal_step"]))
        if self.target is None or self.lost or (self._way is None and not self.exploring):
            # looking for a place never seen, lost, or hopping along the graph to the place
            return np.append(action, -1.0).astype(np.float32)
        if math.dist(self.pos, self.target) < STOP_AT:
            return ARRIVE
        if self._way is None or self.relocalized != self._jumps:
            self._way, self._jumps = self._to_point(self.target), self.relocalized
        if self._way.done:
            return ARRIVE
        drive = self._way.action(np.array([*self.pos, self.yaw]))
        drive = guard(np.clip(drive, -1.0, 1.0), obs["ranges"])
        return np.append(drive, -1.0).astype(np.float32)

    def _target(self, place: int, step: int) -> np.ndarray | None:
        """The goal's own tour step where the env gives it (the ceiling), else the place's
        spot."""
        if 0 <= step < len(self.path):
            return self.path[step].copy()
        return self.spot(place)

    def _to_point(self, target: np.ndarray) -> WaypointController:
        """Waypoints along the tour's roadmap from the step nearest the robot to the step
        nearest ``target``, then to ``target``."""
        every = np.arange(len(self.path))
        start = self._nearest_step(every)
        end = int(np.argmin(np.linalg.norm(self.path - target, axis=1)))
        way = self.roadmap.route(start, end) or [end]
        points = _resample(np.vstack([self.pos, self.path[way], target]), WAYPOINT_SPACING)[1:]
        return WaypointController([(x, y, 0.2) for x, y in points])
