"""Benchmarks of the recognizers: latency as the map grows, and quality on simulated tours.

    python -m placeclust.benchmark latency [--features sift orb] [--sizes 10 100 500]
    python -m placeclust.benchmark tours [--features sift orb] [--scenes 0 1 2] [--rooms 4 8]

``latency`` needs no simulator: it grows a map of synthetic places and times the online
recognizer at each size on frames it tracks (the current place) and on frames of a random
earlier place (a loop closure through the relocalization index). ``tours`` records scripted
tours of the simulator (cached in ``--cache``) and scores every recognizer against the rooms.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from placeclust.online import OnlinePlaceClustering
from placeclust.synthetic import jitter, textured


def _median_ms(model: OnlinePlaceClustering, frames: list[np.ndarray]) -> float:
    times = []
    for f in frames:
        start = time.perf_counter()
        model.learn_predict_one(f)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.median(times))


def latency_vs_map_size(features: str, sizes: list[int], probes: int = 30, seed: int = 0
                        ) -> list[dict[str, float]]:
    """Median ms per frame at each map size, for tracking and for loop closures.

    The map grows with one synthetic place per new image (512×128); after it reaches each size,
    ``probes`` frames of the current place and ``probes`` revisits of random earlier places are
    timed (they may update kernels, as in real use, but open no place).
    """
    rng = np.random.default_rng(seed)
    model = OnlinePlaceClustering(features)
    bases: list[np.ndarray] = []
    rows = []
    for size in sorted(sizes):
        while len(bases) < size:
            bases.append(textured(10_000 + len(bases)))
            model.learn_one(bases[-1])
        here = bases[-1]
        track = _median_ms(model, [jitter(here, rng) for _ in range(probes)])
        revisits = [jitter(bases[int(rng.integers(len(bases) - 1))], rng) for _ in range(probes)]
        loop = _median_ms(model, revisits)
        rows.append({"features": features, "places": model.n_places, "track_ms": track,
                     "loop_ms": loop})
    return rows


def record_tours(scenes: list[int], rooms: list[int], cache: Path, steps_per_room: int = 250
                 ) -> dict[tuple[int, int], tuple[np.ndarray, np.ndarray]]:
    """``(frames, room)`` of one scripted tour per world, recorded once and kept in ``cache``."""
    cache.mkdir(parents=True, exist_ok=True)
    tours = {}
    for s in scenes:
        for n in rooms:
            path = cache / f"tour_s{s}_r{n}.npz"
            if not path.is_file():
                from envs.demo import record_tour  # the simulator only when a tour is missing

                tour, _ = record_tour(s, n, steps_per_room * n, seed=s, progress=True)
                tour.save(str(path))
            with np.load(path) as z:
                tours[(s, n)] = (z["frames"], z["room"])
    return tours


def tour_scores(tours: dict, algos: list[tuple[str, str]]) -> list[dict]:
    """Scores of each (algorithm, features) on each tour."""
    from placeclust.runner import evaluate, run

    rows = []
    for (s, n), (frames, room) in tours.items():
        for algo, features in algos:
            metrics = evaluate(run(algo, frames, features), room)
            rows.append({"algo": algo, "features": features, "scene": s, "rooms": n, **metrics})
            print(f"scene {s} rooms {n} {algo}/{features}: precision "
                  f"{metrics['precision']:.3f} nmi {metrics['nmi']:.3f} places "
                  f"{metrics['n_places']}/{n} {metrics['ms_per_frame']:.1f} ms", flush=True)
    return rows


def summary_table(rows: list[dict]) -> str:
    """Mean ± std over worlds per method, as in the seed paper 000's Fig. 2."""
    keys = ("precision", "recall", "nmi", "ari")
    lines = ["| method | " + " | ".join(keys) + " | places/rooms | ms/frame |",
             "|---" * (len(keys) + 3) + "|"]
    methods = list(dict.fromkeys((r["algo"], r["features"]) for r in rows))
    for algo, feat in methods:
        sel = [r for r in rows if r["algo"] == algo and r["features"] == feat]
        cells = [f"{np.mean([r[k] for r in sel]):.3f} ± {np.std([r[k] for r in sel]):.3f}"
                 for k in keys]
        ratio = np.mean([r["n_places"] / r["n_rooms"] for r in sel])
        ms = np.median([r["ms_per_frame"] for r in sel])
        lines.append(f"| {algo} ({feat}) | " + " | ".join(cells) + f" | {ratio:.2f} | {ms:.1f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m placeclust.benchmark", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    lat = sub.add_parser("latency", help="latency as the map grows (no simulator)")
    lat.add_argument("--features", nargs="+", default=["sift", "orb"])
    lat.add_argument("--sizes", nargs="+", type=int, default=[10, 50, 100, 250, 500])
    tr = sub.add_parser("tours", help="quality on simulated tours")
    tr.add_argument("--features", nargs="+", default=["sift", "orb"])
    tr.add_argument("--scenes", nargs="+", type=int, default=[0, 1, 2])
    tr.add_argument("--rooms", nargs="+", type=int, default=[4, 8])
    tr.add_argument("--baselines", action="store_true",
                    help="also score nested, kunion, wpgma and kmeans (SIFT)")
    tr.add_argument("--cache", type=Path, default=Path("runs/bench_tours"))
    args = p.parse_args(argv)
    if args.what == "latency":
        if min(args.sizes) < 2:
            p.error("--sizes must be at least 2 places")
        print("| features | places | tracking ms (median) | loop closure ms (median) |")
        print("|---|---|---|---|")
        for feat in args.features:
            for r in latency_vs_map_size(feat, args.sizes):
                print(f"| {feat} | {r['places']} | {r['track_ms']:.1f} | {r['loop_ms']:.1f} |",
                      flush=True)
        return 0
    algos = [("online", f) for f in args.features]
    if args.baselines:
        algos += [(a, "sift") for a in ("nested", "kunion", "wpgma", "kmeans")]
    rows = tour_scores(record_tours(args.scenes, args.rooms, args.cache), algos)
    print(summary_table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
