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

import copy
import math
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from placeclust.protocol import resolve

from ..world.changes import clear_pose
from ..world.conditions import CONDITIONS
from ..world.robot import check_action
from .errand_draws import carry, check_errands
from .errand_goals import Goal, RoomGoals, make_goals
from .goals import NavTask
from .oracles import BoundTrueRooms, TrueRooms
from .place_id import Recognizer
from .place_nav import PlaceNavEnv
from .place_reader import PlaceReader
from .records import Errand, TourRecord, TourState
from .tour import guided_tour


class GuidedTourEnv(NavTask, gym.utils.EzPickle):
    """A guided tour that builds the map, then ``n_errands`` errands to named rooms.

    ``reset`` drives the tour: a scripted route through every room (:mod:`envs.tasks.tour`), the
    recognizer learning from each frame from an empty map, and the guide naming each room once,
    ``name_after`` steps after the robot first enters it. The agent does not act on the tour;
    what it observed comes back as ``info["tour"]`` (:class:`TourRecord`). Then each errand
    names a room the guide named, other than the one the robot is in and at least
    ``min_errand_distance`` of walking away; the errand ends when the robot enters that room or
    after ``errand_steps`` steps, and the next one starts from there (a goal drawn closer is
    drawn again: :mod:`envs.tasks.errand_draws`). The map keeps learning through the errands.

    With ``errand_start="carried"`` the robot is instead carried to each errand's start, as if
    kidnapped, with the recognizer told to forget where it was. Its odometry then says how it
    moved since, not where it is: only recognizing the place tells it that, as in
    ``PlaceNav-ReachRoom-v0``. In a building whose rooms look alike to its rangefinders
    (``layout="corridor"``) this is the task where place ids are needed.

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
    ``recognizer`` (a name of :data:`~envs.tasks.recognizers.RECOGNIZERS`, a calibration
    oracle, a
    ``package.module:Class`` of your own or a recognizer object, default ``"panorama"``),
    ``recognizer_params`` (a path's constructor arguments, see
    :func:`~envs.tasks.recognizers.make_recognizer`), ``n_errands`` (5), ``errand_steps``
    (500: 50 s, half again the longest shortest route of a 6-room building at the planner's
    pace), ``tour_steps_per_room`` (150: the tour runs
    ``n_rooms`` times that, longer if a room is still unnamed, at most three times that),
    ``name_after`` (10), ``min_errand_distance`` (1 m), ``errand_start`` (``"continue"``
    from where the last errand ended, or ``"carried"``), ``max_places`` (64),
    ``success_reward`` (10), ``step_cost`` (0.01), ``shaping`` (1 per metre),
    ``errand_condition`` (None: the tour's; a name of
    :data:`~envs.world.conditions.CONDITIONS`, e.g. ``"night"`` or ``"moved"``: the errands run
    in the same building under it, from the tour's last pose, moved a little if furniture now
    stands there), ``errand_learn`` (True: the map keeps learning during the errands; False:
    it only localizes, ``localize_one``, which a recognizer that reads images must have),
    ``goal_kind`` (``"room"``; ``"image"``: errands to a picture of a spot,
    :class:`~envs.tasks.errand_goals.ImageGoals`, registered as ``PlaceNav-ImageGoal-v0``),
    ``success_radius`` (1 m: an image goal's success, as Habitat's ImageNav),
    ``observe_image`` (False), ``render_mode``, and any argument of
    ``PlaceNav-v0`` (``scene_seed``, ``n_rooms`` (default 6 here), ``camera``: the forward
    camera for ``nested``, the panorama otherwise).

    ``reset(options={"goals": [name, ...]})`` fixes the errands' rooms; a name the guide never
    said is a ``ValueError``. ``reset(options={"tour": state})`` skips the tour and starts from
    the :class:`~envs.tasks.records.TourState` another reset left (:meth:`tour_state`, of this
    env or one of the same building and recognizer): the simulator as the tour left it, the
    map as the tour made it, the episode's draws (goals, carries) as after that tour; its
    errands are those the same reset with a tour of its own gives.

    ## Image goals
    With ``goal_kind="image"`` (``PlaceNav-ImageGoal-v0``) each errand's goal is a picture taken
    near the tour's route under the errands' condition (:mod:`envs.tasks.errand_goals`). The
    observation's ``goal`` is replaced by ``goal_place`` (the place the recognizer gives the
    picture; ``max_places``: unknown), ``goal_step`` (the tour step nearest the goal, known
    only to ``oracle-pose``, the ceiling; else its space's largest value) and ``errand`` (its
    index). The action gains a third entry: above 0 the agent declares arrival, which ends the
    errand, a success within ``success_radius`` metres of walking of the goal. The reward
    shapes on the walking distance to the goal's point. Each errand's record adds
    ``final_distance``, ``goal_place`` and ``goal_step``.

    ## Version History
    - ImageGoal-v0 (placeclust 0.16.0): image goals, as above.
    - v1 (placeclust 0.13.0): errands start at least ``min_errand_distance`` (1 m) of
      walking from their goal room. The recognizers ``online`` and ``online-orb`` are named
      ``panorama`` and ``panorama-orb``, after their presets; ``recognizer`` also takes a
      ``package.module:Class`` with ``recognizer_params``; ``errand_start="carried"`` puts
      the robot down at each errand's start (the default continues as before).
      Since 0.14.0: ``errand_condition`` and ``errand_learn`` (defaults as before), and
      ``recognizer`` takes the calibration oracles (``oracle-noise:P``, ``oracle-split:K``,
      ``oracle-merge:P``, :mod:`envs.tasks.oracles`).
    - v0: first version; still registered, as v1 with ``min_errand_distance=0``.
    """

    def __init__(self, recognizer: str | Recognizer = "panorama", n_errands: int = 5,
                 errand_steps: int = 500, tour_steps_per_room: int = 150, name_after: int = 10,
                 min_errand_distance: float = 1.0, max_places: int = 64,
                 success_reward: float = 10.0, step_cost: float = 0.01, shaping: float = 1.0,
                 observe_image: bool = False, render_mode: str | None = None, n_rooms: int = 6,
                 recognizer_params: Mapping[str, Any] | None = None,
                 errand_start: str = "continue", errand_condition: str | None = None,
                 errand_learn: bool = True, goal_kind: str = "room",
                 success_radius: float = 1.0, **world: Any) -> None:
        # pickle and deepcopy rebuild the env from its arguments, as PlaceNav-v0 does
        gym.utils.EzPickle.__init__(
            self, recognizer=recognizer, recognizer_params=recognizer_params,
            n_errands=n_errands, errand_steps=errand_steps,
            tour_steps_per_room=tour_steps_per_room, name_after=name_after,
            min_errand_distance=min_errand_distance, max_places=max_places,
            success_reward=success_reward, step_cost=step_cost, shaping=shaping,
            observe_image=observe_image, render_mode=render_mode, n_rooms=n_rooms,
            errand_start=errand_start, errand_condition=errand_condition,
            errand_learn=errand_learn, goal_kind=goal_kind, success_radius=success_radius, **world)
        check_errands(n_errands, errand_steps, tour_steps_per_room, name_after,
                      min_errand_distance, errand_start, n_rooms)
        if errand_condition is not None and errand_condition not in CONDITIONS:
            raise ValueError(f"unknown errand_condition {errand_condition!r}; choose one of "
                             f"{sorted(CONDITIONS)} or None (the tour's)")
        #: who gives each frame its place, and the tour's and the errands' worlds
        self.places = PlaceReader(recognizer, n_rooms, max_places, recognizer_params,
                                  errand_condition, errand_learn, observe_image, render_mode,
                                  **world)
        nav = self.nav = self.tour_nav = self.places.tour_nav
        self.errand_nav = self.places.errand_nav
        self.errand_condition, self.errand_learn = errand_condition, errand_learn
        self._tour: TourRecord | None = None  # the last tour, its end pose and last room
        self._tour_state: TourState | None = None  # and all the errands go on from
        self._tour_end, self._tour_room = np.zeros(3), 0
        self.render_mode = render_mode
        self.n_errands, self.errand_steps = n_errands, errand_steps
        self.tour_steps_per_room, self.name_after = tour_steps_per_room, name_after
        self.min_errand_distance = min_errand_distance
        self.errand_start = errand_start
        self.max_places = max_places
        self.observe_image = observe_image
        self._errands: list[Errand] = []
        self._tour_rooms = np.zeros(0, np.int64)
        self._tour_poses = np.zeros((0, 3))
        #: what the errands ask for: a named room, or a picture of a spot (errand_goals)
        self.goals: RoomGoals = make_goals(goal_kind, self, success_reward, step_cost, shaping,
                                           success_radius)
        self.goal_room = self.goals.goal_room
        keep = ("odometry", "heading", "ranges") + ((nav.image_key,) if observe_image else ())
        self.observation_space = spaces.Dict({
            "place_id": spaces.Discrete(max_places + 1), **self.goals.spaces(),
            **{k: nav.observation_space[k] for k in keep}})
        # an image goal's errand ends when the agent says it has arrived (ImageNav's STOP)
        self._action_size = 2 if goal_kind == "room" else 3
        self.action_space = nav.action_space if goal_kind == "room" else spaces.Box(
            -1.0, 1.0, (3,), np.float32)
        self._named: list[str] = []
        self._goals: list[str] = []
        self._over = True  # until the first reset
        self._pose = np.zeros(3)
        self._room = 0  # the last room the robot was in (a doorway is in none)

    @property
    def truth(self) -> TrueRooms | None:
        """The true rooms (``oracle`` and its calibration family), or None for a recognizer."""
        return self.places.truth

    @property
    def tour_rooms(self) -> np.ndarray:
        """The true room of each step of the last tour (-1 in a doorway): ground truth, for
        scoring and for agents that are given it (the oracle), never in the observation."""
        return self._tour_rooms

    @property
    def tour_poses(self) -> np.ndarray:
        """(T, 3) the robot's true pose at each step of the last tour: ground truth, where
        image goals are drawn, never in the observation."""
        return self._tour_poses

    @property
    def errands(self) -> list[Errand]:
        """This episode's errands so far, the current one last."""
        return self._errands

    @property
    def bound_truth(self) -> BoundTrueRooms | None:
        """The true rooms bound to this building (``oracle`` and its family), else None."""
        return self.places.bound

    @property
    def recognizer(self) -> Recognizer | None:
        """The recognizer with the map it has built (``None`` for ``oracle``)."""
        return self.places.recognizer

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        super().reset(seed=seed)  # the tour reseeds nav from this generator's draw
        options = dict(options or {})
        goals = options.pop("goals", None)
        state = options.pop("tour", None)
        if options:
            raise ValueError(f"unknown reset options {sorted(options)}; use 'goals' or 'tour'")
        if goals is not None:
            for name in goals:
                self.plan.room_by_name(name)  # a KeyError naming the rooms, before the tour
        self._use(self.tour_nav, learn=True)
        tour_seed = int(self.np_random.integers(2**31))  # drawn on resume too: same goals
        if state is not None:
            tour, obs, info = self._resume(state)
        else:
            self.places.bind(self.plan, tour_seed)  # the episode's stream stays v1's
            tour, obs, info = self._guided_tour(tour_seed)
            self._tour_state = self._keep_tour(tour, obs, info)
        self._named = tour.heard_names()
        if goals is not None:
            unheard = [g for g in goals if g not in self._named]
            if unheard:
                raise ValueError(f"errand goals {unheard} were never named on the tour; the "
                                 f"guide named {self._named}")
        self._goals = list(goals) if goals is not None else []
        self._errands, self._over = [], False
        if self.errand_nav is not self.tour_nav or not self.errand_learn:
            obs, info = self._change_condition(info["pose"])
        self._pose = info["pose"]
        obs, info = self._start_errand(obs, info)
        return self._observation(obs, info), {
            "tour": tour, "map": tour.map_scores(self._tour_rooms), "named": self._named,
            **self._step_info(info)}

    def step(self, action: np.ndarray
             ) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        if self._over:
            raise RuntimeError("the episode is over; call reset()")
        action = check_action(action, size=self._action_size)
        obs, _, _, _, info = self.places.env.step(action[:2])
        self.places.read(info)
        errand = self._errands[-1]
        errand.steps += 1
        errand.path += math.dist(self._pose[:2], info["pose"][:2])
        self._pose = info["pose"]
        room = self._last_room(info)
        reward, ended, success = self.goals.step(action, info["pose"], info["room_id"], room)
        out = self._step_info(info)
        terminated = False
        if ended or errand.steps >= self.errand_steps:
            errand.success = bool(success)
            errand.extra = self.goals.outcome(info["pose"], room)
            out.update(errand_result=errand.as_dict(), is_success=errand.success)
            if len(self._errands) == self.n_errands:
                terminated = self._over = True
                out["errands"] = [e.as_dict() for e in self._errands]
            else:
                obs, info = self._start_errand(obs, info)
                out.update(self._step_info(info))
        return self._observation(obs, info), reward, terminated, False, out

    def close(self) -> None:
        self.places.close()

    def tour_state(self) -> TourState:
        """What the last tour left, as it stood when the tour ended (copies):
        ``reset(options={"tour": state})`` of this env, or of another of the same building
        and recognizer, runs the errands a tour of its own would have given it, without
        driving the tour again."""
        if self._tour_state is None:
            raise RuntimeError("no tour yet; call reset()")
        return self._tour_state

    def _keep_tour(self, tour: TourRecord, obs: dict[str, Any], info: dict[str, Any]
                   ) -> TourState:
        """The tour's end, kept before any errand moves the robot or the map learns more."""
        return TourState(tour, *self.places.keep(), self._tour_rooms.copy(),
                         self._tour_end.copy(), self._tour_room, self.nav.snapshot(),
                         copy.deepcopy(obs), copy.deepcopy(info), self.places.place,
                         self._tour_poses.copy())

    def _resume(self, state: TourState) -> tuple[TourRecord, dict, dict]:
        """Start from ``state`` instead of a tour: its map, and the simulator as the tour left
        it (the robot in motion, the random streams), seeing the tour's last frame."""
        # a ValueError for another kind of recognizer or building, before any change
        self.places.restore(state.recognizer, state.truth, state.place, state.nav)
        self._tour, self._tour_rooms = state.record, state.rooms.copy()
        self._tour_poses = np.zeros((0, 3)) if state.poses is None else state.poses.copy()
        self._tour_end, self._tour_room = state.pose.copy(), state.room
        self._room = state.room
        self._tour_state = state
        return state.record, copy.deepcopy(state.observation), copy.deepcopy(state.info)

    # -- the condition ---------------------------------------------------------------------

    def _use(self, nav: PlaceNavEnv, learn: bool) -> None:
        """Run on ``nav`` from now on, the recognizer learning or only localizing."""
        self.nav = nav
        self.places.use(nav, learn)

    def _change_condition(self, pose: np.ndarray) -> tuple[dict[str, Any], dict[str, Any]]:
        """Move to the errands' world at the tour's last pose; the frame seen there, under the
        errands' condition, and its place (the map is the tour's, still learning or not)."""
        self._use(self.errand_nav, learn=self.errand_learn)
        return self.places.see(*self.nav.reset(seed=int(self.np_random.integers(2**31)),
                                               options={"pose": clear_pose(self.nav.plan,
                                                                           pose)}))

    # -- the tour --------------------------------------------------------------------------

    def _guided_tour(self, tour_seed: int) -> tuple[TourRecord, dict, dict]:
        """Drive the tour (:func:`~envs.tasks.tour.guided_tour`) and keep what it leaves."""
        poses: list[np.ndarray] = []

        def read(info: dict[str, Any]) -> int:  # the true poses, where image goals are drawn
            poses.append(info["pose"])
            return self.places.read(info)

        record, rooms, obs, info = guided_tour(
            self.places.env, self.plan, read, self.tour_steps_per_room, self.name_after,
            tour_seed, self.nav.model.opt.timestep * self.nav.n_substeps)
        self._tour_poses = np.array(poses, float).reshape(-1, 3)
        if self.recognizer is not None:
            record.place_id = resolve(self.recognizer, record.place_id)
        inside = rooms[rooms >= 0]
        self._room = int(inside[-1]) if inside.size else self._room
        self._tour, self._tour_rooms = record, rooms
        self._tour_end, self._tour_room = info["pose"].copy(), self._room
        return record, obs, info

    # -- errands ---------------------------------------------------------------------------

    def _start_errand(self, obs: dict[str, Any], info: dict[str, Any]
                      ) -> tuple[dict[str, Any], dict[str, Any]]:
        """Draw the next errand's goal (:attr:`goals`) and, if carried, its start; the
        observation and info the errand starts from."""
        room = self._last_room(info)
        goal: Goal = self.goals.draw(self, len(self._errands), info, room, self._named,
                                     self._goals)
        if self.errand_start == "carried":
            obs, info = self._carry(goal.room)
            room, self._pose = self._last_room(info), info["pose"]
        self._errands.append(Errand(goal.name, redrawn=goal.redrawn))
        self._errands[-1].shortest = self.goals.start(goal, info["pose"], room)
        return obs, info

    def _carry(self, goal: int) -> tuple[dict[str, Any], dict[str, Any]]:
        """Carry the robot away from ``goal`` (:func:`~envs.tasks.errand_draws.carry`); the
        recognizer and the true rooms learn that it was moved."""
        obs, info = carry(self.nav, self.np_random, self.goal_room, goal,
                          self.min_errand_distance)
        return self.places.relocated(obs, info)

    def _last_room(self, info: dict[str, Any]) -> int:
        """The room the robot is in or, in a doorway (no room), the one it is leaving."""
        if info["room_id"] >= 0:
            self._room = info["room_id"]
        return self._room

    def _observation(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        raw = self.places.place
        place = raw if 0 <= raw < self.max_places else self.max_places
        out = {"place_id": np.int64(place), **self.goals.observe(self)}
        keys = [k for k in self.observation_space.spaces if k not in out]
        return {**out, **{k: obs[k] for k in keys}}

    def _step_info(self, info: dict[str, Any]) -> dict[str, Any]:
        return {"errand": len(self._errands) - 1, "goal": self._errands[-1].goal,
                "place_id": self.places.place, "room_id": info["room_id"],
                "pose": info["pose"]}

