"""Score an agent on ``PlaceNav-ReachRoom-v0``: success rate, episode length and SPL.

    python -m train.evaluate --agent {ppo,random,noplace,oracle,planner,all} [--policy PATH]
        --episodes N --seed S [--json FILE] [--config YML --policies DIR]

A recognizer in buildings never seen (a guided tour builds its map, then errands to the rooms
the guide named) is scored by ``placeclust errands``, not here; ``--task unseen``, its old
alias, says so and exits with status 2.

``--agent all`` scores every agent with its shipped policy and prints a markdown table.
``--config`` names the hyperparameter file the agents were trained with (its ``env`` sections
give the world and the sensors) and ``--policies`` the folder of their ``ppo_<agent>.zip``; the
robot with 0.8 m proximity sensors is ``--config train/hyperparams/ppo_proximity.yml
--policies assets/policies/proximity``, the corridor of identical offices ``--config
train/hyperparams/ppo_corridor.yml --policies assets/policies/corridor`` (that folder holds
its own map, which ``--map`` then defaults to). A config whose robot lacks the compass or the
rangefinders leaves the planner out of ``--agent all`` (its controller steers with them).

``ppo`` is the PPO agent that acts on the recognizer's ``place_id``; ``noplace`` and
``oracle`` are the same PPO recipe without ``place_id`` and with the true room instead
(:mod:`train.make`). Without ``--policy`` each uses its shipped policy in ``assets/policies``.
Start poses and goals come from ``--seed`` (training uses seeds below 1000; keep evaluation
seeds away from them). SPL (success weighted by path length, Anderson et al. 2018) compares
the distance driven with the walking distance from the start to the goal room's nearest door.
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
from pathlib import Path

import numpy as np

from envs.world.splits import split_of
from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from train.config import HYPERPARAMS, env_section
from train.make import PLANNER_SENSORS, SENSORS, make_env
from train.mapping import EDGES_FILE, MAP_FILE

POLICIES = Path(__file__).resolve().parent.parent / "assets" / "policies"
#: evaluation agent -> the observation set it was trained with (train.make.AGENTS)
OBSERVES = {"ppo": "place", "noplace": "noplace", "oracle": "oracle", "random": "noplace",
            "planner": "planner"}


def _episode(env, act, seed: int | None) -> tuple[bool, int, float, float]:
    obs, info = env.reset(seed=seed)
    start = info["goal_distance"]
    pose, length, steps = info["pose"][:2], 0.0, 0
    reset_agent = getattr(act, "reset", None)
    if reset_agent:
        reset_agent(obs, info)
    while True:
        obs, _, terminated, truncated, info = env.step(act(obs, info))
        steps += 1
        length += math.dist(pose, info["pose"][:2])
        pose = info["pose"][:2]
        if terminated or truncated:
            return bool(info["is_success"]), steps, start, length


class _Agent:
    """A callable ``(obs, info) -> action`` with an optional per-episode ``reset``."""

    def __init__(self, kind: str, env, policy: Path | None, seed: int, map_dir: Path,
                 stochastic: bool = False) -> None:
        self.kind = kind
        self.deterministic = not stochastic
        self.rng = np.random.default_rng(seed)
        if kind == "random":
            return
        if kind == "planner":
            from envs.agents.topological import TopologicalPlanner

            wrapper = env.get_wrapper_attr("recognizer")
            self.planner = TopologicalPlanner.from_files(wrapper, map_dir / EDGES_FILE, seed)
            return
        from stable_baselines3 import PPO

        self.model = PPO.load(policy, device="cpu")

    def reset(self, obs, info) -> None:
        if self.kind == "planner":
            self.planner.reset(obs["goal_panorama"])

    def __call__(self, obs, info) -> np.ndarray:
        if self.kind == "random":
            return self.rng.uniform(-1, 1, 2).astype(np.float32)
        if self.kind == "planner":
            return self.planner.act(obs, info)
        action, _ = self.model.predict(obs, deterministic=self.deterministic)
        return action


def evaluate(agent: str, episodes: int, seed: int, policy: Path | None = None,
             map_dir: Path | None = None, progress: bool = False,
             config_path: Path = HYPERPARAMS, stochastic: bool = False,
             policies: Path = POLICIES) -> dict[str, float]:
    """Run ``episodes`` evaluation episodes of ``agent``; returns the scores.

    PPO agents act on the mean of their action distribution unless ``stochastic`` (then they
    sample, as during training; the draws come from the policy's own seeded generator).

    The world and task settings are the ``env`` section the agent was trained with in
    ``config_path`` (the ``default`` section for ``random`` and ``planner``). Without
    ``policy``, a PPO agent's policy is ``policies/ppo_<observations>.zip``; without
    ``map_dir``, the map is ``policies``' own ``map.npz`` if it has one, else the shipped one.
    """
    if agent not in OBSERVES:
        raise ValueError(f"unknown agent {agent!r}; choose one of {sorted(OBSERVES)}")
    if episodes < 1:
        raise ValueError(f"episodes must be positive, got {episodes}")
    if agent not in ("random", "planner"):
        policy = policy or Path(policies) / f"ppo_{OBSERVES[agent]}.zip"
        if not Path(policy).is_file():
            raise FileNotFoundError(f"no policy file {policy}; train one with python -m "
                                    f"train.train --agent {OBSERVES[agent]}")
    if map_dir is None:
        map_dir = policies if (Path(policies) / MAP_FILE).is_file() else POLICIES
    env_cfg = env_section(config_path, OBSERVES[agent])
    looks = OBSERVES[agent] in ("place", "planner")
    env = make_env(OBSERVES[agent], map_path=Path(map_dir) / MAP_FILE if looks else None,
                   **env_cfg)
    act = _Agent(agent, env, policy, seed, Path(map_dir), stochastic)
    if stochastic and hasattr(act, "model"):
        act.model.set_random_seed(seed)
    from placeclust.progress import progress as progress_bar

    runs = [_episode(env, act, seed if i == 0 else None)
            for i in progress_bar(range(episodes), enabled=progress, desc=agent,
                                       unit="episode")]
    env.close()
    success = np.array([r[0] for r in runs])
    spl = [ok * best / max(best, driven, 1e-9) for ok, _, best, driven in runs]
    return {"agent": agent, "episodes": episodes, "seed": seed, "stochastic": stochastic,
            "success_rate": float(success.mean()),
            "mean_length": float(np.mean([r[1] for r in runs])),
            "spl": float(np.mean(spl))}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    pre = ArgumentParser(add_help=False)
    pre.add_argument("--task", default="reach")
    if pre.parse_known_args(argv)[0].task == "unseen":
        # train/ sits on the library and the tasks, not on the command line it would forward to
        print("python -m train.evaluate: --task unseen is now `placeclust errands` (the same "
              "options, without --task)", file=sys.stderr)
        return 2
    p = ArgumentParser(prog="python -m train.evaluate", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--task", choices=("reach",), default="reach",
                   help="PlaceNav-ReachRoom-v0 on the training building (buildings never seen: "
                   "placeclust errands)")
    p.add_argument("--agent", required=True, choices=[*sorted(OBSERVES), "all"])
    p.add_argument("--policy", type=Path, help="policy zip (default: the shipped one)")
    p.add_argument("--map", type=Path, help="folder with map.npz (default: the --policies "
                   "folder if it holds one, else the shipped map)")
    p.add_argument("--config", type=Path, default=HYPERPARAMS,
                   help="hyperparameter file the agents were trained with (world, sensors)")
    p.add_argument("--policies", type=Path, default=POLICIES,
                   help="folder of the ppo_<agent>.zip policies used without --policy")
    p.add_argument("--episodes", type=int, default=50)
    p.add_argument("--seed", type=int, default=1000)
    p.add_argument("--json", type=Path, help="also write the scores here")
    p.add_argument("--stochastic", action="store_true",
                   help="PPO agents sample actions instead of taking the mean")
    p.add_argument("--docs", metavar="FILE", help="with --agent all, also write the table "
                   "into FILE's section agents-<config> (docs/benchmarks.md)")
    args = p.parse_args(argv)
    if args.docs and args.agent != "all":
        p.error("--docs writes the table of --agent all")
    if args.agent == "all" and args.policy:
        p.error("--policy names one agent's policy; it cannot go with --agent all")
    try:
        agents = _table_agents(args.config) if args.agent == "all" else [args.agent]
        table = [evaluate(a, args.episodes, args.seed, args.policy, args.map, progress=True,
                          config_path=args.config, stochastic=args.stochastic,
                          policies=args.policies) for a in agents]
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if args.agent == "all":
        print(markdown_table(table))
        if args.docs:
            scene = env_section(args.config, "random").get("scene_seed", 0)
            body = (f"{args.episodes} episodes drawn from seed {args.seed}, configuration "
                    f"`{args.config.name}` (scene {scene}, {split_of(scene)} split: the "
                    "building the agents were trained in), PPO acting on its mean action"
                    f"{' (sampled)' if args.stochastic else ''}.\n\n{markdown_table(table)}")
            name = "agents-" + args.config.stem.replace("_", "-")
            command = shlex.join(["python", "-m", "train.evaluate", *argv])
            write_section(args.docs, name, body, command)
    else:
        print(" ".join(f"{k}={v:.3f}" if isinstance(v, float) else f"{k}={v}"
                       for k, v in table[0].items()))
    if args.json:
        args.json.write_text(json.dumps(table if args.agent == "all" else table[0], indent=2))
    return 0


TABLE_ORDER = ("random", "noplace", "planner", "ppo", "oracle")


def _table_agents(config_path: Path) -> list[str]:
    """The agents of ``--agent all``: the planner only where the robot has its sensors."""
    sensors = env_section(config_path, "planner").get("sensors", SENSORS)
    if PLANNER_SENSORS <= set(sensors):
        return list(TABLE_ORDER)
    print("the planner steers by compass and rangefinders, which this robot lacks: left out",
          file=sys.stderr)
    return [a for a in TABLE_ORDER if a != "planner"]


def markdown_table(rows: list[dict]) -> str:
    """The scores of several agents as a markdown table."""
    lines = ["| agent | success rate | mean length (steps) | SPL |", "|---|---|---|---|"]
    lines += [f"| {r['agent']} | {r['success_rate']:.2f} | {r['mean_length']:.1f} | "
              f"{r['spl']:.2f} |" for r in rows]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
