"""``placeclust like DATASET``: the simulator asked a real data set's question through the
data set's camera, and whether it ranks recognizers as the data does.

    placeclust like ../shared/data/vpr-bench-corridor --split val [--sensor grey=1 jpeg=75]
    placeclust like ../shared/data/vpr-bench-corridor --split val \
        --camera-file assets/cameras/vpr-bench-corridor.json [--textures photo]

The camera is the data set's (:func:`placeclust.camera.camera_of`): its image size and colour,
and the field of view and sensor effects its ``camera.json`` states, or a camera file named by
``--camera-file`` for a data set you cannot write to; ``--sensor`` overrides single effects.
``--textures photo`` gives each simulated building's surfaces photographic statistics
(:mod:`envs.tasks.photo_textures`) before its first frame: a realism lever, not a camera.

The measuring is :mod:`envs.runs.sim2real`'s (how a building is made like the data set, what
is kept); this module parses the command and writes the report: both sides' score per
configuration (VPR-Bench's top-1 corrected for chance, with the raw top-1 and its chance beside
it and ranked too; for a labelled image folder, NMI of its clustering),
:func:`placeclust.transfer.rank_transfer`'s rank correlation (buildings
resampled on the simulated side, blocks of queries on the real side) and pairwise agreement,
and the image statistics side by side.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import sys
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.camera import CAMERA_FILE, camera_of, sensor_of
from placeclust.docs_section import write_section
from placeclust.imagestats import revisit_table, stats_table
from placeclust.metrics import nmi
from placeclust.progress import plural
from placeclust.runner import ALGORITHMS, preset_params
from placeclust.stats import Estimate, interval
from placeclust.transfer import (
    BLOCK,
    RealScore,
    Transfer,
    rank_transfer,
    transfer_difference,
)
from placeclust.vprbench import above_chance

from ..agents.lap import MAX_OFFSET
from ..runs.sim2real import (
    ALGOS,
    FEATURES,
    QUERY_ROUTES,
    QUESTIONS,
    Matched,
    condition_kwargs,
    config_name,
    question_of,
    run_matched,
)
from ..tasks.photo_textures import Photo
from ..world.conditions import CONDITIONS
from ..world.layout import room_count
from ..world.sensor import Sensor
from ..world.splits import SPLITS, check_split
from ..world.splits import scenes as split_scenes


def real_score(real: dict[str, Any], names: list[str], question: str, raw: bool = False
               ) -> RealScore:
    """The real side as :func:`placeclust.transfer.rank_transfer` resamples it: each query's
    hit and chance, top-1 above chance recomputed on the queries drawn (``raw``: top-1), or
    each frame's place and label, NMI recomputed on the frames drawn."""
    if question == "vpr-bench":
        hits = RealScore.of_means({n: real["configs"][n]["hits"] for n in names})
        if raw:
            return hits
        arrays = {n: (np.asarray(real["configs"][n]["hits"], float),
                      np.asarray(real["configs"][n]["chances"], float)) for n in names}
        return RealScore(hits.methods, hits.n_units,
                         lambda name, idx: above_chance(*(a[idx] for a in arrays[name])))
    labels = np.asarray(real["labels"])
    places = {n: np.asarray(real["configs"][n]["places"]) for n in names}

    def score(name: str, idx: np.ndarray) -> float:
        kept = idx[labels[idx] >= 0]
        return nmi(places[name][kept], labels[kept]) if len(kept) else float("nan")

    return RealScore(tuple(names), len(labels), score)


def transfer_of(real: dict[str, Any], sims: list[dict[str, Any]], m: Matched,
                algo: str | None = None, raw: bool = False) -> Transfer:
    """The rank comparison over the configurations that ran on both sides (``algo``'s alone:
    whether the simulator picks the features for one recognizer as the data does); ``raw``
    ranks a VPR-Bench question by top-1 as VPR-Bench scores it, not corrected for chance."""
    names = [config_name(a, f) for a, f in m.configs if algo in (None, a)]
    key = "top1" if raw else "score"
    return rank_transfer({n: [s["configs"][n][key] for s in sims] for n in names},
                         real_score(real, names, m.question, raw))


def _agreement(t: Transfer) -> str:
    return (f"Spearman {t.rho.mean:.2f} [{t.rho.low:.2f}, {t.rho.high:.2f}], pairs ordered "
            f"alike {t.agreement.mean:.2f} [{t.agreement.low:.2f}, {t.agreement.high:.2f}]")


def _within(real: dict[str, Any], sims: list[dict[str, Any]], m: Matched) -> list[str]:
    """One line per recognizer run with 3 features or more: its own rank agreement, which a
    ranking carried by one recognizer failing on both sides would hide."""
    lines = []
    for algo in dict.fromkeys(a for a, _ in m.configs):
        n = sum(a == algo for a, _ in m.configs)
        if n >= 3:
            lines.append(f"- `{algo}` over its {n} features: "
                         f"{_agreement(transfer_of(real, sims, m, algo))}")
    return lines


def _question(m: Matched) -> str:
    if m.question == "images":
        return ("one drive of the tour, clustered; NMI against its rooms, as the folder's "
                "against its labels (`placeclust.realdata.cluster_folder`)")
    if m.query_route == "lap":
        drives, query = (f"a drive of the tour and the same path driven again up to "
                         f"{MAX_OFFSET:g} m to one side (a second lap, `envs.agents.lap`)",
                         "lap")
    else:
        drives, query = "the two halves of one tour", "half driven again"
    drives += (" under one light" if not m.query_conditions else
               f", the query {query} under `{' + '.join(m.query_conditions)}`")
    return (f"the reference and query drives {drives}; a query's references lie within "
            f"{m.radius:g} m in its room, heading within half the field of view; top-1 at "
            "the level of places (VPR-Bench's, `placeclust.vprbench`) above chance, "
            "(top-1 − chance) / (1 − chance), chance being what a uniformly drawn place of "
            "the map scores (a map of one place scores 0, not 1)")


def _textures(m: Matched) -> str:
    p = m.photo
    return "" if p is None else (f"; surfaces with photographic statistics (detail "
                                 f"{p.detail:g}, grain {p.grain:g}, {p.stains} stains)")


def _row(name: str, sims: list[dict[str, Any]], sim_mean: float, on_real: Estimate,
         rc: dict[str, Any]) -> str:
    """One configuration's row: both sides' score with intervals; for a VPR-Bench question
    the raw top-1 and chance beside them."""
    est = interval([[s["configs"][name]["score"]] for s in sims])
    cells = [name, f"{sim_mean:.3f} [{est.low:.3f}, {est.high:.3f}]",
             f"{on_real.mean:.3f} [{on_real.low:.3f}, {on_real.high:.3f}]"]
    if "top1" in rc:
        sim_top1 = np.mean([s["configs"][name]["top1"] for s in sims])
        sim_chance = np.mean([s["configs"][name]["chance"] for s in sims])
        cells += [f"{sim_top1:.3f} ({sim_chance:.3f})", f"{rc['top1']:.3f} ({rc['chance']:.3f})"]
    return "| " + " | ".join([*cells, str(rc["n_places"])]) + " |"


def _header(metric: str, raw: bool) -> list[str]:
    """The table's head: with ``raw``, columns of top-1 and its chance on each side."""
    cells = ["configuration", f"simulated {metric} [95%]", f"real {metric} [95%]"]
    if raw:
        cells += ["simulated top-1 (chance)", "real top-1 (chance)"]
    cells.append("places (real)")
    return ["| " + " | ".join(cells) + " |", "|" + "---|" * len(cells)]


def report(dataset: str, real: dict[str, Any], sims: list[dict[str, Any]], m: Matched
           ) -> str:
    """The markdown section: both sides per configuration, the agreement, image statistics."""
    t = transfer_of(real, sims, m)
    metric = QUESTIONS[m.question]
    names = list(t.methods)
    units = "queries" if m.question == "vpr-bench" else "frames"
    lines = [f"Camera like `{dataset}`'s: {m.camera.describe()}; sensor "
             f"{m.sensor.as_dict() or 'none'}{_textures(m)}. Simulated: scene seeds "
             f"{', '.join(str(s['scene']) for s in sims)}, {m.rooms} rooms, "
             f"{m.steps_per_room} frames a room a drive (every {m.stride}); {_question(m)} "
             f"({np.mean([s['queries'] for s in sims]):.0f} {units} scored a building). "
             f"Simulated {metric}: the mean over buildings with its 95% bootstrap interval over "
             f"buildings; real: with a moving-block bootstrap of {BLOCK} {units}.", "",
             *_header(metric, "top1" in real["configs"][names[0]])]
    lines += [_row(name, sims, sim_mean, t.real[k], real["configs"][name])
              for k, (name, sim_mean) in enumerate(zip(names, t.sim_means))]
    lines += ["", f"Spearman's rank correlation over {len(names)} configurations: "
              f"{t.rho.mean:.2f} [{t.rho.low:.2f}, {t.rho.high:.2f}]; pairs ordered alike: "
              f"{t.agreement.mean:.2f} [{t.agreement.low:.2f}, {t.agreement.high:.2f}] "
              f"({t.concordant} alike, {t.discordant} opposite, {t.ties} tied on a side, of "
              f"{len(t.pairs)}).", ""]
    if m.question == "vpr-bench":
        lines += [f"Ranked by raw top-1 (VPR-Bench's score, not corrected for chance): "
                  f"{_agreement(transfer_of(real, sims, m, raw=True))}.", ""]
    within = _within(real, sims, m)
    if within:
        lines += ["Within one recognizer (the features ranked for it):", "", *within, ""]
    opposite = [p for p in t.pairs if p.verdict == "disagree"]
    if opposite:
        lines += [f"Pairs the simulator orders against the data (A − B {metric}; share of "
                  "resamples that order them alike):", "",
                  "| A | B | simulated A − B | real A − B | alike in resamples |",
                  "|---|---|---|---|---|"]
        lines += [f"| {p.a} | {p.b} | {p.sim:+.3f} | {p.real:+.3f} | {p.p_agree:.2f} |"
                  for p in opposite]
        lines.append("")
    stats = {f"{dataset}": real["image_stats"],
             **{f"simulated scene {s['scene']}": s["image_stats"] for s in sims}}
    lines += ["Image statistics (SIFT, the 500 strongest keypoints, Lowe's ratio 0.8, "
              "`placeclust.imagestats`; simulated places are rooms):", "", stats_table(stats)]
    if "revisit" in real and all("revisit" in s for s in sims):
        revisit = {f"{dataset}": real["revisit"],
                   **{f"simulated scene {s['scene']}": s["revisit"] for s in sims}}
        lines += ["", "What a localizer sees: each query's most matches with one of its "
                  "references (`placeclust.imagestats.revisit_stats`; the nested mapper opens "
                  "a location under 25):", "", revisit_table(revisit)]
    return "\n".join(lines)


def build_parser(prog: str) -> ArgumentParser:
    from placeclust.presets import PRESETS

    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dataset", help="a VPR-Bench folder (ref/, query/, ground truth), a "
                   "drive with a loop-closure matrix (same_place.bmp) or an image folder with "
                   "labels.csv")
    p.add_argument("--split", choices=tuple(SPLITS), help="simulated buildings: the first 4 "
                   "of this split unless --scenes names some of it")
    p.add_argument("--scenes", nargs="+", type=int, help="simulated buildings' scene seeds")
    p.add_argument("--algos", nargs="+", default=list(ALGOS), choices=ALGORITHMS,
                   help=f"recognizers (default {' '.join(ALGOS)}; a VPR-Bench data set needs "
                   "ones that localize on a fixed map)")
    p.add_argument("--features", nargs="+", default=list(FEATURES), choices=FEATURES)
    p.add_argument("--preset", choices=tuple(PRESETS), default="paper")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="a constructor argument of every recognizer run (repeatable)")
    p.add_argument("--camera-file", metavar="FILE", help="a camera.json describing the data "
                   "set's camera (field of view, colour, sensor effects), read instead of its "
                   "own; assets/cameras/ holds those measured here")
    p.add_argument("--sensor", nargs="+", metavar="NAME=VALUE", help="the camera's effects "
                   "(envs.world.sensor: grey, exposure, shot_noise, read_noise, motion_blur, blur, "
                   "vignetting, jpeg), each replacing the camera file's; a grey data set makes "
                   "the camera grey")
    p.add_argument("--textures", choices=("plain", "photo"), default="plain",
                   help="photo: walls, floors and furniture given photographic statistics "
                   "(envs.tasks.photo_textures, a realism lever at its measured settings); "
                   "plain: PlaceNav-v0's own")
    p.add_argument("--rooms", type=room_count, default=4)
    p.add_argument("--steps-per-room", type=int, default=100, help="frames a room a drive")
    p.add_argument("--stride", type=int, default=1, help="keep every STRIDE-th frame (a "
                   "slower frame rate)")
    p.add_argument("--radius", type=float, default=1.0, help="a query's references: within "
                   "this many metres, in its room, looking the same way")
    p.add_argument("--doors", type=float, metavar="F", help="buildings with doors (F of the "
                   "doorways with an automatic door)")
    p.add_argument("--query-condition", nargs="+", choices=tuple(CONDITIONS), default=[],
                   help="a VPR-Bench question's query drive under these conditions together "
                   "(a lighting, an appearance change; the reference drive's otherwise): the "
                   "same route on another day")
    p.add_argument("--query-route", choices=QUERY_ROUTES, default="tour",
                   help="a VPR-Bench question's query drive: tour, the tour's second half (its "
                   "rooms again along other paths); lap, the reference drive's path driven "
                   "again a little to one side, as a data set's second traversal is")
    p.add_argument("--against", metavar="OUT", help="another like run's report folder on the "
                   "same buildings (the same command without a lever): the report adds how "
                   "much better this one ranks, paired over buildings")
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
        ValueError: a data set of neither kind, recognizers a VPR-Bench set's queries cannot
            use, a bad --stride, --radius, --steps-per-room, --sensor, camera file or split.
    """
    if args.stride < 1 or args.steps_per_room < 1:
        raise ValueError(f"--stride and --steps-per-room must be at least 1, got "
                         f"{args.stride} and {args.steps_per_room}")
    if not (math.isfinite(args.radius) and args.radius > 0):
        raise ValueError(f"--radius must be a positive number of metres, got {args.radius}")
    question = question_of(args.dataset)
    condition_kwargs(tuple(args.query_condition))  # a ValueError for two lightings
    if (args.query_condition or args.query_route != "tour") and question != "vpr-bench":
        raise ValueError(f"--query-condition and --query-route set a query drive, and "
                         f"{args.dataset} asks no queries (a labelled folder is clustered as "
                         "one drive)")
    cannot = [a for a in args.algos if a not in ALGOS]
    if question == "vpr-bench" and cannot:
        raise ValueError(f"{', '.join(cannot)} cannot localize on a fixed map, which "
                         f"{args.dataset}'s queries need; use {' or '.join(ALGOS)}")
    configs = tuple((a, f) for a in dict.fromkeys(args.algos)
                    for f in dict.fromkeys(args.features))
    scene_list = list(args.scenes or (split_scenes(args.split)[:4] if args.split else []))
    if args.split:
        check_split(args.split, scene_list)
    params = preset_params(args.preset, args.param)
    where = args.camera_file or str(Path(args.dataset) / CAMERA_FILE)
    stated = Sensor.of(sensor_of(args.dataset, args.camera_file), where)
    m = Matched(camera_of(args.dataset, args.camera_file), Sensor.parse(args.sensor, stated),
                configs, question, rooms=args.rooms, steps_per_room=args.steps_per_room,
                stride=args.stride, radius=args.radius, doors=args.doors,
                params=tuple(sorted(params.items())),
                query_conditions=tuple(args.query_condition),
                photo=Photo() if args.textures == "photo" else None,
                query_route=args.query_route)
    return args.dataset, scene_list, m, Path(args.out or f"runs/like-{Path(args.dataset).name}")


def baseline_of(folder: str, scenes: list[int], m: Matched) -> list[dict[str, Any]]:
    """The buildings ``scenes`` of the like run kept in ``folder`` (``--against``).

    Raises:
        ValueError: a building is not kept there, or lacks one of ``m``'s configurations.
    """
    out = []
    for scene in scenes:
        path = Path(folder) / "sim" / f"scene_{scene}.json"
        if not path.is_file():
            raise ValueError(f"--against {folder}: no building {scene} kept there "
                             f"({path} missing); run it on the same scenes first")
        kept = json.loads(path.read_text())
        missing = [config_name(a, f) for a, f in m.configs
                   if config_name(a, f) not in kept["configs"]]
        if missing:
            raise ValueError(f"--against {folder}: building {scene} lacks {', '.join(missing)}")
        out.append(kept)
    return out


def against(real: dict[str, Any], sims: list[dict[str, Any]], base: list[dict[str, Any]],
            folder: str, m: Matched) -> str:
    """The report's paragraph: this run's rank agreement against ``folder``'s, paired."""
    names = [config_name(a, f) for a, f in m.configs]
    rho, alike = transfer_difference(
        {n: [s["configs"][n]["score"] for s in sims] for n in names},
        {n: [s["configs"][n]["score"] for s in base] for n in names},
        real_score(real, names, m.question))
    return (f"Against `{folder}` (the same {plural(len(sims), 'building')}, resampled together, "
            f"and the same real draws): Spearman {_signed(rho)}, pairs ordered alike "
            f"{_signed(alike)} (this run minus that one).")


def _signed(e: Estimate) -> str:
    if not math.isfinite(e.mean):  # Spearman's rho of fewer than 3 configurations
        return "undefined"
    return f"{e.mean:+.2f} [{e.low:+.2f}, {e.high:+.2f}]"


def main(argv: list[str] | None = None, prog: str = "placeclust like") -> int:
    """``placeclust like DATASET ...``; the exit status (2: bad input, named in one line)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(prog).parse_args(argv)
    try:
        dataset, scene_list, m, out = matched_from_args(args)
        base = baseline_of(args.against, scene_list, m) if args.against else None
        real, sims = run_matched(dataset, scene_list, m, out, args.workers or os.cpu_count() or 1,
                                 args.executor, args.ray_address)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    text = report(dataset, real, sims, m)
    if base is not None:
        text += "\n\n" + against(real, sims, base, args.against, m)
    (out / "results.md").write_text(f"# {dataset} through its own camera\n\n{text}\n")
    print(text)
    if args.docs:
        write_section(args.docs, out.name, text, shlex.join([*prog.split(), *argv]))
    return 0
