"""``PlaceNav-GuidedTour-v1``: a guide shows the robot a building it has never seen, naming the
rooms; the robot maps it online; then it runs errands to rooms named by the guide.

This is the setting of COLD, seed 001's data set: a person drives the robot through the
building and names the rooms, the robot's recognizer builds its map as it goes, and only then is
the robot asked to go somewhere. The recognizer is what is being tested: the agent knows a room
only by the place the recognizer reported when the guide named it, so with ids that mean
nothing (``recognizer="random"``) the names mean nothing either.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3, n_errands=1,
    ...                tour_steps_per_room=40)
    >>> obs, info = env.reset(seed=0)
    >>> sorted(info["tour"].heard_names()) == sorted(r.name for r in env.unwrapped.plan.rooms)
    True
    >>> obs["goal"] in info["tour"].heard_names(), info["map"]["precision"]
    (True, 1.0)
    >>> env.close()
"""

from __future__ import annotations

import math
import string
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from placeclust import PANORAMA, PANORAMA_ORB, OnlinePlaceClustering
from placeclust.metrics import score
from placeclust.nested import NestedMapper
from placeclust.null import NoPlaces, RandomPlaces
from placeclust.protocol import is_offline, reads_images, resolve
from placeclust.runner import check_params, make, recognizer_class

from .goals import GoalRoom, NavTask
from .place_id import PlaceIdWrapper, Recognizer
from .place_nav import PlaceNavEnv
from .tour import tour_steps

#: recognizers by name: ``oracle`` gives the true room (the upper bound); ``panorama`` is seed
#: 000's online recognizer in its 360° configuration with SIFT (the preset ``panorama``,
#: :data:`placeclust.PANORAMA`), ``panorama-orb`` in ORB's (the preset ``panorama-orb``,
#: :data:`placeclust.PANORAMA_ORB`, with ORB); ``nested`` seed 001 on the forward camera;
#: ``random`` ids that mean nothing; ``none`` no ids at all. ``online`` is the paper's defaults
#: everywhere in placeclust (``placeclust bench --algos online``), so it is not a name here.
RECOGNIZERS = ("oracle", "panorama", "panorama-orb", "nested", "random", "none")
#: the names these recognizers had before placeclust 0.13.0, for the error that says so
RENAMED = {"online": "panorama", "online-orb": "panorama-orb"}
NAME_CHARSET = frozenset(string.ascii_lowercase + string.digits + " -_")


def make_recognizer(name: str, n_rooms: int, max_places: int = 64,
                    params: Mapping[str, Any] | None = None) -> Recognizer | None:
    """A fresh recognizer for the closed loop (``None`` for ``oracle``, the true rooms).

    Args:
        name: one of :data:`RECOGNIZERS`, or ``package.module:Class``, an online recognizer of
            your own (``learn_predict_one``, ``n_places``, ``graph``; see
            :mod:`placeclust.checks`), loaded as ``placeclust cluster --algo`` loads it.
        n_rooms: the building's rooms (``random`` draws ids from twice as many).
        max_places: the cap of ``panorama`` and ``panorama-orb``'s maps.
        params: a module path's constructor arguments (``features`` included). A name is one
            configuration, so it takes none: for another, name the class with the arguments,
            e.g. ``placeclust.online:OnlinePlaceClustering`` with ``PANORAMA``'s and yours.

    Raises:
        ValueError: an unknown name, a path that does not load or is not an online recognizer,
            or parameters with a name.
    """
    params = dict(params or {})
    if ":" in name:
        return _own_recognizer(name, params)
    check_recognizer_name(name)
    if params:
        raise ValueError(f"{name!r} is one configuration and takes no parameters, got "
                         f"{sorted(params)}; give package.module:Class with them instead")
    if name == "oracle":
        return None
    if name == "panorama":
        return OnlinePlaceClustering("sift", **PANORAMA, max_places=max_places)
    if name == "panorama-orb":
        return OnlinePlaceClustering("orb", **PANORAMA_ORB, max_places=max_places)
    if name == "nested":
        return NestedMapper()
    if name == "random":
        return RandomPlaces(n_ids=2 * n_rooms)
    return NoPlaces()


def _own_recognizer(path: str, params: dict[str, Any]) -> Recognizer:
    cls = recognizer_class(path)  # a ValueError that names a path or class that does not load
    if is_offline(cls):
        raise ValueError(f"{path} is an offline recognizer (fit_predict); the closed loop "
                         "needs an online one (learn_predict_one)")
    check_params(path, [k for k in params if k != "features"])
    model = make(path, **params)
    if not isinstance(model, Recognizer):
        raise ValueError(f"{path} lacks what the closed loop reads of a recognizer: "
                         "learn_predict_one, predict_one, n_places and graph")
    return model


def check_recognizer_name(name: str) -> None:
    """A ``ValueError`` naming the choices if ``name`` is neither one of :data:`RECOGNIZERS` nor
    a ``package.module:Class`` that loads."""
    if name in RECOGNIZERS:
        return
    if ":" in name:
        recognizer_class(name)
        return
    hint = f" ('{name}' was renamed '{RENAMED[name]}' in 0.13.0)" if name in RENAMED else ""
    raise ValueError(f"unknown recognizer {name!r}; choose one of {RECOGNIZERS} or give "
                     f"package.module:Class{hint}")


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
    """

    place_id: np.ndarray
    heard: np.ndarray
    odometry: np.ndarray
    heading: np.ndarray
    control_dt: float

    def heard_names(self) -> list[str]:
        """The room names the guide said, in the order said."""
        return [str(h) for h in self.heard if h]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TourRecord):
            return NotImplemented
        return self.control_dt == other.control_dt and all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("place_id", "heard", "odometry", "heading"))


@dataclass
class Errand:
    """One errand's outcome: ``success``, ``steps``, ``path`` driven and ``shortest`` walking
    distance (m) from its start to the goal room, and ``spl`` (Anderson et al. 2018)."""

    goal: str
    success: bool = False
    steps: int = 0
    path: float = 0.0
    shortest: float = 0.0
    redrawn: bool = False

    @property
    def spl(self) -> float:
        return float(self.success) * self.shortest / max(self.shortest, self.path, 1e-9)

    def as_dict(self) -> dict[str, Any]:
        return {"goal": self.goal, "success": self.success, "steps": self.steps,
                "path": self.path, "shortest": self.shortest, "spl": self.spl,
                "redrawn": self.redrawn}


class GuidedTourEnv(NavTask, gym.utils.EzPickle):
    """A guided tour that builds the map, then ``n_errands`` errands to named rooms.

    ``reset`` drives the tour: a scripted route through every room (:mod:`envs.tasks.tour`), the
    recognizer learning from each frame from an empty map, and the guide naming each room once,
    ``name_after`` steps after the robot first enters it. The agent does not act on the tour;
    what it observed comes back as ``info["tour"]`` (:class:`TourRecord`). Then each errand
    names a room the guide named, other than the one the robot is in and at least
    ``min_errand_distance`` of walking away; the errand ends when the robot enters that room or
    after ``errand_steps`` steps, and the next one starts from there. The map keeps learning
    through the errands.

    An errand starts where the last one ended, at the door of the room just reached, so the
    room behind that door would be an errand of one step across a threshold. A goal drawn
    closer than ``min_errand_distance`` is drawn again among the rooms far enough (its
    :class:`Errand` says ``redrawn``), as Habitat rejects episodes that start within the
    success distance; where no named room is far enough the first draw stands.

    ## Action Space
    ``PlaceNav-v0``'s: ``Box(-1, 1, (2,))``, normalised forward speed and turn rate.

    ## Observation Space
    ``Dict`` with ``place_id`` (``Discrete(max_places + 1)``, ``max_places`` = unknown),
    ``goal`` (``Text``: the errand's room name), and the robot's ``odometry``, ``heading`` and
    ``ranges`` (as in ``PlaceNav-v0``); with ``observe_image=True`` also the camera image. No
    ground truth: the agent knows rooms only through the names it heard on the tour.

    ## Rewards
    Per step ``shaping * (d_before - d_after) - step_cost`` with ``d`` the ground-truth walking
    distance to the goal room (:class:`~envs.tasks.goals.GoalRoom`; potential-based, so it does
    not change the optimal policy), and ``success_reward`` on entering it. In a doorway the
    distance is measured from the room the robot is leaving.

    ## Episode End
    Terminates when the last errand ends; errands bound the episode, so it never truncates.

    ## Info
    At reset: ``tour`` (:class:`TourRecord`), ``map`` (the tour's ``precision``, ``nmi``,
    ``n_places``, ``places_per_room`` against the true rooms), ``named`` (room names said).
    Every step: ``errand`` (index), ``goal``, ``place_id`` (raw, -1 unknown), ``room_id`` and
    ``pose`` (ground truth, for scoring only). The step that ends an errand adds
    ``errand_result`` (:class:`Errand` as a dict) and ``is_success``; the last step adds
    ``errands`` (all of them).

    ## Arguments
    ``recognizer`` (a name of :data:`RECOGNIZERS`, a ``package.module:Class`` of your own or a
    recognizer object, default ``"panorama"``), ``recognizer_params`` (a path's constructor
    arguments, see :func:`make_recognizer`), ``n_errands`` (5), ``errand_steps``
    (500: 50 s, half again the longest shortest route of a 6-room building at the planner's
    pace), ``tour_steps_per_room`` (150: the tour runs
    ``n_rooms`` times that, longer if a room is still unnamed, at most three times that),
    ``name_after`` (10), ``min_errand_distance`` (1 m), ``max_places`` (64),
    ``success_reward`` (10), ``step_cost`` (0.01), ``shaping`` (1 per metre),
    ``observe_image`` (False), ``render_mode``, and any argument of
    ``PlaceNav-v0`` (``scene_seed``, ``n_rooms`` (default 6 here), ``camera``: the forward
    camera for ``nested``, the panorama otherwise).

    ``reset(options={"goals": [name, ...]})`` fixes the errands' rooms; a name the guide never
    said is a ``ValueError``.

    ## Version History
    - v1 (placeclust 0.13.0): errands start at least ``min_errand_distance`` (1 m) of
      walking from their goal room. The recognizers ``online`` and ``online-orb`` are named
      ``panorama`` and ``panorama-orb``, after their presets; ``recognizer`` also takes a
      ``package.module:Class`` with ``recognizer_params``.
    - v0: first version; still registered, as v1 with ``min_errand_distance=0``.
    """

    def __init__(self, recognizer: str | Recognizer = "panorama", n_errands: int = 5,
                 errand_steps: int = 500, tour_steps_per_room: int = 150, name_after: int = 10,
                 min_errand_distance: float = 1.0, max_places: int = 64,
                 success_reward: float = 10.0, step_cost: float = 0.01, shaping: float = 1.0,
                 observe_image: bool = False, render_mode: str | None = None, n_rooms: int = 6,
                 recognizer_params: Mapping[str, Any] | None = None, **world: Any) -> None:
        # pickle and deepcopy rebuild the env from its arguments, as PlaceNav-v0 does
        gym.utils.EzPickle.__init__(
            self, recognizer=recognizer, recognizer_params=recognizer_params,
            n_errands=n_errands, errand_steps=errand_steps,
            tour_steps_per_room=tour_steps_per_room, name_after=name_after,
            min_errand_distance=min_errand_distance, max_places=max_places,
            success_reward=success_reward, step_cost=step_cost, shaping=shaping,
            observe_image=observe_image, render_mode=render_mode, n_rooms=n_rooms, **world)
        if n_errands < 1 or errand_steps < 1 or tour_steps_per_room < 1 or name_after < 1:
            raise ValueError("n_errands, errand_steps, tour_steps_per_room and name_after must "
                             f"be positive, got {n_errands}, {errand_steps}, "
                             f"{tour_steps_per_room}, {name_after}")
        if not min_errand_distance >= 0:
            raise ValueError(f"min_errand_distance must be 0 or more metres, got "
                             f"{min_errand_distance}")
        if recognizer_params and not isinstance(recognizer, str):
            raise ValueError("recognizer_params go with a package.module:Class recognizer, "
                             "not with a recognizer object")
        model = (make_recognizer(recognizer, n_rooms, max_places, recognizer_params)
                 if isinstance(recognizer, str) else recognizer)
        self.oracle = model is None
        world.setdefault("camera", "forward" if recognizer == "nested" else "panorama")
        # a recognizer that reads no images (random, none) gets none rendered: the same ids
        looks = model is not None and reads_images(model)
        nav = PlaceNavEnv(n_rooms=n_rooms, render_mode=render_mode,
                          panorama=looks or observe_image, **world)
        self._place_ids = None if model is None else PlaceIdWrapper(
            nav, model, max_places=max_places, learn=True, reset_map=True)
        self._env: gym.Env = nav if self._place_ids is None else self._place_ids
        self.nav = nav
        self.render_mode = render_mode
        self.n_errands, self.errand_steps = n_errands, errand_steps
        self.tour_steps_per_room, self.name_after = tour_steps_per_room, name_after
        self.min_errand_distance = min_errand_distance
        self.max_places = max_places
        self.observe_image = observe_image
        self.goal_room = GoalRoom(self.plan, success_reward, step_cost, shaping)
        keep = ("odometry", "heading", "ranges") + ((nav.image_key,) if observe_image else ())
        self.observation_space = spaces.Dict({
            "place_id": spaces.Discrete(max_places + 1),
            "goal": spaces.Text(40, min_length=1, charset=NAME_CHARSET),
            **{k: nav.observation_space[k] for k in keep}})
        self.action_space = nav.action_space
        self._named: list[str] = []
        self._goals: list[str] = []
        self._errands: list[Errand] = []
        self._over = True  # until the first reset
        self._pose = np.zeros(3)
        self._tour_rooms = np.zeros(0, np.int64)
        self._room = 0  # the last room the robot was in (a doorway is in none)

    @property
    def recognizer(self) -> Recognizer | None:
        """The recognizer with the map it has built (``None`` for ``oracle``)."""
        return None if self._place_ids is None else self._place_ids.recognizer

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        super().reset(seed=seed)  # the tour reseeds nav from this generator's draw
        options = dict(options or {})
        goals = options.pop("goals", None)
        if options:
            raise ValueError(f"unknown reset options {sorted(options)}; use 'goals'")
        if goals is not None:
            for name in goals:
                self.plan.room_by_name(name)  # a KeyError naming the rooms, before the tour
        tour, obs, info = self._guided_tour(int(self.np_random.integers(2**31)))
        self._named = tour.heard_names()
        if goals is not None:
            unheard = [g for g in goals if g not in self._named]
            if unheard:
                raise ValueError(f"errand goals {unheard} were never named on the tour; the "
                                 f"guide named {self._named}")
        self._goals = list(goals) if goals is not None else []
        self._errands, self._over = [], False
        self._pose = info["pose"]
        self._start_errand(info)
        return self._observation(obs, info), {
            "tour": tour, "map": self._map_scores(tour, self._tour_rooms), "named": self._named,
            **self._step_info(info)}

    def step(self, action: np.ndarray
             ) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        if self._over:
            raise RuntimeError("the episode is over; call reset()")
        obs, _, _, _, info = self._env.step(action)
        errand = self._errands[-1]
        errand.steps += 1
        errand.path += math.dist(self._pose[:2], info["pose"][:2])
        self._pose = info["pose"]
        reward, success = self.goal_room.step(info["pose"], info["room_id"],
                                              room=self._last_room(info))
        out = self._step_info(info)
        terminated = False
        if success or errand.steps >= self.errand_steps:
            errand.success = bool(success)
            out.update(errand_result=errand.as_dict(), is_success=errand.success)
            if len(self._errands) == self.n_errands:
                terminated = self._over = True
                out["errands"] = [e.as_dict() for e in self._errands]
            else:
                self._start_errand(info)
                out.update(errand=len(self._errands) - 1, goal=self._errands[-1].goal)
        return self._observation(obs, info), reward, terminated, False, out

    def close(self) -> None:
        self._env.close()

    # -- the tour --------------------------------------------------------------------------

    def _guided_tour(self, tour_seed: int) -> tuple[TourRecord, dict, dict]:
        """Drive the tour, naming each room ``name_after`` steps after first entering it."""
        n_rooms = len(self.plan.rooms)
        planned = self.tour_steps_per_room * n_rooms
        places, heard, odometry, heading, rooms = [], [], [], [], []
        named: set[int] = set()
        run, last_room = 0, -1
        for t, (obs, info) in enumerate(tour_steps(self._env, 3 * planned, seed=tour_seed)):
            room = info["room_id"]
            if room >= 0:
                self._room = room
            run = run + 1 if room == last_room else 1
            last_room = room
            say = ""
            if room >= 0 and room not in named and run >= self.name_after:
                named.add(room)
                say = self.plan.rooms[room].name
            places.append(self._raw_place(info))
            heard.append(say)
            odometry.append(obs["odometry"])
            heading.append(obs["heading"])
            rooms.append(room)
            if t + 1 >= planned and len(named) == n_rooms:
                break
        ids = np.array(places, np.int64)
        if self.recognizer is not None:
            ids = resolve(self.recognizer, ids)
        self._tour_rooms = np.array(rooms)
        record = TourRecord(ids, np.array(heard, dtype=object), np.array(odometry),
                            np.array(heading), self.nav.model.opt.timestep * self.nav.n_substeps)
        return record, obs, info

    def _map_scores(self, tour: TourRecord, rooms: np.ndarray) -> dict[str, float]:
        inside = rooms >= 0
        s = score(tour.place_id[inside], rooms[inside])
        return {"precision": s["precision"], "nmi": s["nmi"], "n_places": s["n_places"],
                "places_per_room": s["n_places"] / max(s["n_rooms"], 1)}

    # -- errands ---------------------------------------------------------------------------

    def _start_errand(self, info: dict[str, Any]) -> None:
        k = len(self._errands)
        room = self._last_room(info)
        goal, redrawn = (self._goals[k], False) if k < len(self._goals) else self._draw_goal(
            info["pose"], room)
        self._errands.append(Errand(goal, redrawn=redrawn))
        self._errands[-1].shortest = self.goal_room.start(
            self.plan.room_by_name(goal).id, info["pose"], room=room)

    def _draw_goal(self, pose: Sequence[float], room: int) -> tuple[str, bool]:
        """A named room other than ``room``; drawn again among those at least
        ``min_errand_distance`` away if the first draw is closer. Returns (name, redrawn)."""
        here = self.plan.rooms[room].name
        others = [n for n in self._named if n != here] or self._named
        goal = others[int(self.np_random.integers(len(others)))]
        far = [n for n in others if self.goal_room.walk(self.plan.room_by_name(n).id, pose,
                                                        room) >= self.min_errand_distance]
        if goal in far or not far:  # the first draw stands: the same goals as v0 where far
            return goal, False
        return far[int(self.np_random.integers(len(far)))], True

    def _last_room(self, info: dict[str, Any]) -> int:
        """The room the robot is in or, in a doorway (no room), the one it is leaving."""
        if info["room_id"] >= 0:
            self._room = info["room_id"]
        return self._room

    def _raw_place(self, info: dict[str, Any]) -> int:
        return int(info["room_id"] if self.oracle else info["place_id"])

    def _observation(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        raw = self._raw_place(info)
        place = raw if 0 <= raw < self.max_places else self.max_places
        out = {"place_id": np.int64(place), "goal": self._errands[-1].goal}
        keys = [k for k in self.observation_space.spaces if k not in out]
        return {**out, **{k: obs[k] for k in keys}}

    def _step_info(self, info: dict[str, Any]) -> dict[str, Any]:
        return {"errand": len(self._errands) - 1, "goal": self._errands[-1].goal,
                "place_id": self._raw_place(info), "room_id": info["room_id"],
                "pose": info["pose"]}
