"""Errands in buildings never seen: one guided tour per building, then errands to named rooms.

Each building of a split gets one episode of ``PlaceNav-GuidedTour-v0``: the tour builds the
recognizer's map from nothing, then the agent runs ``goals`` errands on it. Nothing is trained
on the building and nothing is retrained when the recognizer changes, so the success rate
ranks recognizers by what their maps are worth to an agent.

    python -m train.evaluate --task unseen --split test --rooms 6 --recognizer online \\
        --goals-per-scene 5 --seed 0 --json runs/unseen.json

Examples:
    >>> from train.unseen import run_scene
    >>> row = run_scene(0, n_rooms=3, recognizer="oracle", goals=2, seed=0,
    ...                 tour_steps_per_room=40)
    >>> row["success_rate"], row["precision"]
    (1.0, 1.0)
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the environments)
from envs.guided_tour import RECOGNIZERS
from train.tour_planner import TourPlanner

#: agents that act on a guided tour's map; ``planner`` is the best
AGENTS = ("planner", "ppo", "random")
POLICY = Path(__file__).resolve().parent.parent / "assets" / "policies" / "errands" / \
    "ppo_errands.zip"


def run_scene(scene_seed: int, n_rooms: int = 6, recognizer: str = "online",
              agent: str = "planner", goals: int = 5, seed: int = 0,
              policy: str | Path | None = None, **task: Any) -> dict[str, Any]:
    """One guided tour of building ``scene_seed`` and ``goals`` errands; the outcome.

    Args:
        scene_seed, n_rooms: the building.
        recognizer: one of :data:`~envs.guided_tour.RECOGNIZERS`.
        agent: one of :data:`AGENTS`.
        goals: errands after the tour.
        seed: the episode's seed (with the scene seed: the tour's route and the errands' goals).
        policy: the ``ppo`` agent's policy (default: the shipped one).
        **task: more ``PlaceNav-GuidedTour-v0`` arguments.

    Returns:
        ``success_rate``, ``spl``, ``mean_length`` (steps per errand), the tour map's
        ``precision``, ``nmi``, ``n_places``, ``places_per_room``, the ``errands`` themselves
        and ``seconds``.
    """
    if agent not in AGENTS:
        raise ValueError(f"unknown agent {agent!r}; choose one of {AGENTS}")
    if recognizer not in RECOGNIZERS:
        raise ValueError(f"unknown recognizer {recognizer!r}; choose one of {RECOGNIZERS}")
    model = _load_policy(Path(policy or POLICY)) if agent == "ppo" else None
    start = time.perf_counter()
    env = gym.make("PlaceNav-GuidedTour-v0", recognizer=recognizer, scene_seed=scene_seed,
                   n_rooms=n_rooms, n_errands=goals, **task)
    if model is not None:  # the learned agent sees the planner's hints and corrects its action
        from train.errand_agent import PlannerHints

        env = PlannerHints(env, seed)
    try:
        obs, info = env.reset(seed=seed * 100_003 + scene_seed)
        act = (_agent(agent, env, info, obs, seed) if model is None
               else lambda x: model.predict(x, deterministic=True)[0])
        done = False
        while not done:
            obs, _, done, _, step_info = env.step(act(obs))
    finally:
        env.close()
    errands = step_info["errands"]
    return {"scene_seed": scene_seed, "recognizer": recognizer, "agent": agent,
            "success_rate": float(np.mean([e["success"] for e in errands])),
            "spl": float(np.mean([e["spl"] for e in errands])),
            "mean_length": float(np.mean([e["steps"] for e in errands])),
            **info["map"], "errands": errands, "seconds": time.perf_counter() - start}


def _agent(kind: str, env: gym.Env, info: dict, obs: dict, seed: int):
    if kind == "random":
        rng = np.random.default_rng(seed)
        return lambda _obs: rng.uniform(-1, 1, 2).astype(np.float32)
    planner = TourPlanner(unknown=env.unwrapped.max_places, seed=seed)
    planner.reset(info["tour"], obs)
    return planner.act


def _load_policy(policy: Path):
    """The PPO errand agent's model (:mod:`train.errand_agent`)."""
    from stable_baselines3 import PPO

    if not policy.is_file():
        raise FileNotFoundError(f"no policy file {policy}; train one with python -m "
                                "train.train --agent errands --config "
                                "train/hyperparams/ppo_errands.yml")
    return PPO.load(policy, device="cpu")


def summarize(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Scores over buildings: errand-weighted means, and the worst building's success rate."""
    errands = [e for r in rows for e in r["errands"]]
    return {
        "recognizer": rows[0]["recognizer"], "agent": rows[0]["agent"],
        "scenes": [r["scene_seed"] for r in rows], "errands": len(errands),
        "success_rate": float(np.mean([e["success"] for e in errands])),
        "worst_scene_success": float(min(r["success_rate"] for r in rows)),
        "spl": float(np.mean([e["spl"] for e in errands])),
        "mean_length": float(np.mean([e["steps"] for e in errands])),
        **{k: float(np.mean([r[k] for r in rows]))
           for k in ("precision", "nmi", "n_places", "places_per_room")},
        "seconds": float(sum(r["seconds"] for r in rows)),
    }


def main(argv: list[str] | None = None) -> int:
    """``python -m train.evaluate --task unseen ...``: one recognizer, one agent, a split."""
    import argparse
    import json
    import sys

    from envs.splits import add_scope_arguments, scope_seeds
    from train.leaderboard import make_jobs, run_jobs

    p = argparse.ArgumentParser(prog="python -m train.evaluate --task unseen",
                                description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--task", choices=("unseen",), default="unseen")
    add_scope_arguments(p, n_scenes=8)
    p.add_argument("--rooms", type=int, default=6)
    p.add_argument("--recognizer", choices=RECOGNIZERS, required=True)
    p.add_argument("--agent", choices=AGENTS, default="planner")
    p.add_argument("--policy", type=Path, help="the ppo agent's policy (default: shipped)")
    p.add_argument("--goals-per-scene", type=int, default=5)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", type=Path, help="also write the scores here")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--out", type=Path, help="keep each building's result here and resume")
    args = p.parse_args(argv)
    seeds = scope_seeds(args, p)
    if args.goals_per_scene < 1:
        p.error(f"--goals-per-scene must be positive, got {args.goals_per_scene}")
    jobs = make_jobs(seeds, [args.recognizer], args.rooms, args.agent, args.goals_per_scene,
                     args.seed, args.policy)
    try:
        rows = run_jobs(jobs, args.out, args.workers)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    summary = {**summarize(rows), "split": args.split, "rooms": args.rooms, "seed": args.seed}
    print(" ".join(f"{k}={v:.3f}" for k, v in summary.items() if isinstance(v, float)))
    if args.json:
        args.json.write_text(json.dumps({**summary, "buildings": rows}, indent=1))
    return 0
