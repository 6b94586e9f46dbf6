"""Simulator speed against its floor: ``placeclust speed``.

This machine's speed drifts by 2× within an hour, so steps per second alone say little. The
command times, in one run and one process, ``env.step`` and its *floor*: a bare
``mujoco.Renderer`` render and read-back of a trivial textured scene with as many pixels as the
panorama, the least any panorama of that size can cost here. Their ratio is the figure to
compare. It also times the physics alone (``panorama=False``) and what two spawned
``AsyncVectorEnv`` workers give over one process. With ``--docs docs/benchmarks.md`` it writes
its table there. ``--sensor`` times each camera effect of :mod:`envs.world.sensor` against
``env.step`` with a forward camera instead.
"""

from __future__ import annotations

import argparse
import functools
import os
import resource
import shlex
import sys
import time
from collections.abc import Callable, Mapping
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section

from ..runs.vector import make_vector_env
from ..world.sensor import Sensor

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


def _cpu_seconds() -> float:
    """CPU time of this process, all its threads (llvmpipe's rasterizers among them)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _seconds(run: Callable[[], object], n: int) -> tuple[float, float]:
    """Mean wall and CPU seconds of one of ``n`` calls of ``run``."""
    wall, cpu = time.perf_counter(), _cpu_seconds()
    for _ in range(n):
        run()
    return (time.perf_counter() - wall) / n, (_cpu_seconds() - cpu) / n


def _interleaved(runs: Mapping[str, Callable[[], object]], n: int, rounds: int
                 ) -> dict[str, np.ndarray]:
    """Each run's (wall, CPU) seconds per call, one row per round: the runs are taken in turn
    each round, so that the machine's drift falls on all of them alike and a ratio of two runs
    is best taken round by round."""
    for run in runs.values():  # warm up shader variants and caches
        _seconds(run, 20)
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in runs}
    for _ in range(rounds):
        for name, run in runs.items():
            times[name].append(_seconds(run, n))
    return {name: np.array(t) for name, t in times.items()}


def ratio(times: dict[str, np.ndarray], num: str, den: str) -> float:
    """Median over rounds of ``num``'s wall time over ``den``'s."""
    return float(np.median(times[num][:, 0] / times[den][:, 0]))


def _floor_scene(width: int, height: int) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(_FLOOR_XML.format(w=width, h=height))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _stepper(env: gym.Env, seed: int = 0) -> Callable[[], None]:
    """One ``env.step`` with a random action per call, from a reset with ``seed``."""
    env.reset(seed=seed)
    env.action_space.seed(seed)

    def step() -> None:
        env.step(env.action_space.sample())

    return step


def size_timings(width: int, height: int, steps: int, rounds: int = 5, n_rooms: int = 4,
                 scene_seed: int = 0, **world: Any) -> dict[str, np.ndarray]:
    """Seconds per call (rows: rounds; columns: wall, CPU) of the floor, the physics alone and
    ``env.step`` at one panorama size, in a building with ``world``'s options.

    The floor is a bare render and read-back of ``width`` x ``height`` pixels of a trivial
    textured scene; the physics is ``env.step`` with ``panorama=False``.
    """
    model, data = _floor_scene(width, height)
    kwargs: dict[str, Any] = {"panorama_width": width, "panorama_height": height,
                              "n_rooms": n_rooms, "scene_seed": scene_seed,
                              "max_episode_steps": None, **world}
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


def vector_speedups(width: int, height: int, steps: int, workers: int = 2, rounds: int = 3,
                    n_rooms: int = 4) -> dict[str, float]:
    """Env steps per second of ``workers`` spawned ``AsyncVectorEnv`` workers over one process
    (one env stepped in this process), measured in turn: workers with the default threads, and
    single-threaded ones (:func:`envs.runs.vector.make_vector_env`)."""
    kwargs: dict[str, Any] = {"panorama_width": width, "panorama_height": height,
                              "n_rooms": n_rooms, "max_episode_steps": None}
    make = functools.partial(gym.make, ENV_ID, **kwargs)
    env = make()
    vecs = {"default threads": gym.vector.AsyncVectorEnv([make] * workers, context="spawn"),
            "single-threaded": make_vector_env(workers, **kwargs)}
    try:
        runs = {"one": _stepper(env)}
        for name, vec in vecs.items():
            vec.reset(seed=0)
            vec.action_space.seed(0)
            runs[name] = functools.partial(lambda v: v.step(v.action_space.sample()), vec)
        t = _interleaved(runs, steps, rounds)
    finally:
        for vec in vecs.values():
            vec.close()
        env.close()
    return {name: workers * ratio(t, "one", name) for name in vecs}


#: (width, height, rooms) of the rows: the two sizes of the issue in the default world, and a
#: building three times as large, where culling matters most
#: (width, height, rooms, world options): the last two, windows and lamps by day and by night
#: (:mod:`envs.world.local_light`), say what baked light costs beside the first
ROWS: tuple[tuple[int, int, int, dict[str, Any]], ...] = (
    (512, 128, 4, {}), (256, 64, 4, {}), (512, 128, 12, {}),
    (512, 128, 4, {"local_light": True}), (512, 128, 4, {"local_light": True, "lighting": "night"}))


#: each camera effect of :class:`envs.world.sensor.Sensor` alone, at a setting a cheap real
#: camera shows, then all of them; the motion blur at a 9-pixel smear (a turn at 0.5 rad/s
#: with a 20 ms exposure and a 900-pixel focal length is 9 pixels)
EFFECTS: dict[str, tuple[Sensor, float]] = {
    "grey": (Sensor(grey=True), 0.0), "exposure +0.5 EV": (Sensor(exposure=0.5), 0.0),
    "shot + read noise": (Sensor(shot_noise=1.0, read_noise=2.0), 0.0),
    "motion blur, 9 px": (Sensor(motion_blur=0.02), 9.0), "lens blur 1 px": (Sensor(blur=1.0), 0.0),
    "vignetting 0.3": (Sensor(vignetting=0.3), 0.0), "JPEG 75": (Sensor(jpeg=75), 0.0),
    "all of them": (Sensor(grey=True, exposure=0.5, shot_noise=1.0, read_noise=2.0,
                           motion_blur=0.02, blur=1.0, vignetting=0.3, jpeg=75), 9.0)}
#: forward-camera sizes the effects are timed at: the corridor's, the env's default, RTAB-Map's
SENSOR_SIZES = ((160, 120), (320, 240), (512, 384))


def sensor_timings(width: int, height: int, steps: int, rounds: int = 5
                   ) -> dict[str, np.ndarray]:
    """Seconds per call (rows: rounds; columns: wall, CPU) of ``env.step`` with a ``width`` x
    ``height`` forward camera and of each of :data:`EFFECTS` on one of its frames."""
    env = gym.make("PlaceNav-v0", camera="forward", image_width=width, image_height=height,
                   max_episode_steps=None)
    frame = env.reset(seed=0)[0]["image"]
    rng = np.random.default_rng(0)
    runs: dict[str, Callable[[], object]] = {"step": _stepper(env)}
    for name, (sensor, blur) in EFFECTS.items():
        runs[name] = functools.partial(sensor.apply, frame, rng, blur)
    try:
        return _interleaved(runs, steps, rounds)
    finally:
        env.close()


def sensor_table(steps: int, rounds: int) -> str:
    """The cost of each camera effect as a share of ``env.step`` at each of
    :data:`SENSOR_SIZES`, medians over rounds taken in turn."""
    lines = [f"Each camera effect (`envs.world.sensor.Sensor`) on one rendered forward frame, "
             f"as a share of `env.step` with that camera (PlaceNav-v0, scene 0, random "
             f"actions, one process); medians over {rounds} rounds of {steps} calls taken in "
             "turn, the ratio round by round. `env.step` ms is context only.", "",
             "| effect | " + " | ".join(f"{w}x{h}" for w, h in SENSOR_SIZES) + " |",
             "|---|" + "---|" * len(SENSOR_SIZES)]
    timings = [sensor_timings(w, h, steps, rounds) for w, h in SENSOR_SIZES]
    lines.append("| `env.step` ms | " + " | ".join(
        f"{1e3 * np.median(t['step'][:, 0]):.2f}" for t in timings) + " |")
    for name in EFFECTS:
        lines.append(f"| {name} | " + " | ".join(
            f"{ratio(t, name, 'step'):.3f}" for t in timings) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None, prog: str = "placeclust speed"
         ) -> None:
    parser = ArgumentParser(prog=prog, description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=100, help="calls per timing and round")
    parser.add_argument("--rounds", type=int, default=15, help="rounds of the three timings")
    parser.add_argument("--workers", type=int, default=2, help="AsyncVectorEnv workers")
    parser.add_argument("--sensor", action="store_true", help="instead: each camera "
                        "effect's cost against env.step (section 'sensor-costs')")
    parser.add_argument("--docs", metavar="FILE", help="also write the table into FILE's "
                        "'simulator' section (docs/benchmarks.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    if args.steps < 1 or args.workers < 1 or args.rounds < 1:
        parser.error("--steps, --rounds and --workers must be positive")
    if args.sensor:
        table = sensor_table(args.steps, args.rounds)
        print(table)
        if args.docs:
            write_section(args.docs, "sensor-costs", table, shlex.join([*prog.split(), *argv]))
        return
    lines = [f"PlaceNav-v0, scene 0, random actions, one process; medians over {args.rounds} "
             f"rounds of {args.steps} calls, the three timings taken in turn and the ratio taken "
             "round by round. *Floor*: a bare `mujoco.Renderer` render and read-back of a "
             "trivial textured scene with the panorama's pixels; *physics*: `env.step` with "
             "`panorama=False`; *cores*: CPU time over wall time of `env.step` (all threads).",
             "", "| panorama | rooms | world | floor ms | physics ms | env.step ms "
             "| env.step / floor | cores | steps/s |", "|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    cores = []
    for w, h, rooms, world in ROWS:
        t = size_timings(w, h, args.steps, args.rounds, n_rooms=rooms, **world)
        step = np.median(t["step"], axis=0)
        cores.append(step[1] / step[0])
        options = " ".join(f"{k}={v}" for k, v in world.items()) or "as built"
        lines.append(f"| {w}x{h} | {rooms} | {options} | "
                     f"{1e3 * np.median(t['floor'][:, 0]):.2f} | "
                     f"{1e3 * np.median(t['physics'][:, 0]):.2f} | {1e3 * step[0]:.2f} | "
                     f"**{ratio(t, 'step', 'floor'):.2f}x** | {cores[-1]:.2f} | "
                     f"{1 / step[0]:.0f} |")
        print(lines[-1], flush=True)
    w, h, rooms, _ = ROWS[0]
    speedup = vector_speedups(w, h, args.steps, args.workers, n_rooms=rooms)
    lines += ["", f"`AsyncVectorEnv` with {args.workers} spawned workers at {w}x{h}, in env "
              f"steps per second over one process: **{speedup['single-threaded']:.2f}x** with "
              f"single-threaded workers (`envs.runs.vector.make_vector_env`), "
              f"{speedup['default threads']:.2f}x with the default threads ({os.cpu_count()} "
              f"CPUs; measured in turn, 3 rounds). One process already keeps {cores[0]:.2f} "
              f"cores busy, so {args.workers} workers can give at most "
              f"{min(args.workers, os.cpu_count() or 1) / cores[0]:.2f}x here."]
    print(lines[-1], flush=True)
    if args.docs:
        write_section(args.docs, "simulator", "\n".join(lines),
                      shlex.join([*prog.split(), *argv]))


if __name__ == "__main__":
    main()
