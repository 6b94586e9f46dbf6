"""How far an errand agent's dead reckoning is off, errand after errand.

    python -m train.drift assets/policies/tour/continued_noplace/best_model.zip \\
        assets/policies/tour/continued_oracle/best_model.zip --n-scenes 6

Each policy runs the errands that continue from a guided tour (``PlaceNav-GuidedTour-v1``,
its training recognizer) on the first ``n_scenes`` ``val`` buildings. After every decision,
the agent's dead reckoning (:class:`~envs.agents.tour_features.TourFeatures`: odometry and
compass integrated since the tour; for ``oracle``, re-anchored at the doors) is compared with
where the robot is, both in the frame of the tour's dead-reckoned path, which the guide's
careful driving keeps within centimetres of the truth. Wheel odometry slips while a robot pushes
against a wall, so how far the estimate drifts depends on how the policy drives; the table
gives the median and 90th percentile of the error over the decisions of each quarter of the
errands, all buildings pooled.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the environments)
from envs.agents.learned import LearnedAgent, config_path
from envs.agents.tour_features import TourFeatures
from envs.runs.results import policy_name, seed_span
from envs.world.layout import room_count
from envs.world.splits import scenes
from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section

#: the errands of an episode are reported in this many consecutive groups
GROUPS = 4


def drift(policy: str | Path, scene_seeds: list[int], rooms: int = 6, errands: int = 20,
          seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Run ``policy`` on each building; its dead reckoning's error after every decision.

    Args:
        policy: a continued-errand policy whose ``config.yml`` observes tour features.
        scene_seeds, rooms: the buildings.
        errands: errands after each tour.
        seed: the episodes' seed.

    Returns:
        (errors in metres, the errand each was made in), one entry per decision.

    Raises:
        ValueError: a policy that does not act on tour features, or one of carried errands
            (a carry loses dead reckoning: there is nothing to measure).
    """
    agent = LearnedAgent.load(policy)
    task: dict[str, Any] = agent_task(policy)
    errors, errand_of = [], []
    for scene_seed in scene_seeds:
        env = agent.wrap(gym.make("PlaceNav-GuidedTour-v1", scene_seed=scene_seed,
                                  n_rooms=rooms, n_errands=errands, **task), seed)
        if not isinstance(env, TourFeatures):
            raise ValueError(f"{policy} observes {agent.observe!r}, not tour features")
        try:
            obs, info = env.reset(seed=seed * 100_003 + scene_seed)
            # the tour's frame: where its dead reckoning ends is where the robot stands
            offset = np.asarray(info["pose"][:2]) - env.position
            act, done = agent.actor(), False
            while not done:
                obs, _, done, _, info = env.step(act(obs))
                errors.append(float(np.linalg.norm(env.position + offset - info["pose"][:2])))
                errand_of.append(int(info["errand"]))
        finally:
            env.close()
    return np.asarray(errors), np.asarray(errand_of)


def agent_task(policy: str | Path) -> dict[str, Any]:
    """The ``PlaceNav-GuidedTour-v1`` arguments of ``policy``'s training: its recognizer.

    Raises:
        ValueError: a policy trained on carried errands.
    """
    import yaml

    env = yaml.safe_load(config_path(Path(policy)).read_text()).get("env", {})
    if env.get("errand_start", "continue") != "continue":
        raise ValueError(f"{policy} is a carried-errand policy: a carry loses dead reckoning")
    return {"recognizer": env.get("recognizer", "oracle")}


def table(rows: dict[str, tuple[np.ndarray, np.ndarray]], errands: int) -> str:
    """A markdown table: a row per policy, a column per group of errands."""
    edges = np.linspace(0, errands, GROUPS + 1).round().astype(int)
    head = [f"errands {a + 1}–{b}" for a, b in zip(edges[:-1], edges[1:])]
    lines = ["| policy | " + " | ".join(head) + " |", "|---" * (len(head) + 1) + "|"]
    for name, (errors, errand_of) in rows.items():
        cells = []
        for a, b in zip(edges[:-1], edges[1:]):
            part = errors[(errand_of >= a) & (errand_of < b)]
            cells.append(f"{np.median(part):.2f} ({np.percentile(part, 90):.2f})"
                         if len(part) else "–")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = ArgumentParser(prog="python -m train.drift", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("policies", nargs="+", type=Path, help="continued-errand policy files")
    p.add_argument("--n-scenes", type=int, default=6, help="val buildings")
    p.add_argument("--rooms", type=room_count, default=6)
    p.add_argument("--errands", type=int, default=20, help="errands after each tour")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's section")
    p.add_argument("--section", default="agents-drift", help="the section's name")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    if min(args.n_scenes, args.rooms, args.errands) < 1:
        p.error("--n-scenes, --rooms and --errands must be positive")
    seeds = list(scenes("val", args.n_scenes))
    try:
        rows = {policy_name(str(path)): drift(path, seeds, args.rooms, args.errands, args.seed)
                for path in args.policies}
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    body = (f"val buildings {seed_span(seeds)} ({len(seeds)}, {args.rooms} rooms, "
            f"{args.errands} errands each, continued from the tour); error of the agent's dead "
            "reckoning after each decision, metres: median (90th percentile), buildings "
            f"pooled.\n\n{table(rows, args.errands)}")
    print(body)
    if args.docs:
        write_section(args.docs, args.section, body,
                      shlex.join(["python", "-m", "train.drift", *argv]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
