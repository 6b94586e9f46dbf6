"""What an errand of ``PlaceNav-GuidedTour-v1`` asks for: a named room, or a picture of a spot.

Two strategies behind one seam, each owning its goal's draw, its part of the observation, its
reward and when the errand ends (:class:`GuidedTourEnv <envs.tasks.guided_tour.GuidedTourEnv>`
asks its ``goals`` object, never a goal's type):

- :class:`RoomGoals` (v1's errands): a room the guide named; the errand succeeds on entering it.
- :class:`ImageGoals` (``PlaceNav-ImageGoal-v0``): a picture taken near the tour's route, in
  the camera the recognizer reads, under the errands' condition, as in Habitat's ImageNav
  (Zhu et al. 2017; Krantz et al. 2022). The agent sees no pixels: the env localizes the
  picture on a copy of the recognizer's map that has forgotten where the robot is (its
  ``localize_one``, the fixed map's own query; ``predict_one`` for a recognizer without it),
  so the robot's own tracking never moves, and observes that place (``goal_place``). The
  agent declares arrival with the action's third entry (> 0, ImageNav's STOP); it succeeds if
  it stops within ``success_radius`` metres of walking of the goal. The errand records the
  walking distance left (``final_distance``) beside SPL.

How an image goal is drawn (Habitat's PointNav rules, Savva et al. 2019, where they apply): a
step of the guided tour inside a room, uniformly, so every goal is where the tour drove and an
agent replaying the tour can reach it; the pose the robot had there (moved off furniture that
the errands' condition moved onto it), turned to a uniform heading. It must lie at least
``max(min_errand_distance, 2 * success_radius)`` of walking from the errand's start, so an
agent that stops where it stands cannot succeed; of :data:`GOAL_DRAWS` draws the first that
does stands, else the farthest (the errand says ``redrawn`` when the first did not). Habitat's
rule against straight-line episodes (geodesic over Euclidean distance below 1.1) is left out:
rooms joined by doorways make nearly every episode bend.

Examples:
    >>> import numpy as np
    >>> from envs.world.layout import generate_floor_plan
    >>> plan = generate_floor_plan(3, np.random.default_rng(0))
    >>> walk = PointWalk(plan)
    >>> a, b = plan.rooms[0], plan.rooms[1]
    >>> walk(a.center, a.center)
    0.0
    >>> walk(a.center, b.center) >= float(np.hypot(*np.subtract(a.center, b.center)))
    True
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import networkx as nx
import numpy as np
from gymnasium import spaces

from placeclust.protocol import place_of, reset_position

from ..world.changes import clear_pose
from ..world.layout import FloorPlan
from .errand_draws import draw_goal
from .goals import GoalRoom, door_graph

#: the kinds of goal an errand can have
GOAL_KINDS = ("room", "image")
#: draws of an image goal before the farthest one stands
GOAL_DRAWS = 20
#: chars of a room name
NAME_CHARSET = frozenset("abcdefghijklmnopqrstuvwxyz0123456789 -_")


class TourTask(Protocol):
    """What a goal strategy reads of its env (``PlaceNav-GuidedTour-v1``'s
    :class:`~envs.tasks.guided_tour.GuidedTourEnv`, which imports this module)."""

    @property
    def plan(self) -> Any: ...

    @property
    def nav(self) -> Any: ...

    @property
    def np_random(self) -> np.random.Generator: ...

    @property
    def truth(self) -> Any: ...

    @property
    def errand_start(self) -> str: ...

    @property
    def min_errand_distance(self) -> float: ...

    @property
    def max_places(self) -> int: ...

    @property
    def n_errands(self) -> int: ...

    @property
    def tour_steps_per_room(self) -> int: ...

    @property
    def tour_rooms(self) -> np.ndarray: ...

    @property
    def tour_poses(self) -> np.ndarray: ...

    @property
    def errands(self) -> list[Any]: ...

    @property
    def bound_truth(self) -> Any: ...

    @property
    def recognizer(self) -> Any: ...


class PointWalk:
    """Walking distance (m) between two points of a building, through its doorways.

    Within a room the straight line (rooms are rectangles); between rooms the shortest way
    through the doorways' centres. Furniture is not walked around, as in
    :class:`~envs.tasks.goals.GoalRoom`. ``room_a``/``room_b`` say which room a point is taken
    to be in (a doorway's point: the one it is leaving); ``inf`` where no way leads.
    """

    def __init__(self, plan: FloorPlan) -> None:
        self.plan = plan
        self._between = dict(nx.all_pairs_dijkstra_path_length(door_graph(plan)))
        self._doors = {r.id: [i for i, d in enumerate(plan.doors) if r.id in d.rooms]
                       for r in plan.rooms}

    def __call__(self, a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray,
                 room_a: int | None = None,
                 room_b: int | None = None) -> float:
        ra = self.plan.room_at(a[0], a[1]) if room_a is None else room_a
        rb = self.plan.room_at(b[0], b[1]) if room_b is None else room_b
        if ra < 0 or rb < 0:
            return math.inf
        if ra == rb:
            return math.dist(a[:2], b[:2])
        doors = self.plan.doors
        return min((math.dist(a[:2], (doors[i].x, doors[i].y))
                    + self._between[i].get(j, math.inf)
                    + math.dist((doors[j].x, doors[j].y), b[:2])
                    for i in self._doors[ra] for j in self._doors[rb]), default=math.inf)


@dataclass
class Goal:
    """One errand's goal: its room (id and name), whether it was redrawn, and for an image
    goal its pose, the tour step it was drawn at and the place the recognizer gave it."""

    room: int
    name: str
    redrawn: bool = False
    pose: np.ndarray | None = None
    step: int = -1
    place: int = -1


class RoomGoals:
    """v1's errands: go to a room the guide named (:func:`~envs.tasks.errand_draws.draw_goal`).

    A strategy keeps no reference to its env (pickling rebuilds an env, and a reference would
    point at the rebuilt one's stand-in): the env passes itself where a draw needs it.
    """

    kind = "room"

    def __init__(self, env: TourTask, success_reward: float, step_cost: float,
                 shaping: float) -> None:
        self.goal_room = GoalRoom(env.plan, success_reward, step_cost, shaping)
        self.goal: Goal | None = None

    def spaces(self) -> dict[str, spaces.Space]:
        """The goal's entries of the observation: the room's name."""
        return {"goal": spaces.Text(40, min_length=1, charset=NAME_CHARSET)}

    def draw(self, env: TourTask, k: int, info: dict[str, Any], room: int,
             named: list[str], fixed: list[str]) -> Goal:
        """Errand ``k``'s goal in ``env``: ``fixed[k]`` if given, else a named room drawn away
        from ``room``, where the robot stands (``info``)."""
        if k < len(fixed):
            name, redrawn = fixed[k], False
        elif env.errand_start == "carried":  # any named room: the start is drawn away from it
            name, redrawn = named[int(env.np_random.integers(len(named)))], False
        else:
            name, redrawn = draw_goal(env.np_random, self.goal_room, named, info["pose"],
                                      room, env.min_errand_distance)
        return Goal(env.plan.room_by_name(name).id, name, redrawn)

    def start(self, goal: Goal, pose: Sequence[float], room: int) -> float:
        """Aim at ``goal`` from ``pose`` in ``room``; the walking distance to it."""
        self.goal = goal
        return self.goal_room.start(goal.room, pose, room=room)

    def step(self, action: np.ndarray, pose: Sequence[float], room_id: int, room: int
             ) -> tuple[float, bool, bool]:
        """(reward, errand over, success) of a step that ended at ``pose``."""
        reward, success = self.goal_room.step(pose, room_id, room=room)
        return reward, success, success

    def observe(self, env: TourTask) -> dict[str, Any]:
        """The goal's entries of ``env``'s observation."""
        assert self.goal is not None
        return {"goal": self.goal.name}

    def outcome(self, pose: Sequence[float], room: int) -> dict[str, Any]:
        """What an ended errand adds to its record: nothing for a room."""
        return {}


class ImageGoals(RoomGoals):
    """Errands to a picture of a spot (the module's rules); success within ``radius`` metres
    of walking when the agent stops."""

    kind = "image"

    def __init__(self, env: TourTask, success_reward: float, step_cost: float,
                 shaping: float, radius: float) -> None:
        super().__init__(env, success_reward, step_cost, shaping)
        self.max_places, self.n_errands = env.max_places, env.n_errands
        #: the longest tour there can be: ``goal_step``'s unknown value
        self.max_steps = 3 * len(env.plan.rooms) * env.tour_steps_per_room
        if not radius > 0:
            raise ValueError(f"success_radius must be a positive number of metres, got {radius}")
        self.radius = radius
        self.walk = PointWalk(env.plan)
        self.success_reward, self.step_cost, self.shaping = success_reward, step_cost, shaping
        self.distance = 0.0
        self.image: np.ndarray | None = None  # the last goal's picture (None: none rendered)

    def spaces(self) -> dict[str, spaces.Space]:
        """The goal picture's place (``max_places``: unknown), and its tour step where the
        recognizer knows the goal's pose (the ceiling, ``oracle-pose``; else unknown)."""
        return {"goal_place": spaces.Discrete(self.max_places + 1),
                "goal_step": spaces.Discrete(self.max_steps + 1),
                "errand": spaces.Discrete(self.n_errands)}

    def draw(self, env: TourTask, k: int, info: dict[str, Any], room: int,
             named: list[str], fixed: list[str]) -> Goal:
        steps = np.flatnonzero(env.tour_rooms >= 0)
        far = max(env.min_errand_distance, 2 * self.radius)
        best: tuple[float, int] = (-1.0, int(steps[0]))
        redrawn = False
        for _ in range(GOAL_DRAWS):
            t = int(steps[int(env.np_random.integers(len(steps)))])
            d = self.walk(info["pose"], env.tour_poses[t], room, int(env.tour_rooms[t]))
            if env.errand_start == "carried" or d >= far:
                best = (d, t)
                break
            redrawn = True
            best = max(best, (d, t))
        t = best[1]
        x, y, _ = clear_pose(env.nav.plan, env.tour_poses[t])
        pose = np.array([x, y, float(env.np_random.uniform(-math.pi, math.pi))])
        goal_room = int(env.tour_rooms[t])
        goal = Goal(goal_room, env.plan.rooms[goal_room].name, redrawn, pose, t)
        self.image = self._picture(env, pose)
        goal.place = self._localize(env, goal)
        return goal

    def start(self, goal: Goal, pose: Sequence[float], room: int) -> float:
        self.goal = goal
        assert goal.pose is not None
        self.distance = self.walk(pose, goal.pose, room, goal.room)
        return self.distance

    def step(self, action: np.ndarray, pose: Sequence[float], room_id: int, room: int
             ) -> tuple[float, bool, bool]:
        assert self.goal is not None and self.goal.pose is not None
        distance = self.walk(pose, self.goal.pose, room, self.goal.room)
        if not math.isfinite(distance):
            distance = self.distance
        reward = self.shaping * (self.distance - distance) - self.step_cost
        self.distance = distance
        stop = bool(action[2] > 0)
        success = stop and distance <= self.radius
        return reward + (self.success_reward if success else 0.0), stop, success

    def observe(self, env: TourTask) -> dict[str, Any]:
        assert self.goal is not None
        place = self.goal.place if 0 <= self.goal.place < env.max_places else env.max_places
        knows = env.truth is not None and env.truth.pose
        return {"goal_place": np.int64(place),
                "goal_step": np.int64(self.goal.step if knows else self.max_steps),
                "errand": np.int64(len(env.errands) - 1)}

    def outcome(self, pose: Sequence[float], room: int) -> dict[str, Any]:
        assert self.goal is not None and self.goal.pose is not None
        return {"final_distance": float(self.walk(pose, self.goal.pose, room, self.goal.room)),
                "goal_place": int(self.goal.place), "goal_step": int(self.goal.step)}

    def _picture(self, env: TourTask, pose: np.ndarray) -> np.ndarray | None:
        """The picture a robot standing at ``pose`` takes in the errands' world, without
        moving the robot (the simulator is put back as it was); None where the recognizer
        reads no images."""
        nav = env.nav
        if not nav.with_panorama:
            return None
        snapshot = nav.snapshot()
        try:
            obs, _ = nav.reset(options={"pose": pose})
        finally:
            nav.restore(snapshot)
        return obs[nav.image_key]

    def _localize(self, env: TourTask, goal: Goal) -> int:
        """The place of the goal's picture: the true rooms' (a calibration oracle's own
        answer), or the recognizer's (:func:`placeclust.protocol.place_of` without ranking:
        ``localize_one``, the fixed map's query with its own threshold, else
        ``predict_one``)."""
        if env.bound_truth is not None:
            assert goal.pose is not None
            return env.bound_truth.goal(goal.room, goal.pose)
        recognizer = env.recognizer
        if recognizer is None:
            return -1
        if self.image is None:  # one that reads no images (random, none): its next answer
            model = copy.deepcopy(recognizer)
            reset_position(model)
            return int(model.learn_predict_one(None))
        return place_of(recognizer, self.image, rank=False)  # v0 names no place by rank


def make_goals(kind: str, env: TourTask, success_reward: float, step_cost: float,
               shaping: float, radius: float) -> RoomGoals:
    """The goal strategy ``kind`` (one of :data:`GOAL_KINDS`) for ``env``."""
    if kind == "room":
        return RoomGoals(env, success_reward, step_cost, shaping)
    if kind == "image":
        return ImageGoals(env, success_reward, step_cost, shaping, radius)
    raise ValueError(f"unknown goals {kind!r}; choose one of {GOAL_KINDS}")
