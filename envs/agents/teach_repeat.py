"""A topological planner that learns its map from the guided tour, for ``PlaceNav-GuidedTour-v1``.

Teach and repeat (Furgale & Barfoot 2010) on the recognizer's own places. The tour is the teach
pass: the planner dead-reckons the tour's path from odometry and compass, and keeps, for every
pair of places the recognizer moved between, the stretches of path where the tour crossed from
one to the other. Names attach to the place the recognizer reported when the guide spoke. An
errand is the repeat pass: the shortest path on the place graph from the current place to a
place carrying the goal's name, each hop driven by replaying the nearest stretch of the tour
that crossed it (forwards, or backwards when the tour crossed the other way), reached along
the tour's own path through the current place (or along the whole tour's path where the place's
own steps do not lead there). The recognizer decides where the goal is and which way to go;
odometry only drives each hop, which ends when the recognizer reports the next place or the
replayed stretch runs out. Two places the tour drove within ``OVERLAP`` of each
other are neighbours (a room the recognizer split in two). With ids that mean nothing the graph
means nothing, and the planner is lost; without ids (``UNKNOWN`` everywhere) it explores.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> from envs.agents.teach_repeat import TourPlanner
    >>> env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3, n_errands=1,
    ...                tour_steps_per_room=40)
    >>> obs, info = env.reset(seed=0)
    >>> planner = TourPlanner(unknown=env.unwrapped.max_places)
    >>> planner.reset(info["tour"], obs)
    >>> done = False
    >>> while not done:
    ...     obs, reward, done, _, info = env.step(planner.act(obs))
    >>> info["errands"][0]["success"]
    True
    >>> env.close()
"""

from __future__ import annotations

import math
from collections import deque

import networkx as nx
import numpy as np
from scipy.spatial.distance import cdist

from ..tasks.tour import WaypointController
from ..world.robot import N_RANGES
from .roadmap import Roadmap
from .topological import steer

#: seconds of tour path before a crossing that a hop may join, and after it that it drives
RUN_UP, FOLLOW_THROUGH = 4.0, 2.0
WAYPOINT_SPACING = 0.2  # m between the waypoints of a replayed stretch
OVERLAP = 0.4  # m: two places whose tour paths came this close are neighbours
SAME_PLACE = 1.2  # m: steps of one place this close are joined on the roadmap
PASSED = 3  # places just left whose late reports are ignored


def dead_reckon(odometry: np.ndarray, heading: np.ndarray, dt: float,
                start: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """(T, 2) positions from forward speeds (``odometry[:, 0]``, m/s) and compass headings
    (cos, sin), integrated at the mean heading of each step; the first row is ``start``."""
    yaw = np.unwrap(np.arctan2(heading[:, 1], heading[:, 0]))
    mid = np.concatenate([[yaw[0]], (yaw[1:] + yaw[:-1]) / 2])
    step = dt * odometry[:, 0, None] * np.stack([np.cos(mid), np.sin(mid)], axis=1)
    step[0] = 0.0
    return np.asarray(start) + np.cumsum(step, axis=0)


class TourPlanner:
    """Drives to the place the guide named, along the place graph learnt on the tour.

    Args:
        unknown: the ``place_id`` observation's value for "unknown" (the env's ``max_places``).
        seed: for the exploration's random turns.

    Call :meth:`reset` with the tour record and the first observation of each episode, then
    :meth:`act` once per observation, that first one included.
    """

    def __init__(self, unknown: int, seed: int = 0) -> None:
        self.unknown = unknown
        self.rng = np.random.default_rng(seed)
        self.graph = nx.Graph()
        self.names: dict[str, int] = {}

    def reset(self, tour, obs: dict[str, np.ndarray]) -> None:
        """Learn the map from ``tour`` (a :class:`~envs.tasks.records.TourRecord`)."""
        self.dt = tour.control_dt
        self.path = dead_reckon(tour.odometry, tour.heading, self.dt)
        self.pos = self.path[-1].copy()
        self._at_reset = True
        self.yaw = self._yaw(obs)
        places = tour.place_id
        self.places = places
        self.graph = nx.Graph()
        self.stretches: dict[tuple[int, int], list[np.ndarray]] = {}
        self._learn_crossings(places)
        self._learn_overlaps(places)
        self._learn_roadmap()
        self.place = int(places[places >= 0][-1]) if (places >= 0).any() else -1
        # hops weigh the distance between the places' centres on the tour, so the shortest
        # route is the shortest drive, not the fewest places
        centre = {p: self.path[places == p].mean(axis=0) for p in self.graph.nodes}
        for a, b in self.graph.edges:
            self.graph.edges[a, b]["weight"] = float(np.linalg.norm(centre[a] - centre[b]))
        self.names = {str(n): self._named_place(t) for t, n in enumerate(tour.heard) if n}
        self._hop: tuple[int, int] | None = None
        self._passed: deque[int] = deque(maxlen=PASSED)  # places just left: reports ignored
        self._goal = ""
        self._controller: WaypointController | None = None

    def _named_place(self, t: int) -> int:
        """The place at step ``t``, or the nearest known one in time (the guide spoke while the
        recognizer had no answer)."""
        known = np.flatnonzero(self.places >= 0)
        if known.size == 0:
            return -1
        return int(self.places[known[np.argmin(np.abs(known - t))]])

    def act(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The action for one step of an errand."""
        self._dead_reckon(obs)
        self._check_pose(obs)
        place = int(obs["place_id"])
        if obs["goal"] != self._goal:  # a new errand: nothing left behind yet
            self._goal, self._passed = str(obs["goal"]), deque(maxlen=PASSED)
        along = self._hop is not None and place == self._hop[1]
        # believing itself at the goal while the errand goes on, the planner is wrong about
        # where it is: any report is worth more than that belief, a place just left included
        lost = self.place == self.names.get(self._goal, -1)
        if place not in (self.place, self.unknown) and place in self.graph \
                and (along or lost or place not in self._passed):
            # arriving where the hop led, the place left stays behind: a report of it (the
            # recognizer wavering at a boundary) must not turn the robot back
            if along:
                self._passed.append(self.place)
            else:
                self._passed.clear()
            self.place = place
        if self._hop is not None and self._controller is not None and self._controller.done:
            # replayed to its end: the tour was in b there, so the robot is taken to be in b
            # (a recognizer lags behind at a doorway, or keeps one of a room's places) until
            # the recognizer names a place it has not just replayed its way out of
            self._passed.append(self._hop[0])
            self.place, self._hop = self._hop[1], None
        hop = self._next_hop(self.names.get(self._goal, -1))
        if hop is not None and hop != self._hop:
            self._controller = self._replay(*hop)
        self._hop = hop
        if hop is None or self._controller is None:
            return steer(obs["heading"], obs["ranges"], None, self.rng)
        action = self._controller.action(np.array([*self.pos, self.yaw]))
        return guard(np.clip(action, -1.0, 1.0), obs["ranges"]).astype(np.float32)

    def _check_pose(self, obs: dict[str, np.ndarray]) -> None:
        """Where a subclass corrects the dead-reckoned pose before acting; this one trusts it."""

    @property
    def exploring(self) -> bool:
        """Whether the last action was a wander: no goal place, no route, or already there."""
        return self._hop is None or self._controller is None

    def _next_hop(self, goal: int) -> tuple[int, int] | None:
        if goal < 0 or self.place < 0 or self.place == goal:
            return None
        try:
            route = nx.shortest_path(self.graph, self.place, goal, weight="weight")
        except (nx.NetworkXNoPath, nx.NodeNotFound):
            return None
        return route[0], route[1]

    def _learn_crossings(self, places: np.ndarray) -> None:
        """A hop for every change of place on the tour, with the stretch of path around it:
        ``RUN_UP`` s before the change to ``FOLLOW_THROUGH`` s after, and the same stretch
        backwards for the hop the other way."""
        run_up, through = round(RUN_UP / self.dt), round(FOLLOW_THROUGH / self.dt)
        last_t, last = -1, -1
        for t, p in enumerate(places.tolist()):
            if p < 0:
                continue
            self.graph.add_node(p)
            if last >= 0 and p != last:
                end = len(self.path) - 1
                self._add_hop(last, p, np.arange(max(t - run_up, 0), min(t + through, end) + 1))
                self._add_hop(p, last, np.arange(min(t + run_up, end),
                                                 max(last_t - through, 0) - 1, -1))
            last_t, last = t, p

    def _learn_overlaps(self, places: np.ndarray, reach: float = OVERLAP) -> None:
        """A hop between two places the tour never crossed between but drove within ``reach``
        metres of each other in: one room the recognizer split in two, entered twice."""
        points = {p: np.flatnonzero(places == p)[::3] for p in self.graph.nodes}
        nodes = sorted(points)
        for i, a in enumerate(nodes):
            for b in nodes[i + 1:]:
                if self.graph.has_edge(a, b):
                    continue
                d = cdist(self.path[points[a]], self.path[points[b]])
                k = np.unravel_index(np.argmin(d), d.shape)
                if d[k] < reach:
                    ia, ib = points[a][k[0]], points[b][k[1]]
                    self._add_hop(a, b, np.array([ia, ib]))
                    self._add_hop(b, a, np.array([ib, ia]))

    def _learn_roadmap(self) -> None:
        """The tour's path as a graph of free space (:class:`~envs.agents.roadmap.Roadmap`):
        each step joined to the next, to any other step within ``OVERLAP`` metres (where the
        tour passed again), and to any step of the same place within ``SAME_PLACE`` metres (the
        recognizer says they are one room, with no wall between)."""
        self.roadmap = Roadmap(self.path, join=OVERLAP, places=self.places,
                               same_place=SAME_PLACE)

    def _add_hop(self, a: int, b: int, stretch: np.ndarray) -> None:
        """A hop a -> b driven through ``stretch``, indices of tour steps in driving order."""
        self.graph.add_edge(a, b)
        self.stretches.setdefault((a, b), []).append(stretch)

    def _replay(self, a: int, b: int) -> WaypointController | None:
        """Waypoints to the nearest stretch of tour that went from a to b, then along it.

        The way to the stretch keeps to where the tour drove in place a (:meth:`_approach`);
        which stretch, and so where the robot goes, is the place graph's choice.
        """
        stretches = self.stretches.get((a, b), [])
        if not stretches:
            return None
        run_up = round(RUN_UP / self.dt)
        steps = min(stretches, key=lambda s: np.linalg.norm(self.path[s] - self.pos,
                                                            axis=1).min())
        join = int(np.argmin(np.linalg.norm(self.path[steps[:run_up + 1]] - self.pos, axis=1)))
        approach = self._approach(a, int(steps[join]))
        points = _resample(self.path[np.concatenate([approach, steps[join:]])],
                           WAYPOINT_SPACING)
        return WaypointController([(x, y, 0.25) for x, y in points])

    def _approach(self, a: int, target: int) -> np.ndarray:
        """Tour steps from the robot to ``target``: along the roadmap of place a's steps from
        the one nearest the robot (inside the place, the way the tour drove), or, where those
        steps do not lead there (a place the recognizer spread over two rooms), along the whole
        roadmap from the tour step nearest the robot, never straight across rooms."""
        inside = np.flatnonzero(self.places == a)
        if inside.size:
            way = self.roadmap.route(self._nearest_step(inside), target,
                                     within={*inside.tolist(), target})
            if way is not None:
                return np.array(way[:-1], np.int64)
        way = self.roadmap.route(self._nearest_step(np.arange(len(self.path))), target)
        assert way is not None, "the tour's path joins every step to the next"
        return np.array(way[:-1], np.int64)

    def _nearest_step(self, steps: np.ndarray) -> int:
        """The one of tour ``steps`` whose dead-reckoned position is nearest the robot."""
        return int(steps[np.argmin(np.linalg.norm(self.path[steps] - self.pos, axis=1))])

    def _dead_reckon(self, obs: dict[str, np.ndarray]) -> None:
        if self._at_reset:  # the tour's last row already counted this observation's motion
            self._at_reset = False
            return
        yaw = self._yaw(obs)
        mid = self.yaw + 0.5 * math.remainder(yaw - self.yaw, math.tau)
        self.pos += self.dt * float(obs["odometry"][0]) * np.array([math.cos(mid), math.sin(mid)])
        self.yaw = yaw

    @staticmethod
    def _yaw(obs: dict[str, np.ndarray]) -> float:
        return math.atan2(float(obs["heading"][1]), float(obs["heading"][0]))


def guard(action: np.ndarray, ranges: np.ndarray, clearance: float = 0.12,
          slow: float = 0.3) -> np.ndarray:
    """``action`` with its forward (or backward) speed cut as the rangefinders facing that way
    read less than ``clearance + slow`` m, to zero at ``clearance``.

    Wheels pushing against a wall spin on the spot while their encoders report motion, which
    would corrupt the dead reckoning every hop relies on; the cut keeps them off walls.
    """
    k = N_RANGES // 2
    facing = ranges[[-1, 0, 1]] if action[0] >= 0 else ranges[[k - 1, k, k + 1]]
    scale = float(np.clip((facing.min() - clearance) / slow, 0.0, 1.0))
    return np.array([action[0] * scale, action[1]])


def _resample(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points along a polyline, ``spacing`` apart, ending at its last point."""
    keep = [points[0]]
    for p in points[1:]:
        if np.linalg.norm(p - keep[-1]) >= spacing:
            keep.append(p)
    if np.linalg.norm(points[-1] - keep[-1]) > 0:
        keep.append(points[-1])
    return np.array(keep)
