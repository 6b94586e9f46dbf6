"""Train a PPO agent on ``PlaceNav-ReachRoom-v0`` (the rl-baselines3-zoo pattern).

    python -m train.train --agent place --seed 0

Hyperparameters come from ``train/hyperparams/ppo.yml`` or ``--config`` (one section per
agent, see :mod:`train.make`; read by :mod:`train.config`). The run folder
(``runs/train/<agent>_s<seed>`` by default) gets the resolved config, the place map (``place``
agent: built from a scripted tour unless ``--map`` names one), ``progress.csv`` (SB3's logger),
checkpoints, ``policy.zip`` and ``train_info.json``.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import json
import shutil
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import yaml

from envs.agents.learned import ALGOS, learner
from envs.runs.vector import single_threaded_workers
from envs.world.splits import check_split
from placeclust.argparsing import ArgumentParser
from train.config import HYPERPARAMS, load_config
from train.make import AGENTS, make_env
from train.mapping import EDGES_FILE, MAP_FILE, build_map

TRAINABLE = tuple(a for a in AGENTS if a != "planner")
#: ``env`` keys of a config that change the world a map is made in (its ``world_id``)
MAP_WORLD_KEYS = ("layout", "extra_doors", "panorama_width", "panorama_height", "n_cameras")


def prepare_map(agent: str, out: Path, env_cfg: dict[str, Any], given: Path | None,
                progress: bool, map_cfg: dict[str, Any] | None = None) -> Path | None:
    """The map file the agent localizes on (copied into ``out`` so the run is self-contained).

    Without ``given``, a new map is built (:func:`train.mapping.build_map`) with the
    recognizer arguments ``map_cfg`` (the config's ``map`` section).
    """
    if agent not in ("place", "planner"):
        return None
    if given is None:
        world = {k: env_cfg[k] for k in MAP_WORLD_KEYS if k in env_cfg}
        return build_map(out, env_cfg.get("scene_seed", 0), env_cfg.get("n_rooms", 4),
                         progress=progress, recognizer=map_cfg, **world)
    for name in (MAP_FILE, EDGES_FILE):
        if Path(given, name).resolve() != Path(out, name).resolve():
            shutil.copy(Path(given, name), out / name)
    return out / MAP_FILE


def train(agent: str, seed: int = 0, out: Path | None = None, timesteps: int | None = None,
          n_envs: int | None = None, map_dir: Path | None = None, progress: bool = True,
          config_path: Path = HYPERPARAMS) -> Path:
    """Train ``agent`` (a section of the config) and return the path of the saved policy.

    A section's ``env`` may name the :func:`train.make.make_env` agent it trains (``kind``,
    default the section's name): ``ppo_tour.yml``'s ``place`` and ``place_lstm`` both train
    ``kind: errands``, one with PPO and one with ``algo: recurrent_ppo``.
    """
    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.logger import configure
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    cfg = load_config(agent, config_path)
    env_cfg = dict(cfg.pop("env", {}))
    kind = env_cfg.pop("kind", agent)
    if kind not in TRAINABLE:
        raise ValueError(f"unknown agent {kind!r}; trainable agents are {TRAINABLE}")
    algo = cfg.pop("algo", "ppo")
    if algo not in ALGOS:
        raise ValueError(f"unknown algo {algo!r} in {config_path}; choose one of {ALGOS}")
    model_class = learner(algo)  # a missing sb3-contrib is said before any map is built
    # agents train on train-split buildings only: val chooses, test reports (envs.world.splits)
    check_split("train", env_cfg.get("scene_seeds", [env_cfg.get("scene_seed", 0)]))
    map_cfg = dict(cfg.pop("map", {}))
    # the command line overrides the file; the rest of cfg goes to PPO
    file_n_envs, file_timesteps = cfg.pop("n_envs", 1), cfg.pop("n_timesteps", None)
    n_envs, timesteps = n_envs or file_n_envs, timesteps or file_timesteps
    if timesteps is None:
        raise ValueError(f"{config_path} gives no n_timesteps for {agent!r}; pass --timesteps")
    policy = cfg.pop("policy")
    out = Path(out or f"runs/train/{agent}_s{seed}")
    out.mkdir(parents=True, exist_ok=True)
    map_path = prepare_map(kind, out, env_cfg, map_dir, progress, map_cfg)
    (out / "config.yml").write_text(yaml.safe_dump(
        {"agent": agent, "seed": seed, "n_envs": n_envs, "n_timesteps": timesteps,
         "algo": algo, "policy": policy, "env": {"kind": kind, **env_cfg},
         **_map_record(map_path, map_dir, map_cfg), **cfg}))
    with _one_thread_each(n_envs > 1):
        # spawned workers: a worker forked from a process that has rendered deadlocks in
        # Mesa's EGL
        venv = make_vec_env(functools.partial(make_env, kind, map_path=map_path, **env_cfg),
                            n_envs=n_envs, seed=seed,
                            vec_env_cls=SubprocVecEnv if n_envs > 1 else DummyVecEnv,
                            vec_env_kwargs={"start_method": "spawn"} if n_envs > 1 else None,
                            monitor_kwargs={"info_keywords": ("is_success",)})
        model = model_class(policy, venv, seed=seed, device="cpu", verbose=0, **cfg)
        model.set_logger(configure(str(out), ["csv", "stdout"] if progress else ["csv"]))
        checkpoints = CheckpointCallback(max(timesteps // 10 // n_envs, 1),
                                         str(out / "checkpoints"), name_prefix="ppo")
        start = time.perf_counter()
        # a bar on a terminal only: in a log SB3's stdout table already reports progress
        model.learn(timesteps, callback=checkpoints, progress_bar=progress and sys.stderr.isatty())
        minutes = (time.perf_counter() - start) / 60
        venv.close()
    model.save(out / "policy.zip")
    (out / "train_info.json").write_text(json.dumps(
        {"agent": agent, "algo": algo, "seed": seed, "timesteps": timesteps, "n_envs": n_envs,
         "minutes": round(minutes, 2), "versions": _versions()}, indent=2))
    return out / "policy.zip"


def _map_record(map_path: Path | None, given: Path | None, map_cfg: dict[str, Any]
                ) -> dict[str, Any]:
    """What config.yml says about the map: none, the arguments it was built with, or its source."""
    if map_path is None:
        return {}
    return {"map": map_cfg if given is None else {"copied_from": str(given)}}


@contextlib.contextmanager
def _one_thread_each(enabled: bool) -> Iterator[None]:
    """One thread for torch here, and single-threaded workers spawned meanwhile.

    When the workers fill the cores, a multi-threaded torch in the learner, or llvmpipe,
    OpenCV, OpenMP or OpenBLAS threads in a worker, starve the others: with 2 workers on 2
    cores the place agent ran at 53-57 steps/s with the default threads, 72-75 with one
    OpenMP thread each (``envs.runs.vector.single_threaded_workers`` sets the rest). Settings the
    user made win; all are restored afterwards.
    """
    import torch

    if not enabled:
        yield
        return
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        with single_threaded_workers():
            yield
    finally:
        torch.set_num_threads(threads)


def _versions() -> dict[str, str]:
    import gymnasium
    import mujoco
    import sb3_contrib
    import stable_baselines3
    import torch

    return {"stable_baselines3": stable_baselines3.__version__,
            "sb3_contrib": sb3_contrib.__version__, "torch": torch.__version__,
            "gymnasium": gymnasium.__version__, "mujoco": mujoco.__version__,
            "python": sys.version.split()[0]}


def main(argv: list[str] | None = None) -> int:
    p = ArgumentParser(prog="python -m train.train", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--agent", default="place",
                   help="a section of the config (ppo.yml: place, noplace, oracle, errands)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", type=Path, help="run folder (default runs/train/<agent>_s<seed>)")
    p.add_argument("--timesteps", type=int, help="override n_timesteps of the config")
    p.add_argument("--n-envs", type=int, help="override n_envs of the config")
    p.add_argument("--map", type=Path, help="folder with map.npz and map_edges.json to reuse")
    p.add_argument("--config", type=Path, default=HYPERPARAMS)
    p.add_argument("--no-progress", action="store_true")
    args = p.parse_args(argv)
    if args.timesteps is not None and args.timesteps < 1:
        p.error(f"--timesteps must be positive, got {args.timesteps}")
    try:
        path = train(args.agent, args.seed, args.out, args.timesteps, args.n_envs, args.map,
                     not args.no_progress, args.config)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"policy saved to {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
