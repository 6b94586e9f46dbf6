"""Latency of the online recognizer as its map grows.

    python -m placeclust.benchmark latency [--features sift orb] [--sizes 10 100 500]

It needs no simulator: it grows a map of synthetic places and times the online recognizer at
each size on frames it tracks (the current place) and on frames of a random earlier place (a
loop closure through the relocalization index), and times the feature detection alone on the
tracked frames: the rest of a frame is the recognizer's own work. Quality on simulated tours is
``placeclust bench`` (:mod:`placeclust.bench`), which also runs this sweep for its plot.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from placeclust.features import FeatureExtractor
from placeclust.frames import to_gray
from placeclust.online import OnlinePlaceClustering
from placeclust.synthetic import jitter, textured


def _median_ms(model: OnlinePlaceClustering, frames: list[np.ndarray], from_here: bool = False
               ) -> float:
    """Median ms of ``learn_predict_one`` over ``frames``; ``from_here``: each frame starts
    from the graph and place the model has now (the edge a loop closure adds is taken back)."""
    times = []
    for f in frames:
        graph, current = (model.graph.copy(), model.current) if from_here else (None, None)
        start = time.perf_counter()
        model.learn_predict_one(f)
        times.append(time.perf_counter() - start)
        if from_here:
            model.graph, model.current = graph, current
    return 1000.0 * float(np.median(times))


def _features_ms(model: OnlinePlaceClustering, frames: list[np.ndarray]) -> float:
    """Median ms of the feature detection alone (the model's settings) over ``frames``."""
    extractor = FeatureExtractor(model.features, model.max_features, model.normalize,
                                 model.scale, model.view)
    times = []
    for f in frames:
        gray = to_gray(f)
        start = time.perf_counter()
        extractor.extract_pair(gray)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.median(times))


def latency_vs_map_size(features: str, sizes: list[int], probes: int = 30, seed: int = 0
                        ) -> list[dict[str, float]]:
    """Median ms per frame at each map size, for tracking and for loop closures, and of the
    feature detection alone on the tracking frames (``features_ms``, the part that does not
    depend on the map).

    The map grows with one synthetic place per new image (512×128); after it reaches each size,
    ``probes`` frames of the current place and ``probes`` revisits of random earlier places are
    timed (they may update kernels, as in real use, but open no place). Every revisit starts
    from the newest place and its graph as they were: otherwise the loop-closure edges of the
    probes themselves would give the current place of a 10-place map 7 neighbours to check and
    that of a 500-place map 3, and the sizes would not be compared on the same search.
    """
    rng = np.random.default_rng(seed)
    model = OnlinePlaceClustering(features)
    bases: list[np.ndarray] = []
    rows = []
    for size in sorted(sizes):
        while len(bases) < size:
            bases.append(textured(10_000 + len(bases)))
            model.learn_one(bases[-1])
        tracked = [jitter(bases[-1], rng) for _ in range(probes)]
        track = _median_ms(model, tracked)
        detect = _features_ms(model, tracked)
        revisits = [jitter(bases[int(rng.integers(len(bases) - 1))], rng) for _ in range(probes)]
        loop = _median_ms(model, revisits, from_here=True)
        rows.append({"features": features, "places": model.n_places, "track_ms": track,
                     "loop_ms": loop, "features_ms": detect})
    return rows


def best_of_sweeps(features: str, sizes: list[int], repeats: int = 3
                   ) -> list[dict[str, float]]:
    """:func:`latency_vs_map_size` run ``repeats`` times, each on a fresh map (the same frames).

    Returns one row per size: ``track_ms``, ``loop_ms`` and ``features_ms`` are the lowest of
    the sweeps' medians and ``track_ms_max``, ``loop_ms_max``, ``features_ms_max`` the highest.
    A shared machine slows down for seconds at a time, so one sweep can find one size slow; the
    sweeps lie half a minute apart, and the lowest figure is the machine's own speed (as
    ``timeit`` takes the best of its runs).
    """
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, got {repeats}")
    sweeps = [latency_vs_map_size(features, sizes) for _ in range(repeats)]
    rows = []
    for points in zip(*sweeps):
        row = dict(points[0])
        for key in ("track_ms", "loop_ms", "features_ms"):
            values = [p[key] for p in points]
            row[key], row[f"{key}_max"] = min(values), max(values)
        rows.append(row)
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m placeclust.benchmark", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    lat = sub.add_parser("latency", help="latency as the map grows (no simulator)")
    lat.add_argument("--features", nargs="+", default=["sift", "orb"])
    lat.add_argument("--sizes", nargs="+", type=int, default=[10, 50, 100, 250, 500])
    lat.add_argument("--repeats", type=int, default=3,
                     help="sweeps, each on a fresh map; the lowest median per size is reported")
    args = p.parse_args(argv)
    if min(args.sizes) < 2:
        p.error("--sizes must be at least 2 places")
    if args.repeats < 1:
        p.error("--repeats must be at least 1")
    print(f"median ms per frame over 30 frames, lowest (highest) of {args.repeats} sweeps\n")
    print("| features | places | tracking ms | loop closure ms | of which detection ms |")
    print("|---|---|---|---|---|")
    for feat in args.features:
        rows = best_of_sweeps(feat, args.sizes, args.repeats)
        for r in rows:
            print(f"| {feat} | {r['places']} | {r['track_ms']:.1f} ({r['track_ms_max']:.1f}) | "
                  f"{r['loop_ms']:.1f} ({r['loop_ms_max']:.1f}) | "
                  f"{r['features_ms']:.1f} ({r['features_ms_max']:.1f}) |", flush=True)
        first, last = rows[0], rows[-1]
        print(f"| {feat} | {last['places']} / {first['places']} | "
              f"{last['track_ms'] / first['track_ms']:.2f}x | "
              f"{last['loop_ms'] / first['loop_ms']:.2f}x | |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
