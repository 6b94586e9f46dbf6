"""Simulator speed against its floor: ``python -m envs.benchmark``.

This machine's speed drifts by 2× within an hour, so steps per second alone say little. The
command times, in one run and one process, ``env.step`` and its *floor*: a bare
``mujoco.Renderer`` render and read-back of a trivial textured scene with as many pixels as the
panorama, the least any panorama of that size can cost here. Their ratio is the figure to
compare. It also times the physics alone (``panorama=False``) and what two spawned
``AsyncVectorEnv`` workers give over one process. With ``--docs docs/benchmarks.md`` it writes
its table there.
"""

from __future__ import annotations

import argparse
import functools
import os
import shlex
import sys
import time
from collections.abc import Callable

import gymnasium as gym
import mujoco
import numpy as np

from placeclust.docs_section import write_section

SIZES = ((512, 128), (256, 64))
ENV_ID = f"{__package__}:PlaceNav-v0"  # spawned workers import this package by its own name

# A checkered floor and a box seen by one camera, with the env's visual settings (no shadows,
# no multisampling): the cheapest textured picture of a given size.
_FLOOR_XML = """
<mujoco>
  <visual><quality shadowsize="0" offsamples="0"/><global offwidth="{w}" offheight="{h}"/></visual>
  <asset>
    <texture name="grid" type="2d" builtin="checker" width="256" height="256"
             rgb1=".2 .3 .4" rgb2=".8 .7 .6"/>
    <material name="grid" texture="grid" texrepeat="8 8"/>
  </asset>
  <worldbody>
    <light pos="0 0 3"/>
    <geom type="plane" size="5 5 .1" material="grid"/>
    <geom type="box" pos="1 0 .5" size=".3 .3 .3" material="grid"/>
    <camera name="eye" pos="-2 0 1" xyaxes="0 -1 0 .3 0 1"/>
  </worldbody>
</mujoco>
"""


def _seconds(run: Callable[[], None], n: int) -> float:
    """Mean seconds of one of ``n`` calls of ``run``."""
    start = time.perf_counter()
    for _ in range(n):
        run()
    return (time.perf_counter() - start) / n


def _interleaved(runs: dict[str, Callable[[], None]], n: int, rounds: int) -> dict[str, float]:
    """Median over ``rounds`` of each run's mean time per call, the runs taken in turn each
    round, so that the machine's drift falls on all of them alike."""
    for run in runs.values():  # warm up shader variants and caches
        _seconds(run, 20)
    times: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(rounds):
        for name, run in runs.items():
            times[name].append(_seconds(run, n))
    return {name: float(np.median(t)) for name, t in times.items()}


def _floor_scene(width: int, height: int) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(_FLOOR_XML.format(w=width, h=height))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _stepper(env: gym.Env, seed: int = 0) -> Callable[[], None]:
    """One ``env.step`` with a random action per call, from a reset with ``seed``."""
    env.reset(seed=seed)
    env.action_space.seed(seed)
    return lambda: env.step(env.action_space.sample())


def size_timings(width: int, height: int, steps: int, rounds: int = 5, n_rooms: int = 4
                 ) -> dict[str, float]:
    """Seconds per call of the floor, the physics alone and ``env.step`` at one panorama size.

    The floor is a bare render and read-back of ``width`` x ``height`` pixels of a trivial
    textured scene; the physics is ``env.step`` with ``panorama=False``.
    """
    model, data = _floor_scene(width, height)
    kwargs = {"panorama_width": width, "panorama_height": height, "n_rooms": n_rooms,
              "max_episode_steps": None}
    env = gym.make("PlaceNav-v0", **kwargs)
    blind = gym.make("PlaceNav-v0", **kwargs, panorama=False)
    with mujoco.Renderer(model, height, width) as renderer:
        def floor() -> None:
            renderer.update_scene(data, "eye")
            renderer.render()

        try:
            return _interleaved({"floor": floor, "physics": _stepper(blind),
                                 "step": _stepper(env)}, steps, rounds)
        finally:
            env.close()
            blind.close()


def vector_speedup(width: int, height: int, steps: int, workers: int = 2, rounds: int = 3,
                   n_rooms: int = 4) -> float:
    """Env steps per second of ``workers`` spawned ``AsyncVectorEnv`` workers over one process
    (one env stepped in this process), measured in turn."""
    make = functools.partial(gym.make, ENV_ID, panorama_width=width, panorama_height=height,
                             n_rooms=n_rooms, max_episode_steps=None)
    env = make()
    vec = gym.vector.AsyncVectorEnv([make] * workers, context="spawn")
    try:
        vec.reset(seed=0)
        vec.action_space.seed(0)
        t = _interleaved({"one": _stepper(env),
                          "vec": lambda: vec.step(vec.action_space.sample())}, steps, rounds)
    finally:
        vec.close()
        env.close()
    return t["one"] * workers / t["vec"]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m envs.benchmark", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=200, help="calls per timing, 5 rounds")
    parser.add_argument("--rooms", type=int, default=4)
    parser.add_argument("--workers", type=int, default=2, help="AsyncVectorEnv workers")
    parser.add_argument("--docs", metavar="FILE", help="also write the table into FILE's "
                        "'simulator' section (docs/benchmarks.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    if args.steps < 1 or args.workers < 1:
        parser.error("--steps and --workers must be positive")
    lines = [f"PlaceNav-v0, scene 0, {args.rooms} rooms, random actions, one process; "
             f"medians over 5 rounds of {args.steps} calls, the three timings taken in turn. "
             "*Floor*: a bare `mujoco.Renderer` render and read-back of a trivial textured "
             "scene with the panorama's pixels; *physics*: `env.step` with `panorama=False`.",
             "", "| panorama | floor ms | physics ms | env.step ms | env.step / floor | steps/s |",
             "|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for w, h in SIZES:
        t = size_timings(w, h, args.steps, n_rooms=args.rooms)
        lines.append(f"| {w}x{h} | {1e3 * t['floor']:.2f} | {1e3 * t['physics']:.2f} | "
                     f"{1e3 * t['step']:.2f} | **{t['step'] / t['floor']:.1f}x** | "
                     f"{1 / t['step']:.0f} |")
        print(lines[-1], flush=True)
    w, h = SIZES[0]
    speedup = vector_speedup(w, h, args.steps, args.workers, n_rooms=args.rooms)
    lines += ["", f"`AsyncVectorEnv` with {args.workers} spawned workers at {w}x{h}: "
              f"**{speedup:.2f}x** the env steps per second of one process "
              f"({os.cpu_count()} CPUs; measured in turn, 3 rounds)."]
    print(lines[-1], flush=True)
    if args.docs:
        write_section(args.docs, "simulator", "\n".join(lines),
                      shlex.join(["python", "-m", "envs.benchmark", *argv]))


if __name__ == "__main__":
    main()
