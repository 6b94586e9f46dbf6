"""Simulator speed: ``python -m envs.benchmark`` prints env steps/s at two panorama sizes.

One process, one env, physics plus a panorama every step, random actions. With ``--docs
docs/benchmarks.md`` it also writes its table there.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time

import gymnasium as gym
import numpy as np

from placeclust.docs_section import write_section


def steps_per_second(width: int, height: int, steps: int, n_rooms: int = 4, seed: int = 0
                     ) -> float:
    """Median-of-3 env steps per second at a ``width`` x ``height`` panorama."""
    env = gym.make("PlaceNav-v0", panorama_width=width, panorama_height=height,
                   n_rooms=n_rooms, scene_seed=seed, max_episode_steps=None)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    for a in actions[:20]:  # warm up shader variants and caches
        env.step(a)
    rates = []
    for _ in range(3):
        start = time.perf_counter()
        for a in actions:
            env.step(a)
        rates.append(steps / (time.perf_counter() - start))
    env.close()
    return float(np.median(rates))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=int, default=500, help="steps per timing run")
    parser.add_argument("--rooms", type=int, default=4)
    parser.add_argument("--docs", metavar="FILE", help="also write the table into FILE's "
                        "'simulator' section (docs/benchmarks.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error(f"--steps must be positive, got {args.steps}")
    lines = [f"PlaceNav-v0, {args.rooms} rooms, {args.steps} steps x 3 runs, one process, "
             "random actions, physics and a panorama every step.", "",
             "| panorama | steps/s |", "|---|---|"]
    print(lines[0])
    for w, h in [(512, 128), (256, 64)]:
        rate = steps_per_second(w, h, args.steps, args.rooms)
        lines.append(f"| {w}x{h} | {rate:.0f} |")
        print(f"  {w}x{h}: {rate:7.0f} steps/s", flush=True)
    if args.docs:
        write_section(args.docs, "simulator", "\n".join(lines),
                      shlex.join(["python", "-m", "envs.benchmark", *argv]))


if __name__ == "__main__":
    main()
