"""An agent that goes to the spot of an image goal and stops there (``PlaceNav-ImageGoal-v0``).

:class:`SpotPlanner` is the :class:`~envs.agents.relocalize.RelocalizingPlanner` with a target
inside the goal's place. The env tells it the place the recognizer gave the goal's picture
(``goal_place``); from the tour's record it picks the spot where a goal of that place most
likely is: the *medoid* of the tour's steps in that place (the step nearest, in sum, to all the
others, in the tour's dead-reckoned frame). Goals are drawn at the tour's own steps
(:mod:`envs.tasks.errand_goals`), so over the goals a place can hold, the medoid is the step
whose expected distance to the goal is smallest. The ceiling (``oracle-pose``) gives the
goal's own tour step instead (``goal_step``).

It drives as the relocalizer does: the place graph's hops to the goal's place (the recognizer
decides the way), then, in that place or wherever the graph leads no further, the tour's
roadmap to the target step, with the scan matcher correcting the dead reckoning all along.
It declares arrival (the action's third entry, 1) when it believes itself within
:data:`STOP_AT` of the target, or at the end of the roadmap's way. With no goal place it
cannot know where to go and stops at once, as an ImageNav agent gives up: ``none`` costs no
time. So a finer map pays: a place's medoid lies nearer each of its goals.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> env = gym.make("PlaceNav-ImageGoal-v0", recognizer="oracle-pose", n_rooms=3,
    ...                n_errands=2, tour_steps_per_room=60)
    >>> obs, info = env.reset(seed=0)
    >>> agent = SpotPlanner(unknown=env.unwrapped.max_places)
    >>> agent.reset(info["tour"], obs)
    >>> done = False
    >>> while not done:
    ...     obs, reward, done, _, info = env.step(agent.act(obs))
    >>> [e["success"] for e in info["errands"]], [e["final_distance"] < 1 for e in info["errands"]]
    ([True, True], [True, True])
    >>> env.close()
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.spatial.distance import cdist

from ..tasks.tour import WaypointController
from .relocalize import RelocalizingPlanner
from .teach_repeat import WAYPOINT_SPACING, _resample, guard

#: m: believed this close to its target, the agent declares arrival
STOP_AT = 0.3
#: tour steps of a place its medoid is chosen among (evenly spaced): the cost stays bounded
MEDOID_STEPS = 400
#: the action that declares arrival
ARRIVE = np.array([0.0, 0.0, 1.0], np.float32)


class SpotPlanner(RelocalizingPlanner):
    """Drives to the tour step where the goal's place most likely holds the goal, and stops.

    Args:
        unknown: the ``place_id`` (and ``goal_place``) observations' value for "unknown".
        seed: for the exploration's random turns.

    Call :meth:`reset` with the tour record and the first observation of each episode, then
    :meth:`act` once per observation.
    """

    def reset(self, tour, obs: dict[str, np.ndarray]) -> None:
        super().reset(tour, obs)
        self._medoids: dict[int, int] = {}
        self._errand_index = -1
        self.target: int | None = None  # the tour step it drives to
        self._way: WaypointController | None = None
        self._jumps = 0

    def spot(self, place: int) -> int | None:
        """The medoid of the tour's steps in ``place`` (module doc); None if it has none."""
        if place not in self._medoids:
            steps = np.flatnonzero(self.places == place)
            if steps.size == 0:
                return None
            steps = steps[np.linspace(0, steps.size - 1, min(steps.size, MEDOID_STEPS))
                          .astype(int)]
            points = self.path[steps]
            self._medoids[place] = int(steps[np.argmin(cdist(points, points).sum(axis=1))])
        return self._medoids[place]

    def act(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The action for one step of an errand: (forward, turn, arrive)."""
        k, place = int(obs["errand"]), int(obs["goal_place"])
        if k != self._errand_index:  # a new errand: aim at its spot
            self._errand_index, self._way = k, None
            step = int(obs["goal_step"])
            known = place != self.unknown and place >= 0
            self.target = (step if 0 <= step < len(self.path)
                           else self.spot(place) if known else None)
        goal = f"errand {k}"  # the planner's goal: the goal's place, under a name of its own
        self.names[goal] = place if place in self.graph else -1
        seen: dict[str, Any] = {**obs, "goal": goal}
        action = super().act(seen)  # dead reckoning, scan matching, hops
        if self.target is None:
            return ARRIVE  # no goal place: nowhere to go
        if self.lost:
            return np.append(action, -1.0).astype(np.float32)
        if self._way is None and not self.exploring:
            return np.append(action, -1.0).astype(np.float32)  # hops to the goal's place
        target = self.path[self.target]
        if math.dist(self.pos, target) < STOP_AT:
            return ARRIVE
        if self._way is None or self.relocalized != self._jumps:
            self._way, self._jumps = self._to_target(), self.relocalized
        if self._way.done:
            return ARRIVE
        drive = self._way.action(np.array([*self.pos, self.yaw]))
        drive = guard(np.clip(drive, -1.0, 1.0), obs["ranges"])
        return np.append(drive, -1.0).astype(np.float32)

    def _to_target(self) -> WaypointController:
        """Waypoints along the tour's roadmap from the step nearest the robot to the target."""
        assert self.target is not None
        start = self._nearest_step(np.arange(len(self.path)))
        way = self.roadmap.route(start, self.target) or [self.target]
        points = _resample(np.vstack([self.pos, self.path[way]]), WAYPOINT_SPACING)[1:]
        return WaypointController([(x, y, 0.2) for x, y in points])
