"""The ``placeclust`` command line: ``tour``, ``cluster``, ``demo`` and ``bench``.

It sits above both the library (:mod:`placeclust`) and the simulator (this package): ``tour``,
``demo`` and ``bench`` drive the simulator, ``cluster`` runs a recognizer on a recorded tour.
"""

from __future__ import annotations

import argparse
import importlib
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from placeclust import PRESETS, strict_json
from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from placeclust.features import FEATURES
from placeclust.runner import ALGORITHMS, check_params, evaluate, preset_params, run

from ..world.conditions import CONDITIONS, LIGHTING
from ..world.layout import room_count
from ..world.sensor import Sensor
from ..world.splits import SPLITS, check_split, scenes, split_of
from .bench_report import format_table

if TYPE_CHECKING:
    from ..tasks.tour import Tour
    from ..world.layout import FloorPlan
    from .bench import Matrix


def load_tour(path: str) -> tuple[np.ndarray, np.ndarray]:
    """``(frames, room)`` from a ``tour.npz``, with clear errors for missing or wrong arrays."""
    p = Path(path)
    if not p.is_file():
        _bad_input(f"tour file {path} does not exist")
    with open(p, "rb") as f:
        head = f.read(4)
    if not head:
        _bad_input(f"tour file {path} is empty")
    if head != b"PK\x03\x04":  # a .npz is a zip archive of .npy arrays
        _bad_input(f"{path} is not a .npz archive (as placeclust tour writes)")
    try:
        z = np.load(p, allow_pickle=False)
        for key in ("frames", "room"):
            if key not in z.files:
                _bad_input(f"{path} has no '{key}' array (it has {z.files})")
        frames, room = z["frames"], z["room"]
    except (OSError, ValueError, EOFError) as exc:  # a damaged archive, pickled arrays
        _bad_input(f"cannot read {path} as a .npz archive: {exc}")
    if frames.ndim not in (3, 4) or frames.dtype != np.uint8:
        _bad_input(f"'frames' must be uint8 (T, H, W[, 3]), got {frames.dtype} {frames.shape}")
    if room.shape != (len(frames),):
        _bad_input(f"'room' has shape {room.shape}, expected ({len(frames)},)")
    return frames, room


def _bad_input(message: str) -> NoReturn:
    """One line naming the problem on standard error, and exit status 2 (bad input)."""
    print(f"error: {message}", file=sys.stderr)
    raise SystemExit(2)


def cmd_tour(args: argparse.Namespace) -> None:
    if args.steps < 1:
        raise SystemExit(f"error: --steps must be a positive number of frames, got {args.steps}")
    from ..tasks.tour import record_tour

    if args.export_vpr_bench and args.query_condition == args.lighting:
        raise ValueError(f"--query-condition {args.query_condition} is the tour's own "
                         "lighting; a VPR-Bench query traversal is under another condition")
    out = Path(args.out)
    if args.camera == "forward":  # --width and --height size the forward image instead
        size = {"image_width": args.width or 320, "image_height": args.height or 240,
                "camera": "forward", "image_fov": args.fov}
    else:
        if args.fov != 70.0:
            raise ValueError("--fov sets the forward camera's field of view; the panorama's "
                             "is 360°: add --camera forward")
        size = {"width": args.width or 512, "height": args.height or 128}
    sensor = Sensor.parse(args.sensor)

    def record(**condition: object) -> tuple[Tour, FloorPlan]:
        """The tour's route in its building, under ``condition`` (default: the lighting)."""
        return record_tour(args.scene_seed, args.rooms, args.steps, args.seed,
                           progress=not args.quiet, doors=args.doors, sensor=sensor,
                           **{"lighting": args.lighting, **size, **condition})

    tour, plan = record()
    out.mkdir(parents=True, exist_ok=True)
    tour.save(str(out / "tour.npz"), scene_seed=args.scene_seed, tour_seed=args.seed,
              lighting=args.lighting, camera=args.camera)
    from .figures import save_floor_plan

    save_floor_plan(plan, str(out / "floorplan.png"), tour.pose,
                    title=f"scene {args.scene_seed}, {args.rooms} rooms, {args.steps} steps")
    print(f"wrote {out / 'tour.npz'} ({args.steps} frames, scene {args.scene_seed}: "
          f"{split_of(args.scene_seed) or 'no'} split) and {out / 'floorplan.png'}")
    if args.export_images:
        tour.export_images(args.export_images, args.lighting)
        print(f"wrote {len(tour.frames)} images and labels.csv to {args.export_images}")
    if args.export_vpr_bench:
        query, _ = record(**CONDITIONS[args.query_condition])
        truth = tour.export_vpr_bench(args.export_vpr_bench, query, args.gt_radius)
        print(f"wrote a VPR-Bench dataset to {args.export_vpr_bench}: {len(tour.frames)} ref, "
              f"{len(query.frames)} query, {np.mean([len(t) for t in truth]):.1f} references a "
              "query")


def tour_scene(path: str) -> dict[str, object]:
    """The scene seed a ``tour.npz`` was recorded in, its split and camera (those recorded)."""
    with np.load(path, allow_pickle=False) as z:
        camera: dict[str, object] = {"camera": str(z["camera"])} if "camera" in z.files else {}
        if "scene_seed" not in z.files:
            return camera
        seed = int(z["scene_seed"])
    return {"scene_seed": seed, "split": split_of(seed), **camera}


def cmd_cluster(args: argparse.Namespace) -> None:
    params: dict[str, Any] = preset_params(args.preset, args.param)
    check_params(args.algo, params)
    if args.images:
        return cluster_images(args, params)
    if args.query:
        raise ValueError("--query needs --images: a tour's queries are placeclust bench "
                         "--conditions day>night")
    frames, room = load_tour(args.tour)
    scene = tour_scene(args.tour)
    if scene.get("camera") == "forward" and params.get("view") == "sides":
        raise ValueError(f"{args.tour} was recorded by the forward camera; view='sides' keeps "
                         "the left and right of a 360° panorama, which this image does not have")
    result = run(args.algo, frames, args.features, progress=not args.quiet, **params)
    metrics = evaluate(result, room)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    np.save(out / "assignments.npy", result.assignments)
    meta = {"algo": args.algo, "features": args.features, "tour": str(args.tour),
            "preset": args.preset, "params": params, **scene}
    shapes = tour_error_shapes(args.tour, result.assignments, room)
    (out / "metrics.json").write_text(strict_json.dumps({**meta, **metrics, **shapes}, indent=2))
    print(format_table({f"{args.algo}/{args.features}": metrics}))
    if shapes:
        print(f"errors' shapes (placeclust.error_shapes): doorway lag {shapes['lag_m']:.2f} m "
              f"(median of {shapes['entries']} entries), {shapes['near_door_share']:.2f} of "
              f"wrong frames within 1 m of an entry, {shapes['revisit_new']:.2f} of "
              f"{shapes['revisits']} revisits open a place")


def tour_error_shapes(path: str, assignments: np.ndarray, room: np.ndarray
                      ) -> dict[str, float]:
    """:func:`placeclust.error_shapes.error_shapes` of a tour's places, where its poses were
    (none for a tour that recorded no poses)."""
    from placeclust.error_shapes import error_shapes

    with np.load(path, allow_pickle=False) as z:
        if "pose" not in z.files:
            return {}
        positions = z["pose"][:, :2]
    return error_shapes(assignments, room, positions)


def cluster_images(args: argparse.Namespace, params: dict[str, Any]) -> None:
    """``cluster --images DIR [--query DIR]``: an image folder or a VPR-Bench dataset (its
    ``ref/`` mapped, its ``query/`` localized and scored by its ground truth)."""
    from placeclust.datasets import ImageFolder
    from placeclust.realdata import cluster_folder, vpr_bench, with_queries, write_run
    from placeclust.vprbench import VPRBench, is_vpr_bench

    progress = not args.quiet
    query: ImageFolder | None
    if is_vpr_bench(args.images):
        if args.query:
            raise ValueError(f"{args.images} is a VPR-Bench dataset: its query/ folder is the "
                             "queries, so leave out --query")
        data = VPRBench(args.images)  # every file is checked before anything runs
        run_ = vpr_bench(args.algo, data, args.features, args.alone, progress, **params)
        mapped, query = data.ref, data.query
    else:
        mapped = ImageFolder(args.images)
        query = ImageFolder(args.query) if args.query else None
        run_ = cluster_folder(args.algo, mapped, args.features, progress=progress, **params)
        if query is not None:
            run_ = with_queries(run_, mapped, query, args.alone, progress)
    meta = {"algo": args.algo, "features": args.features, "images": str(args.images),
            "query": str(args.query or ""), "preset": args.preset, "params": params}
    write_run(args.out, run_, mapped, query, meta)
    poses = getattr(mapped, "poses", None)
    if poses is not None:  # labels.csv gave x, y: where each place is
        from .figures import save_place_map

        save_place_map(None, poses, run_.result.assignments, f"{args.out}/place_map.png",
                       f"{args.algo}: {run_.metrics['n_places']} places",
                       getattr(run_.result.model, "graph", None))
    keys = tuple(k for k in ("precision", "recall", "nmi", "n_places", "n_rooms",
                             "query_top1", "query_recall@1", "query_recall@5", "query_chance",
                             "ms_per_frame") if k in run_.metrics)
    print(format_table({f"{args.algo}/{args.features}": run_.metrics}, keys))
    print(f"wrote {args.out}/metrics.json, assignments.npy and places.png (each place's "
          "frames; place_map.png where labels.csv has poses)")


def cmd_demo(args: argparse.Namespace) -> None:
    from .demo import run_demo

    table = run_demo(args.out, scene_seed=args.scene_seed, n_rooms=args.rooms, steps=args.steps,
                     seed=args.seed)
    if args.docs:
        body = (f"Scene seed {args.scene_seed}, {args.rooms} rooms, {args.steps} frames of "
                f"512x128 panoramas, SIFT, tour seed {args.seed}.\n\n{format_table(table)}")
        write_section(args.docs, "demo", body, args.command_line)


def bench_plan(args: argparse.Namespace) -> tuple[Matrix, Path]:
    """The benchmark matrix and report folder that ``placeclust bench`` ARGS ask for."""
    from dataclasses import replace

    from .bench import SIZES

    size = "quick" if args.quick else args.size
    if args.split:
        args.scenes = args.scenes or scenes(args.split)
        check_split(args.split, args.scenes)
    # Any: the axes are tuples of str or int, steps_per_room an int; Matrix checks them
    overrides: dict[str, Any] = {name: tuple(value) for name, value in (
        ("algos", args.algos), ("features", args.features), ("scenes", args.scenes),
        ("rooms", args.rooms), ("conditions", args.conditions), ("tour_seeds", args.tour_seeds),
        ("latency_sizes", args.latency_sizes), ("datasets", args.dataset)) if value is not None}
    if args.steps_per_room is not None:
        overrides["steps_per_room"] = args.steps_per_room
    if args.doors is not None:
        overrides["doors"] = args.doors
    if args.local_light:
        overrides["local_light"] = True
    params = preset_params(args.preset, args.param)
    if params:
        overrides["params"] = tuple(params.items())
    if args.workers < 0:
        raise ValueError(f"--workers must be 0 (one per core) or more, got {args.workers}")
    return replace(SIZES[size], **overrides), Path(args.out or f"runs/bench-{size}")


def cmd_bench(args: argparse.Namespace) -> None:
    from .bench import run_bench

    matrix, out = bench_plan(args)
    run_bench(matrix, out, args.workers, args.executor, args.ray_address,
              progress=not args.quiet)
    if args.docs:  # the section is named after the report folder: runs/panorama -> panorama
        report = (out / "results.md").read_text().split("\n", 1)[1]  # less its "# " title
        write_section(args.docs, out.name, report, args.command_line)


def _add_bench(sub: argparse._SubParsersAction) -> None:
    bench = sub.add_parser("bench", help="the benchmark matrix: results.csv, table and plots",
                           description="Recognizers x features x worlds x tour seeds, in "
                           "parallel, resuming finished runs. The axes default to --size's.")
    bench.add_argument("--size", choices=("quick", "full"), default="full",
                       help="the matrix's default axes: quick (minutes) or full (hours)")
    bench.add_argument("--quick", action="store_true", help="same as --size quick")
    _add_preset(bench)
    bench.add_argument("--split", choices=tuple(SPLITS),
                       help="take the scenes from this split (its first 4 unless --scenes "
                       "names some of it): train to tune, val to choose, test to report")
    bench.add_argument("--out", help="report folder (default runs/bench-SIZE)")
    bench.add_argument("--algos", nargs="+", metavar="ALGO",
                       help=f"any of {', '.join(ALGORITHMS)}, or package.module:Class for a "
                       "recognizer of your own (placeclust.checks)")
    bench.add_argument("--features", nargs="+", choices=FEATURES)
    bench.add_argument("--scenes", nargs="*", type=int,
                       help="scene seeds of the simulated tours (none: real data sets only)")
    bench.add_argument("--doors", type=float, metavar="F",
                       help="simulated buildings with doors: F of the doorways with an automatic "
                       "door (envs.world.doors; default: open doorways)")
    bench.add_argument("--local-light", action="store_true",
                       help="simulated buildings with windows and lamps, the light baked where "
                       "it falls (envs.world.local_light; default: lit as a whole)")
    bench.add_argument("--dataset", nargs="+", metavar="DIR",
                       help="real data sets beside the simulated tours: labelled image folders "
                       "(labels.csv) or VPR-Bench folders (placeclust.datasets)")
    bench.add_argument("--rooms", nargs="+", type=room_count)
    bench.add_argument("--conditions", nargs="+", help="day, cloudy, night, moved, noisy, or "
                       "map>test as day>night (online only)")
    bench.add_argument("--tour-seeds", nargs="+", type=int)
    bench.add_argument("--steps-per-room", type=int)
    bench.add_argument("--latency-sizes", nargs="*", type=int,
                       help="map sizes of the latency sweep (none: skip it)")
    bench.add_argument("--param", action="append", metavar="NAME=VALUE",
                       help="a constructor argument of every recognizer run (repeatable), "
                            "e.g. view=sides; overrides the preset's")
    bench.add_argument("--workers", type=int, default=0, help="processes; 0: one per core")
    bench.add_argument("--executor", choices=("process", "ray"), default="process")
    bench.add_argument("--ray-address", help="Ray cluster to join (default: start a local one)")
    bench.add_argument("--quiet", action="store_true")
    _add_docs(bench)
    bench.set_defaults(func=cmd_bench)


def _add_preset(parser: argparse.ArgumentParser) -> None:
    described = "; ".join(
        f"{name}: " + (", ".join(f"{k}={v}" for k, v in args.items()) or "the library defaults "
                       "(seed 000 as published)") for name, args in PRESETS.items())
    parser.add_argument("--preset", choices=tuple(PRESETS), default="paper",
                        help=f"the recognizer's configuration ({described})")


def _add_docs(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--docs", metavar="FILE",
                        help="also write the table into FILE's generated section of this "
                        "command (docs/benchmarks.md; see placeclust.docs_section)")


def build_parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(
        prog="placeclust", description="Unsupervised, online place recognition: record tours "
        "in a simulated building, cluster them into places, benchmark recognizers.")
    sub = parser.add_subparsers(dest="command", required=True)

    tour = sub.add_parser("tour", help="drive a scripted tour and record it")
    tour.add_argument("--scene-seed", type=int, default=0)
    tour.add_argument("--rooms", type=room_count, default=4)
    tour.add_argument("--steps", type=int, default=1000)
    tour.add_argument("--seed", type=int, default=0, help="start pose and route")
    tour.add_argument("--camera", choices=("panorama", "forward"), default="panorama",
                      help="the 360° panorama, or one perspective camera looking ahead (seed "
                      "001's monocular camera)")
    tour.add_argument("--width", type=int, help="image width (panorama 512, forward 320)")
    tour.add_argument("--height", type=int, help="image height (panorama 128, forward 240)")
    tour.add_argument("--fov", type=float, default=70.0, help="the forward camera's horizontal "
                      "field of view, degrees")
    tour.add_argument("--sensor", nargs="+", metavar="NAME=VALUE", help="a real camera's "
                      "effects (envs.world.sensor: grey, exposure, shot_noise, read_noise, "
                      "motion_blur, blur, vignetting, jpeg)")
    tour.add_argument("--lighting", default="day", choices=LIGHTING)
    tour.add_argument("--doors", type=float, metavar="F", help="a building with doors: F of the "
                      "doorways with an automatic door (envs.world.doors; default: none)")
    tour.add_argument("--out", required=True)
    tour.add_argument("--export-images", metavar="DIR",
                      help="also write the frames as an image folder with labels.csv (rooms, "
                      "poses), as cluster --images reads")
    tour.add_argument("--export-vpr-bench", metavar="DIR",
                      help="also write a VPR-Bench dataset: this tour as ref/, the same route "
                      "under --query-condition as query/, and the ground truth")
    tour.add_argument("--query-condition", default="night", choices=tuple(CONDITIONS),
                      help="the query traversal's condition (default night)")
    tour.add_argument("--gt-radius", type=float, default=2.0,
                      help="a query's references: frames within this many metres in its room")
    tour.add_argument("--quiet", action="store_true")
    tour.set_defaults(func=cmd_tour)

    cluster = sub.add_parser("cluster", help="cluster a recorded tour and score it")
    cluster.add_argument("--algo", default="online", metavar="ALGO",
                         help=f"one of {', '.join(ALGORITHMS)} (default online), or "
                         "package.module:Class for a recognizer of your own (placeclust.checks)")
    cluster.add_argument("--features", choices=FEATURES, default="sift")
    source = cluster.add_mutually_exclusive_group(required=True)
    source.add_argument("--tour", help="path to tour.npz")
    source.add_argument("--images", metavar="DIR",
                        help="a folder of images in order (png or jpg; optional labels.csv: "
                        "frame,label[,x,y,heading,condition]), or a VPR-Bench dataset folder "
                        "(ref/, query/, ground_truth_new.npy): see placeclust.datasets")
    cluster.add_argument("--query", metavar="DIR",
                         help="with --images: a second folder localized on the first's map "
                         "(both labelled); a query is right when its place holds a frame of "
                         "its label")
    cluster.add_argument("--alone", action="store_true",
                         help="localize each query on its own, as VPR-Bench matches single "
                         "images (default: in order, tracking, as a robot would)")
    _add_preset(cluster)
    cluster.add_argument("--param", action="append", metavar="NAME=VALUE",
                         help="a constructor argument of the recognizer, e.g. "
                         "t_new_cluster=0.9 or scale=0.75 (repeatable; overrides the "
                         "preset's)")
    cluster.add_argument("--out", required=True)
    cluster.add_argument("--quiet", action="store_true")
    cluster.set_defaults(func=cmd_cluster)

    demo = sub.add_parser("demo", help="tour the default world and report (the main job)")
    demo.add_argument("--out", default="runs/demo")
    demo.add_argument("--scene-seed", type=int, default=0)
    demo.add_argument("--rooms", type=room_count, default=4)
    demo.add_argument("--steps", type=int, default=1000)
    demo.add_argument("--seed", type=int, default=0)
    _add_docs(demo)
    demo.set_defaults(func=cmd_demo)
    _add_bench(sub)
    for name, (_, text) in COMMANDS.items():
        sub.add_parser(name, help=text, add_help=False)  # listed here, parsed by its own main
    return parser


#: subcommands that are commands of their own, with their own options (``placeclust NAME -h``):
#: name -> (module with ``main(argv, prog)``, or ``module:function`` for another function of
#: that signature, relative to this package if it starts with a dot; help)
COMMANDS = {
    "leaderboard": (".leaderboard", "rank recognizers by errand success after a guided tour of "
                    "buildings never seen (the closed loop)"),
    "errands": (".errands", "one recognizer's errands after a guided tour of each building "
                "of a split"),
    "compare": (".compare", "two recognizers' results paired on the same buildings: the "
                "differences with their intervals"),
    "score": (".score", "one suite score over closed-loop tracks, normalized "
              "between no ids and the true rooms, with paired comparisons"),
    "seed001": (".seed001", "seed 001's experiment on its paper's forward camera"),
    "longrun": (".longrun", "the online recognizer in the loop for many steps"),
    "speed": (".speed", "the simulator's steps per second against a bare render"),
    "like": (".like", "the simulator through a real data set's camera, asked its question: "
             "does it rank recognizers as the data does"),
    "stats": ("placeclust.imagestats", "how alike a sequence's places look to local features: "
              "keypoints, matches to the next frame, across places and within (real or "
              "simulated)"),
    "latency": ("placeclust.latency", "the online recognizer's time per frame as its map grows "
                "(no simulator)"),
}


def main(argv: list[str] | None = None) -> None:
    """``placeclust ...``: a subcommand's exit status; Ctrl-C is one line and status 130
    (what a shell reports for SIGINT), saying what was kept where a command keeps runs."""
    try:
        _main(sys.argv[1:] if argv is None else list(argv))
    except KeyboardInterrupt as exc:
        print(str(exc) or "interrupted", file=sys.stderr)
        raise SystemExit(130) from None


def _main(argv: list[str]) -> None:
    if argv and argv[0] in COMMANDS:
        path, _, function = COMMANDS[argv[0]][0].partition(":")
        module = importlib.import_module(path, __package__)
        command = getattr(module, function or "main")
        raise SystemExit(command(argv[1:], prog=f"placeclust {argv[0]}"))
    args = build_parser().parse_args(argv)
    args.command_line = shlex.join(["placeclust", *argv])
    try:
        args.func(args)
    except ValueError as exc:  # bad input named by the library: no traceback for users
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from exc


if __name__ == "__main__":
    main()
