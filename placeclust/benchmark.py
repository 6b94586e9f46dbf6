"""Latency of the online recognizer as its map grows.

    python -m placeclust.benchmark latency [--features sift orb] [--sizes 10 100 500]

It needs no simulator: it grows a map of synthetic places and times the online recognizer at
each size on frames it tracks (the current place) and on frames of a random earlier place (a
loop closure through the relocalization index). Quality on simulated tours is
``placeclust bench`` (:mod:`placeclust.bench`), which also runs this sweep for its plot.
"""

from __future__ import annotations

import argparse
import sys
import time

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


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m placeclust.benchmark", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    lat = sub.add_parser("latency", help="latency as the map grows (no simulator)")
    lat.add_argument("--features", nargs="+", default=["sift", "orb"])
    lat.add_argument("--sizes", nargs="+", type=int, default=[10, 50, 100, 250, 500])
    args = p.parse_args(argv)
    if min(args.sizes) < 2:
        p.error("--sizes must be at least 2 places")
    print("| features | places | tracking ms (median) | loop closure ms (median) |")
    print("|---|---|---|---|")
    for feat in args.features:
        for r in latency_vs_map_size(feat, args.sizes):
            print(f"| {feat} | {r['places']} | {r['track_ms']:.1f} | {r['loop_ms']:.1f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
