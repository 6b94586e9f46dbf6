"""Long runs: the online recognizer in the loop of a scripted tour for tens of thousands of steps.

    placeclust longrun [--steps 20000] [--rooms 12] [--features sift] [--window 2000]

Frames are never stored (:func:`envs.tasks.tour.tour_steps`), so memory is the recognizer's own.
Every ``window`` steps it prints the median and 95th-percentile latency of that window, the places
opened in that window and the places, graph edges and kernel features the map holds, the
process's resident memory, and the precision and NMI of all frames so far: a map that grows
without bound or slows down shows here.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.metrics import score
from placeclust.online import OnlinePlaceClustering

from ..tasks.tour import tour_steps
from ..world.layout import room_count


def resident_mb() -> float:
    """The process's resident memory now, in MiB (Linux ``/proc``; 0 elsewhere)."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return 0.0
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def map_size(model: OnlinePlaceClustering) -> dict[str, int]:
    """Places, graph edges and the kernel features the map holds in all."""
    return {"places": model.n_places, "edges": model.graph.number_of_edges(),
            "kernel_features": int(sum(len(k) for k in model.kernels.values()))}


def long_run(steps: int = 20_000, n_rooms: int = 12, features: str = "sift", scene_seed: int = 0,
             seed: int = 0, window: int = 2000, progress: bool = True,
             max_places: int | None = None) -> list[dict]:
    """Run the online recognizer for ``steps`` steps of a tour; one row per ``window`` steps.

    ``max_places`` caps the map (see :class:`~placeclust.online.OnlinePlaceClustering`).

    Returns:
        Rows with ``step``, ``ms_median``, ``ms_p95`` and ``new_places`` (this window),
        ``places``, ``edges``, ``kernel_features``, ``rss_mb``, and ``precision``/``nmi`` of all
        frames so far.
    """
    if steps < 1 or window < 1:
        raise ValueError(f"steps and window must be positive, got {steps} and {window}")
    env = gym.make("PlaceNav-v0", scene_seed=scene_seed, n_rooms=n_rooms, max_episode_steps=None)
    model = OnlinePlaceClustering(features, max_places=max_places)
    pred, room = np.empty(steps, np.int64), np.empty(steps, np.int64)
    seconds: list[float] = []
    rows: list[dict] = []
    try:
        for t, (obs, info) in enumerate(tour_steps(env, steps, seed)):
            start = time.perf_counter()
            pred[t] = model.learn_predict_one(obs["panorama"])
            seconds.append(time.perf_counter() - start)
            room[t] = info["room_id"]
            if (t + 1) % window == 0 or t + 1 == steps:
                ms = 1000.0 * np.asarray(seconds)
                so_far = score(pred[: t + 1], room[: t + 1])
                opened = model.n_places - (rows[-1]["places"] if rows else 0)
                rows.append({"step": t + 1, "ms_median": float(np.median(ms)),
                             "ms_p95": float(np.percentile(ms, 95)), "new_places": opened,
                             **map_size(model),
                             "rss_mb": resident_mb(), "precision": so_far["precision"],
                             "nmi": so_far["nmi"], "rooms_seen": so_far["n_rooms"]})
                seconds.clear()
                if progress:
                    print(_format_row(rows[-1]), flush=True)
    finally:
        env.close()
    return rows


HEADER = ("| step | ms median | ms p95 | new places | places | edges | kernel features | RSS MiB "
          "| precision | NMI |\n|---|---|---|---|---|---|---|---|---|---|")


def _format_row(r: dict) -> str:
    return (f"| {r['step']} | {r['ms_median']:.1f} | {r['ms_p95']:.1f} | {r['new_places']} | "
            f"{r['places']} | {r['edges']} | {r['kernel_features']} | {r['rss_mb']:.0f} | "
            f"{r['precision']:.3f} | {r['nmi']:.3f} |")


def main(argv: list[str] | None = None, prog: str = "placeclust longrun"
         ) -> int:
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=20_000)
    p.add_argument("--rooms", type=room_count, default=12)
    p.add_argument("--features", default="sift")
    p.add_argument("--scene-seed", type=int, default=0)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--window", type=int, default=2000)
    p.add_argument("--max-places", type=int, help="cap the map at this many places")
    p.add_argument("--json", type=Path, help="also write the rows here")
    args = p.parse_args(argv)
    if args.steps < 1 or args.window < 1:
        p.error("--steps and --window must be positive")
    cap = f", at most {args.max_places} places" if args.max_places else ""
    print(f"{args.steps} steps, {args.rooms} rooms, scene {args.scene_seed}, {args.features}{cap}")
    print(HEADER, flush=True)
    try:
        rows = long_run(args.steps, args.rooms, args.features, args.scene_seed, args.seed,
                        args.window, max_places=args.max_places)
    except ValueError as exc:
        p.error(str(exc))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
