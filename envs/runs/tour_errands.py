"""One building's guided tour and errands with an agent: the closed loop's unit of work.

:func:`run_scene` builds ``PlaceNav-GuidedTour-v1`` for a building and a recognizer, runs the
tour, and lets an agent of :data:`ERRAND_AGENTS` run the errands on the tour's map (or, with
``tracks``, every track's errands from that one tour); the commands
(:mod:`envs.commands.errands`, :mod:`envs.commands.leaderboard`) run it per building.

Examples:
    >>> row = run_scene(0, n_rooms=3, recognizer="oracle", n_errands=2, seed=0,
    ...                 tour_steps_per_room=40)
    >>> row["success_rate"], row["precision"]
    (1.0, 1.0)
"""

from __future__ import annotations

import functools
import importlib.util
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, cast

import gymnasium as gym
import numpy as np

from ..agents import hints
from ..agents.learned import LearnedAgent
from ..agents.relocalize import RelocalizingPlanner
from ..agents.spot import SpotPlanner
from ..agents.spot_memory import SpotMemoryPlanner
from ..agents.teach_repeat import TourPlanner
from ..tasks.guided_tour import GuidedTourEnv
from ..tasks.recognizers import check_recognizer_name
from ..world.textures import ASSETS
from .task_spec import ErrandTask

#: agents that run errands on a guided tour's map: ``planner`` (teach and repeat, v1's),
#: ``relocalizer`` (the planner that finds where it is again on the tour's scans: carried
#: errands, changed worlds), ``spot`` (the relocalizer that goes to an image goal's spot and
#: stops: ``goal_kind="image"``), a learned ``ppo`` policy, ``random`` actions
ERRAND_AGENTS = ("planner", "relocalizer", "spot", "spot-memory", "ppo", "random")
#: the agents that can run each kind of goal; ``spot-memory`` (placenav-v5's) also remembers
#: where it was during the errands, so every place it saw has a spot
AGENTS_FOR = {"room": ("planner", "relocalizer", "ppo", "random"),
              "image": ("spot", "spot-memory", "random")}
#: the shipped errand policy (``make train-errands``), package data of the wheel too
POLICY = ASSETS / "policies" / "errands" / "ppo_errands.zip"


def run_scene(scene_seed: int, n_rooms: int = 6, recognizer: str = "panorama",
              agent: str = "planner", n_errands: int = 5, seed: int = 0,
              policy: str | Path | None = None,
              recognizer_params: dict[str, Any] | None = None,
              tracks: Mapping[str, Mapping[str, Any]] | None = None,
              env_id: str = "PlaceNav-GuidedTour-v1", **task: Any) -> dict[str, Any]:
    """One guided tour of building ``scene_seed`` and ``n_errands`` errands; the outcome.

    Args:
        scene_seed, n_rooms: the building.
        recognizer: one of :data:`~envs.tasks.recognizers.RECOGNIZERS`, or
            ``package.module:Class`` (:func:`~envs.tasks.recognizers.make_recognizer`).
        agent: one of :data:`ERRAND_AGENTS`.
        n_errands: errands after the tour.
        seed: the episode's seed (with the scene seed: the tour's route and the errands' goals).
        policy: the ``ppo`` agent's policy (default: the shipped one); the ``config.yml``
            beside it says what it observes (:class:`~envs.agents.learned.LearnedAgent`).
        recognizer_params: the recognizer's constructor arguments.
        tracks: errands of several tracks after one tour: track name -> its errand arguments
            (``errand_start``, ``errand_condition``, ``errand_learn``). Each track's errands
            start from the tour's state (``TourState``: the map, the simulator and the random
            streams as the tour left them): the errands a tour of its own would give it.
        env_id: the task: ``PlaceNav-GuidedTour-v1`` (room or image goals, by ``goal_kind``)
            or ``PlaceNav-ImageGoal-v1`` (placenav-v5's image goals,
            :mod:`envs.tasks.image_goal`).
        **task: more arguments of ``env_id`` (the tour's, with ``tracks``): with
            ``env_id`` and ``n_errands``, an :class:`~envs.runs.task_spec.ErrandTask`'s
            :meth:`~envs.runs.task_spec.ErrandTask.kwargs` (checked as one) and any other
            argument of the env.

    Returns:
        ``success_rate``, ``spl``, ``mean_length`` (steps per errand), the tour map's
        ``precision``, ``nmi``, ``n_places``, ``places_per_room``, the ``errands`` themselves
        and ``seconds``; with ``tracks``, such a row per track under ``tracks``.
    """
    if agent not in ERRAND_AGENTS:
        raise ValueError(f"unknown agent {agent!r}; choose one of {ERRAND_AGENTS}")
    base = {"env_id": env_id, "n_errands": n_errands, **task}
    check_goals(agent, [ErrandTask.within({**base, **extra})
                        for extra in (tracks or {"": {}}).values()])
    check_recognizer_name(recognizer)
    learned = LearnedAgent.load(policy or POLICY) if agent == "ppo" else None
    head = {"scene_seed": scene_seed, "recognizer": recognizer,
            "recognizer_params": dict(recognizer_params or {}), "agent": agent}
    make = functools.partial(gym.make, env_id, recognizer=recognizer,
                             scene_seed=scene_seed, n_rooms=n_rooms, n_errands=n_errands,
                             recognizer_params=recognizer_params)
    episode = seed * 100_003 + scene_seed
    if tracks is None:
        start = time.perf_counter()
        info, errands = _errands(make(**task), episode, agent, seed, learned)
        return {**head, **_scores(errands), **info["map"], "errands": errands,
                "seconds": time.perf_counter() - start}
    rows: dict[str, Any] = {}
    state = None
    for name, extra in tracks.items():
        start = time.perf_counter()
        env = make(**task, **extra)
        if state is None:  # the tour, once: every track's errands start from what it left
            try:
                env.reset(seed=episode)
                state = cast(GuidedTourEnv, env.unwrapped).tour_state()
            except BaseException:
                env.close()
                raise
        info, errands = _errands(env, episode, agent, seed, learned, {"tour": state})
        rows[name] = {**head, **_scores(errands), **info["map"], "errands": errands,
                      "seconds": time.perf_counter() - start}
    return {**head, "tracks": rows,
            "seconds": float(sum(r["seconds"] for r in rows.values()))}


def check_goals(agent: str, tasks: Iterable[ErrandTask]) -> None:
    """A ``ValueError`` naming the agents that can, if ``agent`` cannot run the errands of
    one of ``tasks`` (:data:`AGENTS_FOR` their ``goal_kind``)."""
    for task in tasks:
        if agent not in AGENTS_FOR[task.goal_kind]:
            raise ValueError(f"the {agent} agent cannot run errands to {task.goal_kind} goals; "
                             f"choose one of {AGENTS_FOR[task.goal_kind]}")


def check_agent(agent: str, policy: Path | None) -> None:
    """Check what an agent needs before any job runs (and before any output folder is made):
    the ``ppo`` agent needs stable-baselines3 (the ``train`` extra) and its policy file.

    Raises:
        ValueError: stable-baselines3 is missing or does not import; the line says which
            extra brings it.
        FileNotFoundError: no such policy file; the line names the shipped policies.
    """
    if agent != "ppo":
        return
    if importlib.util.find_spec("stable_baselines3") is None:
        raise ValueError("the ppo agent needs stable-baselines3: pip install 'placeclust[train]' "
                         "(with torch==2.13.0 first on a CPU machine)")
    try:  # installed is not enough: a torch that does not load fails here, not in every job
        importlib.import_module("stable_baselines3")
    except Exception as exc:  # noqa: BLE001 - any failure of a broken install, named
        first = (str(exc).splitlines() or [""])[0]
        raise ValueError(f"the ppo agent needs stable-baselines3, which is installed but does "
                         f"not import ({type(exc).__name__}: {first}); reinstall it: pip "
                         "install --force-reinstall 'placeclust[train]'") from exc
    path = Path(policy or POLICY)
    if not path.is_file():
        shipped = sorted(p.parent.name for p in (ASSETS / "policies" / "tour").glob(
            "*/best_model.zip"))
        names = f", NAME one of {shipped}" if shipped else " (a clone's)"
        raise FileNotFoundError(f"no policy file {path}; the shipped errand policies are "
                                f"{ASSETS / 'policies' / 'tour'}/NAME/best_model.zip{names}; "
                                "or train one with python -m train.train")


def _errands(env: gym.Env, episode: int, agent: str, seed: int, learned: LearnedAgent | None,
             options: dict[str, Any] | None = None) -> tuple[dict[str, Any], list[dict]]:
    """Run one episode's errands on ``env`` (closed after); the reset's info and the errands."""
    if learned is not None:  # the policy sees what it was trained on (envs.agents.learned)
        env = learned.wrap(env, seed)
    try:
        obs, info = env.reset(seed=episode, options=options)
        act = _agent(agent, env, info, obs, seed) if learned is None else learned.actor()
        done = False
        while not done:
            obs, _, done, _, step_info = env.step(act(obs))
    finally:
        env.close()
    return info, step_info["errands"]


def _scores(errands: list[dict]) -> dict[str, float]:
    out = {"success_rate": float(np.mean([e["success"] for e in errands])),
           "spl": float(np.mean([e["spl"] for e in errands])),
           "mean_length": float(np.mean([e["steps"] for e in errands]))}
    if errands and "final_distance" in errands[0]:  # image goals: the distance left
        out["final_distance"] = float(np.mean([e["final_distance"] for e in errands]))
    return out


def _agent(kind: str, env: gym.Env, info: dict, obs: dict, seed: int):
    if kind == "random":
        rng = np.random.default_rng(seed)
        size = env.action_space.shape
        return lambda _obs: rng.uniform(-1, 1, size).astype(np.float32)
    kind_of = {"relocalizer": RelocalizingPlanner, "spot": SpotPlanner,
               "spot-memory": SpotMemoryPlanner}.get(kind, TourPlanner)
    planner = kind_of(unknown=hints.unknown_place(env), seed=seed)
    planner.reset(info["tour"], obs)
    return planner.act
