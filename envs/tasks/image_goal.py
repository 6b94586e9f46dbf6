"""``PlaceNav-ImageGoal-v1``: errands to pictures whose verdict is the recognizer's (placenav-v5).

``PlaceNav-ImageGoal-v0`` (v3, v4) let the agent's rules and the goal draw decide much of what it
reported: a goal came from the episode's stream after however many draws the robot's last stop
took, so two recognizers ran different errands after the first; a goal picture below the
recognizer's threshold was unknown and stopped the errand. This version changes what the task
decides and nothing else (same tour, rewards, success within ``success_radius`` of walking):

- **The same goals for every recognizer and agent.** Goal ``k`` comes from its own stream,
  ``numpy.random.default_rng([goal seed, scene_seed, k])``, the goal seed being ``reset``'s
  seed, so no recognizer's answer or robot's stop moves it. It is a tour step inside a room
  drawn uniformly, its position moved up to ``goal_offset`` metres off the route (uniform in the
  disc, where the robot fits, in the same room), turned to a uniform heading. Where the errands
  continue, it lies in another room than goal ``k - 1`` and at least
  ``max(min_errand_distance, 2 * success_radius)`` of walking from it: from where a perfect
  agent would stand, not from where this one stopped (the first goal: from the errands' start,
  the tour's end). A carried errand's start is drawn from the goal's stream too.
- **No abstention by rule.** A recognizer that ranks places (``rank_places``,
  :func:`placeclust.protocol.can_rank`) names its best-ranked place for every picture, under
  its threshold too; one that cannot rank localizes as before (``localize_one``, else
  ``predict_one``) and may say unknown.
- **A compass like a robot's**: ``compass`` names a gyro
  (:class:`envs.world.robot.GyroCompass`, default ``"mpu9250"``), whose heading error runs on
  from the tour's first step through every errand; the tour record's ``heading`` carries it as
  the observations do.
- **Where success was lost**, in each errand's record: ``goal_pose`` and ``goal_room`` (the same
  for every recognizer), ``goal_place`` (−1 unknown), and for the goal's place on the tour's
  map: ``named_room`` (one of its tour frames is in the goal's room), ``named_fine`` (one lies
  within ``success_radius`` of walking of the goal) and ``spot_within`` (its spot, the medoid of
  its tour frames' true positions, does): :mod:`envs.runs.decomposition` tabulates them.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> env = gym.make("PlaceNav-ImageGoal-v1", recognizer="oracle", n_rooms=3, n_errands=2,
    ...                tour_steps_per_room=40)
    >>> obs, info = env.reset(seed=0)
    >>> sorted(obs) == sorted(["place_id", "goal_place", "goal_step", "errand", "odometry",
    ...                        "heading", "ranges"])
    True
    >>> env.unwrapped.compass.spec is not None                 # the MPU-9250's heading
    True
    >>> env.close()
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.envs.registration import register, registry
from scipy.spatial.distance import cdist

from placeclust.protocol import place_of, resolve

from ..world.changes import clear_pose
from ..world.robot import RADIUS, GyroCompass, reading
from .errand_draws import CARRY_DRAWS
from .errand_goals import GOAL_DRAWS, Goal, ImageGoals, TourTask
from .guided_tour import GuidedTourEnv
from .records import TourRecord, TourState

#: tour steps of a place its spot (medoid) is chosen among, evenly spaced (as the spot agent)
MEDOID_STEPS = 400
#: tries at moving a goal off the route before it stays on it
OFFSET_DRAWS = 20


def medoid(points: np.ndarray) -> int:
    """The index of the point nearest, in sum, to all the others: a place's spot, chosen among
    :data:`MEDOID_STEPS` of them evenly spaced (the spot agent's rule,
    :class:`~envs.agents.spot.SpotPlanner`)."""
    keep = np.linspace(0, len(points) - 1, min(len(points), MEDOID_STEPS)).astype(int)
    return int(keep[np.argmin(cdist(points[keep], points[keep]).sum(axis=1))])


class SharedImageGoals(ImageGoals):
    """Image goals from a stream of their own (the module's rules), localized by rank where the
    recognizer ranks, each with what the tour's map knew of it.

    ``seed`` (set by the env at each reset) and the building's ``scene_seed`` fix every goal.
    """

    kind = "image"

    def __init__(self, env: TourTask, success_reward: float, step_cost: float,
                 shaping: float, radius: float, offset: float, scene_seed: int) -> None:
        super().__init__(env, success_reward, step_cost, shaping, radius)
        if not offset >= 0:
            raise ValueError(f"goal_offset must be 0 or more metres, got {offset}")
        self.offset, self.scene_seed, self.seed = float(offset), int(scene_seed), 0
        self._anchor: tuple[np.ndarray, int] = (np.zeros(3), -1)
        #: what the tour's map knew of the last goal's place (:meth:`_known`)
        self.known: dict[str, Any] = {}

    def stream(self, k: int, part: int = 0) -> np.random.Generator:
        """Goal ``k``'s random stream (``part`` 1: its carried start's; ``k`` 0, ``part`` 2:
        the compass's)."""
        return np.random.default_rng([self.seed, self.scene_seed, k, part])

    def draw(self, env: TourTask, k: int, info: dict[str, Any], room: int,
             named: list[str], fixed: list[str]) -> Goal:
        if k == 0:  # the errands' start: the tour's end, the same for every recognizer
            self._anchor = (np.asarray(info["pose"], float), room)
        rng = self.stream(k)
        t, redrawn = self._step(env, rng)
        goal_room = int(env.tour_rooms[t])
        pose = self._off_route(env, rng, env.tour_poses[t], goal_room)
        goal = Goal(goal_room, env.plan.rooms[goal_room].name, redrawn, pose, t)
        self._anchor = (pose, goal_room)
        self.image = self._picture(env, pose)
        goal.place = self._localize(env, goal)
        self.known = self._known(env, goal)
        return goal

    def outcome(self, pose: Sequence[float], room: int) -> dict[str, Any]:
        assert self.goal is not None and self.goal.pose is not None
        return {**super().outcome(pose, room), "goal_pose": self.goal.pose.tolist(),
                "goal_room": self.goal.room, **self.known}

    def _step(self, env: TourTask, rng: np.random.Generator) -> tuple[int, bool]:
        """The tour step goal's drawn at: of :data:`GOAL_DRAWS` draws the first in another
        room than the last goal and far enough from it (any, where carried), else the
        farthest; and whether the first draw was not it."""
        steps = np.flatnonzero(env.tour_rooms >= 0)
        far = max(env.min_errand_distance, 2 * self.radius)
        anchor, anchor_room = self._anchor
        best: tuple[float, int] = (-1.0, int(steps[0]))
        for i in range(GOAL_DRAWS):
            t = int(steps[int(rng.integers(len(steps)))])
            if env.errand_start == "carried":
                return t, False
            d = self.walk(anchor, env.tour_poses[t], anchor_room, int(env.tour_rooms[t]))
            if d >= far and int(env.tour_rooms[t]) != anchor_room:
                return t, i > 0
            best = max(best, (d, t))
        return best[1], True

    def _off_route(self, env: TourTask, rng: np.random.Generator, at: np.ndarray,
                   room: int) -> np.ndarray:
        """A pose up to :attr:`offset` from ``at`` (uniform in the disc) where the robot fits
        in the errands' world, in ``room``; ``at`` itself (moved off furniture) if none of
        :data:`OFFSET_DRAWS` fits. The heading is uniform."""
        plan = env.nav.plan
        x, y, _ = clear_pose(plan, at)
        for _ in range(OFFSET_DRAWS if self.offset > 0 else 0):
            r = self.offset * math.sqrt(rng.uniform())
            a = rng.uniform(-math.pi, math.pi)
            px, py = x + r * math.cos(a), y + r * math.sin(a)
            if plan.room_at(px, py) == room and plan.is_free(px, py, RADIUS + 0.05):
                x, y = px, py
                break
        return np.array([x, y, float(rng.uniform(-math.pi, math.pi))])

    def _localize(self, env: TourTask, goal: Goal) -> int:
        """The true rooms' answer (a calibration oracle's own), else the recognizer's
        (:func:`placeclust.protocol.place_of`: its best-ranked place where it ranks). A
        recognizer that reads no images cannot see the picture: its answer is a guess, a place
        of its map drawn from the goal's stream (``random``; none without places), not its
        next answer, which would follow the robot (``random`` holds an id for a second: the
        place it just stopped in, again)."""
        if env.bound_truth is not None or env.recognizer is None:
            return super()._localize(env, goal)
        if self.image is None:
            places = sorted(env.recognizer.graph.nodes)
            guess = self.stream(len(env.errands), part=3)
            return int(places[int(guess.integers(len(places)))]) if places else -1
        return place_of(env.recognizer, self.image)

    def _known(self, env: TourTask, goal: Goal) -> dict[str, Any]:
        """What the tour's map knew of the goal's place: ``named_room``, ``named_fine`` and
        ``spot_within`` (the module's doc), and whether the place is ``unknown``."""
        assert goal.pose is not None
        places = getattr(env, "tour_places", np.zeros(0, np.int64))
        unknown = not 0 <= goal.place < env.max_places
        steps = np.flatnonzero(places == goal.place) if not unknown else np.zeros(0, int)
        out = {"unknown": unknown, "named_room": bool((env.tour_rooms[steps] == goal.room).any()),
               "named_fine": False, "spot_within": False}
        if steps.size == 0:
            return out
        walks = [self._walk_to(goal, env, int(t)) for t in steps]
        out["named_fine"] = bool(min(walks) <= self.radius)
        spot = steps[medoid(env.tour_poses[steps, :2])]  # the spot agent's, in true positions
        out["spot_within"] = bool(walks[list(steps).index(spot)] <= self.radius)
        return out

    def _walk_to(self, goal: Goal, env: TourTask, t: int) -> float:
        """Walking distance from the goal to tour step ``t`` (a doorway's step: in the room
        whose rectangle holds it)."""
        assert goal.pose is not None
        pose, room = env.tour_poses[t], int(env.tour_rooms[t])
        if room == goal.room:  # within a room the straight line: no graph search per step
            return math.dist(goal.pose[:2], pose[:2])
        return self.walk(goal.pose, pose, goal.room, None if room < 0 else room)


class ImageGoalEnv(GuidedTourEnv):
    """``PlaceNav-GuidedTour-v1`` with image goals as the module says (``PlaceNav-ImageGoal-v1``).

    Arguments beyond ``PlaceNav-ImageGoal-v0``'s: ``goal_offset`` (0.5 m: how far off the
    taught route a goal picture is taken, at most) and ``compass`` (``"mpu9250"``, or
    ``"ideal"`` for the true heading; :data:`~envs.world.robot.COMPASSES`). ``goal_kind`` is
    always ``"image"``. Observations, actions, rewards and info are v0's; each errand's
    record adds the goal's pose and room and the tour map's knowledge of its place.
    """

    def __init__(self, goal_offset: float = 0.5, compass: str = "mpu9250",
                 **kwargs: Any) -> None:
        kwargs["goal_kind"] = "image"
        super().__init__(**kwargs)
        # pickle and deepcopy rebuild the env from its own arguments, as the tour env's
        gym.utils.EzPickle.__init__(self, goal_offset=goal_offset, compass=compass, **kwargs)
        GyroCompass.part(compass, 1.0, 0)  # a ValueError naming the compasses, now
        self.compass_name = compass
        v0 = self.goals
        assert isinstance(v0, ImageGoals)
        self.goals = SharedImageGoals(self, v0.success_reward, v0.step_cost, v0.shaping,
                                      v0.radius, goal_offset, int(kwargs.get("scene_seed", 0)))
        self.goal_room = self.goals.goal_room
        self._dt = self.nav.model.opt.timestep * self.nav.n_substeps
        self.compass = GyroCompass.part(compass, self._dt, 0)
        self._clock = 0  # control steps since the tour began: the compass's time

    @property
    def tour_places(self) -> np.ndarray:
        """The tour's place ids as the map holds them now (ids merged since resolved)."""
        if self._tour is None:
            return np.zeros(0, np.int64)
        places = np.asarray(self._tour.place_id)
        return places if self.recognizer is None else resolve(self.recognizer, places)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        goals = self.goals
        assert isinstance(goals, SharedImageGoals)
        # the goals' stream: the seed itself, or (a reset without one) the next of the
        # episodes' stream, which the last seeded reset fixed
        goals.seed = int(seed) if seed is not None else int(self.np_random.integers(2**31))
        self.compass = GyroCompass.part(self.compass_name, self._dt,
                                        int(goals.stream(0, part=2).integers(2**31)))
        return super().reset(seed=seed, options=options)

    def step(self, action: np.ndarray
             ) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        self._clock += 1
        return super().step(action)

    def _guided_tour(self, tour_seed: int) -> tuple[TourRecord, dict, dict]:
        record, obs, info = super()._guided_tour(tour_seed)
        steps = len(record.heading)
        record.heading = reading(record.heading, self.compass.errors(steps))
        self._clock = steps - 1
        return record, obs, info

    def _resume(self, state: TourState) -> tuple[TourRecord, dict, dict]:
        record, obs, info = super()._resume(state)
        self._clock = len(record.heading) - 1
        return record, obs, info

    def _carry(self, goal: int) -> tuple[dict[str, Any], dict[str, Any]]:
        """A carried start from the goal's stream: a room other than ``goal``'s, a pose in it
        (the simulator seeded from the same stream), at least ``min_errand_distance`` of
        walking from the goal where one of :data:`CARRY_DRAWS` draws is."""
        goals = self.goals
        assert isinstance(goals, SharedImageGoals)
        rng = goals.stream(len(self._errands), part=1)
        rooms = [r for r in self.plan.rooms if r.id != goal]
        for _ in range(CARRY_DRAWS):
            room = rooms[int(rng.integers(len(rooms)))]
            obs, info = self.nav.reset(seed=int(rng.integers(2**31)),
                                       options={"room": room.name})
            if self.goal_room.walk(goal, info["pose"], room.id) >= self.min_errand_distance:
                break
        return self.places.relocated(obs, info)

    def _observation(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        out = super()._observation(obs, info)
        out["heading"] = reading(out["heading"], self.compass.error(self._clock))
        return out


# registered on import (envs imports this module), under either package name
if "PlaceNav-ImageGoal-v1" not in registry:
    register(id="PlaceNav-ImageGoal-v1", entry_point=f"{__name__}:ImageGoalEnv",
             max_episode_steps=None)
