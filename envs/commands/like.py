"""``placeclust like DATASET``: the simulator asked a real data set's question through the
data set's camera, and whether it ranks recognizers as the data does.

    placeclust like ../shared/data/vpr-bench-corridor --split val [--sensor grey=1 jpeg=75]

The measuring is :mod:`envs.runs.sim2real`'s (how a building is made like the data set, what
is kept); this module parses the command and writes the report: both sides' top-1 per
configuration, :func:`placeclust.transfer.rank_transfer`'s rank correlation (buildings
resampled on the simulated side, blocks of queries on the real side) and pairwise agreement,
and the image statistics side by side.
"""

from __future__ import annotations

import argparse
import math
import os
import shlex
import sys
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.camera import camera_of
from placeclust.docs_section import write_section
from placeclust.imagestats import stats_table
from placeclust.runner import preset_params
from placeclust.stats import interval
from placeclust.transfer import BLOCK, Transfer, block_resample, rank_transfer

from ..runs.sim2real import ALGOS, FEATURES, Matched, config_name, run_matched
from ..world.layout import room_count
from ..world.sensor import Sensor
from ..world.splits import SPLITS, check_split
from ..world.splits import scenes as split_scenes


def transfer_of(real: dict[str, Any], sims: list[dict[str, Any]], m: Matched) -> Transfer:
    """The rank comparison over the configurations that ran on both sides."""
    names = [config_name(a, f) for a, f in m.configs]
    return rank_transfer({n: [s["configs"][n]["top1"] for s in sims] for n in names},
                         {n: real["configs"][n]["hits"] for n in names})


def report(dataset: str, real: dict[str, Any], sims: list[dict[str, Any]], m: Matched
           ) -> str:
    """The markdown section: both sides per configuration, the agreement, image statistics."""
    t = transfer_of(real, sims, m)
    scenes = ", ".join(str(s["scene"]) for s in sims)
    rng = np.random.default_rng(0)
    lines = [f"Camera like `{dataset}`'s: {m.camera.describe()}; sensor "
             f"{m.sensor.as_dict() or 'none'}. Simulated: scene seeds {scenes}, {m.rooms} "
             f"rooms, {m.steps_per_room} frames a room a drive (every {m.stride}), the reference "
             f"and query drives the two halves of one tour under one light; a query's references "
             f"lie within {m.radius:g} m in its room, heading within half the field of view "
             f"({np.mean([s['queries'] for s in sims]):.0f} queries with one a building). Top-1 "
             "at the level of places (VPR-Bench's, `placeclust.vprbench`): simulated, the mean "
             "over buildings with its 95% bootstrap interval over buildings; real, over queries "
             f"with a moving-block bootstrap of {BLOCK} queries.", "",
             "| configuration | simulated top-1 [95%] | chance (sim) | real top-1 [95%] | "
             "chance (real) | places (real) |", "|---|---|---|---|---|---|"]
    for name, sim_mean in zip(t.methods, t.sim_means):
        est = interval([[s["configs"][name]["top1"]] for s in sims])
        hits = np.asarray(real["configs"][name]["hits"])
        draws = [hits[block_resample(len(hits), BLOCK, rng)].mean() for _ in range(2000)]
        low, high = np.percentile(draws, [2.5, 97.5])
        sim_chance = np.mean([s["configs"][name]["chance"] for s in sims])
        rc = real["configs"][name]
        lines.append(f"| {name} | {sim_mean:.3f} [{est.low:.3f}, {est.high:.3f}] | "
                     f"{sim_chance:.3f} | {rc['top1']:.3f} [{low:.3f}, {high:.3f}] | "
                     f"{rc['chance']:.3f} | {rc['n_places']} |")
    lines += ["", f"Spearman's rank correlation over {len(t.methods)} configurations: "
              f"{t.rho.mean:.2f} [{t.rho.low:.2f}, {t.rho.high:.2f}]; pairs ordered alike: "
              f"{t.agreement.mean:.2f} [{t.agreement.low:.2f}, {t.agreement.high:.2f}] "
              f"({t.concordant} alike, {t.discordant} opposite, {t.ties} tied on a side, of "
              f"{len(t.pairs)}).", ""]
    opposite = [p for p in t.pairs if p.verdict == "disagree"]
    if opposite:
        lines += ["Pairs the simulator orders against the data (A − B top-1; share of "
                  "resamples that order them alike):", "",
                  "| A | B | simulated A − B | real A − B | alike in resamples |",
                  "|---|---|---|---|---|"]
        lines += [f"| {p.a} | {p.b} | {p.sim:+.3f} | {p.real:+.3f} | {p.p_agree:.2f} |"
                  for p in opposite]
        lines.append("")
    stats = {f"{dataset} (ref/)": real["image_stats"],
             **{f"simulated scene {s['scene']} (reference drive)": s["image_stats"]
                for s in sims}}
    lines += ["Image statistics (SIFT, the 500 strongest keypoints, Lowe's ratio 0.8, "
              "`placeclust.imagestats`; simulated places are rooms, the data set's are not "
              "labelled):", "", stats_table(stats)]
    return "\n".join(lines)


def build_parser(prog: str) -> ArgumentParser:
    from placeclust.presets import PRESETS

    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dataset", help="a VPR-Bench folder (ref/, query/, ground truth)")
    p.add_argument("--split", choices=tuple(SPLITS), help="simulated buildings: the first 4 "
                   "of this split unless --scenes names some of it")
    p.add_argument("--scenes", nargs="+", type=int, help="simulated buildings' scene seeds")
    p.add_argument("--algos", nargs="+", default=list(ALGOS), choices=ALGOS)
    p.add_argument("--features", nargs="+", default=list(FEATURES), choices=FEATURES)
    p.add_argument("--preset", choices=tuple(PRESETS), default="paper")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="a constructor argument of every recognizer run (repeatable)")
    p.add_argument("--sensor", nargs="+", metavar="NAME=VALUE", help="the camera's effects "
                   "(envs.world.sensor: grey, exposure, shot_noise, read_noise, motion_blur, "
                   "vignetting, jpeg); a grey data set makes the camera grey")
    p.add_argument("--rooms", type=room_count, default=4)
    p.add_argument("--steps-per-room", type=int, default=100, help="frames a room a drive")
    p.add_argument("--stride", type=int, default=1, help="keep every STRIDE-th frame (a "
                   "slower frame rate)")
    p.add_argument("--radius", type=float, default=1.0, help="a query's references: within "
                   "this many metres, in its room, looking the same way")
    p.add_argument("--doors", type=float, metavar="F", help="buildings with doors (F of the "
                   "doorways with an automatic door)")
    p.add_argument("--out", help="report folder (default runs/like-NAME)")
    p.add_argument("--workers", type=int, default=0, help="processes; 0: one per core")
    p.add_argument("--executor", choices=("process", "ray"), default="process")
    p.add_argument("--ray-address", help="Ray cluster to join")
    p.add_argument("--docs", metavar="FILE", help="also write the report into FILE's section "
                   "named after the report folder (docs/benchmarks.md)")
    return p


def matched_from_args(args: argparse.Namespace) -> tuple[str, list[int], Matched, Path]:
    """The data set, scenes, settings and report folder that ARGS ask for.

    Raises:
        ValueError: a bad --stride, --radius, --steps-per-room, --sensor or split.
    """
    if args.stride < 1 or args.steps_per_room < 1:
        raise ValueError(f"--stride and --steps-per-room must be at least 1, got "
                         f"{args.stride} and {args.steps_per_room}")
    if not (math.isfinite(args.radius) and args.radius > 0):
        raise ValueError(f"--radius must be a positive number of metres, got {args.radius}")
    configs = tuple((a, f) for a in dict.fromkeys(args.algos)
                    for f in dict.fromkeys(args.features))
    scene_list = list(args.scenes or (split_scenes(args.split)[:4] if args.split else []))
    if args.split:
        check_split(args.split, scene_list)
    params = preset_params(args.preset, args.param)
    m = Matched(camera_of(args.dataset), Sensor.parse(args.sensor), configs, rooms=args.rooms,
                steps_per_room=args.steps_per_room, stride=args.stride, radius=args.radius,
                doors=args.doors, params=tuple(sorted(params.items())))
    return args.dataset, scene_list, m, Path(args.out or f"runs/like-{Path(args.dataset).name}")


def main(argv: list[str] | None = None, prog: str = "placeclust like") -> int:
    """``placeclust like DATASET ...``; the exit status (2: bad input, named in one line)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(prog).parse_args(argv)
    try:
        dataset, scene_list, m, out = matched_from_args(args)
        real, sims = run_matched(dataset, scene_list, m, out, args.workers or os.cpu_count() or 1,
                                 args.executor, args.ray_address)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    text = report(dataset, real, sims, m)
    (out / "results.md").write_text(f"# {dataset} through its own camera\n\n{text}\n")
    print(text)
    if args.docs:
        write_section(args.docs, out.name, text, shlex.join([*prog.split(), *argv]))
    return 0
