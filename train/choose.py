"""Choose a training run's policy on ``val`` buildings: rl-baselines3-zoo's ``best_model``.

    python -m train.choose runs/train/carried_place --n-scenes 4

Every checkpoint of the run (``checkpoints/ppo_<n>_steps.zip``, written by
:mod:`train.train`) and its last ``policy.zip`` runs the closed loop's errands
(:func:`envs.runs.tour_errands.run_scene`) on the same ``val`` buildings; the one with the
highest success (then SPL, then the later one) is copied to ``best_model.zip`` and every
candidate's score, with its interval over buildings, goes to ``choice.json``. Nothing is chosen
on ``test`` and the run's own files are left as they are.

The errands are the run's own: its ``errand_start``, ``n_scenes`` buildings of each of its
layouts (its config's ``env``), and its training recognizer (true rooms, or none), so choosing
costs no rendering; ``--recognizer`` and ``--layout`` choose under other conditions.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import sys
import zipfile
from pathlib import Path
from typing import Any

import yaml

from envs.runs.jobs import make_jobs, run_jobs
from envs.runs.results import summarize
from envs.runs.task_spec import ErrandTask
from envs.world.layout import room_count
from envs.world.scene import LAYOUTS
from envs.world.splits import scenes
from placeclust.argparsing import ArgumentParser

#: the file the chosen policy is copied to (rl-baselines3-zoo's name), and the record
BEST, CHOICE = "best_model.zip", "choice.json"


def candidates(run: Path) -> list[tuple[int, Path]]:
    """The run's policies as (decisions trained, file), in training order: its checkpoints,
    then the last ``policy.zip``.

    Raises:
        FileNotFoundError: ``run`` has no ``config.yml`` or no policy.
    """
    _config(run)
    found = []
    for path in Path(run, "checkpoints").glob("*_steps.zip"):
        steps = re.search(r"_(\d+)_steps\.zip$", path.name)
        if steps:
            found.append((int(steps.group(1)), path))
    last = Path(run, "policy.zip")
    if last.is_file():  # PPO rounds the budget up to whole rollouts: the model counts them
        found.append((json.loads(zipfile.ZipFile(last).read("data"))["num_timesteps"], last))
    if not found:
        raise FileNotFoundError(f"{run} holds no policy.zip nor checkpoints/*_steps.zip")
    return sorted(found, key=lambda c: (c[0], c[1].name == "policy.zip"))


def choose(run: Path, n_scenes: int = 4, rooms: int = 6, n_errands: int = 5,
           recognizer: str | None = None, layouts: list[str] | None = None, seed: int = 0,
           workers: int = 1, progress: bool = True) -> dict[str, Any]:
    """Score every candidate of ``run`` on the first ``n_scenes`` ``val`` buildings of each
    layout and copy the best to ``run/best_model.zip``; the record also goes to
    ``run/choice.json``.

    Args:
        run: a :mod:`train.train` run folder.
        n_scenes, rooms, n_errands, seed: the ``val`` buildings (per layout), their rooms,
            errands each and the episodes' seed.
        recognizer: the map's recognizer (default: the run's training one).
        layouts: the buildings' layouts (default: the run's).

    Returns:
        ``candidates`` (each one's ``decisions``, ``policy``, ``success_rate``, ``spl``
        and intervals) and the ``chosen`` one, with the conditions they were scored under.
    """
    env = _config(run)["env"]
    recognizer = recognizer or env.get("recognizer", "oracle")
    layouts = layouts or _layouts(env)
    errand_start = env.get("errand_start", "continue")
    seeds = list(scenes("val", n_scenes))
    steps = env.get("tour_steps_per_room", ErrandTask().tour_steps_per_room)
    tasks = [ErrandTask(n_errands=n_errands, tour_steps_per_room=steps,
                        errand_start=errand_start, layout=layout) for layout in layouts]
    scored = []
    for decisions, policy in candidates(run):
        jobs = [job for task in tasks
                for job in make_jobs(seeds, [recognizer], task, rooms, "ppo", seed, policy)]
        summary = summarize(run_jobs(jobs, run / "choice", workers, progress=progress))
        scored.append({"decisions": decisions, "policy": str(policy.relative_to(run)),
                       **{k: summary[k] for k in ("success_rate", "success_rate_interval",
                                                  "spl", "spl_interval")}})
    best = max(scored, key=lambda c: (c["success_rate"], c["spl"], c["decisions"]))
    shutil.copy(run / best["policy"], run / BEST)
    record = {"split": "val", "scene_seeds": seeds, "layouts": layouts, "rooms": rooms,
              "n_errands": n_errands, "seed": seed, "recognizer": recognizer,
              "errand_start": errand_start,
              "rule": "highest success, then SPL, then the later policy",
              "candidates": scored, "chosen": best}
    (run / CHOICE).write_text(json.dumps(record, indent=2))
    return record


def _config(run: Path) -> dict[str, Any]:
    path = Path(run, "config.yml")
    if not path.is_file():
        raise FileNotFoundError(f"{run} is not a training run: no config.yml (python -m "
                                "train.train writes one)")
    return yaml.safe_load(path.read_text())


def _layouts(env: dict[str, Any]) -> list[str]:
    layouts = env.get("layout", "grid")  # train.buildings.TrainBuildings: one or a list
    return [layouts] if isinstance(layouts, str) else list(layouts)


def main(argv: list[str] | None = None) -> int:
    p = ArgumentParser(prog="python -m train.choose", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", type=Path, help="a run folder of python -m train.train")
    p.add_argument("--n-scenes", type=int, default=4, help="val buildings of each layout")
    p.add_argument("--rooms", type=room_count, default=6)
    p.add_argument("--errands", "--goals-per-scene", dest="errands", type=int, default=5,
                   metavar="N", help="errands a building (--goals-per-scene: its old name)")
    p.add_argument("--recognizer", help="the map's recognizer (default: the run's training "
                   "one)")
    p.add_argument("--layout", choices=LAYOUTS, nargs="+", help="default: the run's")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--no-progress", action="store_true")
    args = p.parse_args(argv)
    if min(args.n_scenes, args.rooms, args.errands) < 1:
        p.error("--n-scenes, --rooms and --errands must be positive")
    try:
        record = choose(args.run, args.n_scenes, args.rooms, args.errands,
                        args.recognizer, args.layout, args.seed, args.workers,
                        not args.no_progress)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for c in record["candidates"]:
        low, high = c["success_rate_interval"]
        mark = " <- chosen" if c is record["chosen"] else ""
        print(f"{c['decisions']:>8} {c['policy']:<34} success {c['success_rate']:.2f} "
              f"[{low:.2f}, {high:.2f}]{mark}")
    print(f"chosen: {args.run / BEST} ({args.run / CHOICE})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
