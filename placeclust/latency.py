"""Latency of the online recognizer as its map grows.

    python -m placeclust.latency [--features sift orb] [--sizes 10 100 500]
    placeclust latency [...]    # the same, from the simulator's command line

It needs no simulator: it grows a map of synthetic places and times the online recognizer at
each size on frames it tracks (the current place) and on frames of a random earlier place (a
loop closure through the relocalization index), and apart from the whole frame, the
recognizer's own work: the frame less its feature detection, which does not depend on the map.
Quality on simulated tours is ``placeclust bench`` (``envs/commands/bench.py``), which also
runs this sweep for its plot.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from typing import Any

import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.online import OnlinePlaceClustering
from placeclust.runner import check_params, literal_params
from placeclust.synthetic import jitter, textured


def _median_ms(model: OnlinePlaceClustering, frames: list[np.ndarray], from_here: bool = False
               ) -> tuple[float, float, float]:
    """Medians over ``frames`` of ``learn_predict_one``, of the feature detection inside it, and
    of the rest, the recognizer's own work (each frame's whole minus its own detection), in ms.

    ``from_here``: each frame starts from the graph and place the model has now (the edge a
    loop closure adds is taken back). A frame that opened or merged a place is kept whole:
    taking back only its graph would leave a kernel without a node.
    """
    extractor = model._extractor
    detection: list[float] = []

    def timed_detection(gray: np.ndarray, own=extractor.extract_pair):
        start = time.perf_counter()
        found = own(gray)
        detection.append(time.perf_counter() - start)
        return found

    times = []
    vars(extractor)["extract_pair"] = timed_detection  # an instance attribute, removed below
    try:
        for f in frames:
            saved = (model.graph.copy(), model.current) if from_here else None
            places = (len(model.kernels), len(model.merged))
            start = time.perf_counter()
            model.learn_predict_one(f)
            times.append(time.perf_counter() - start)
            if saved is not None and places == (len(model.kernels), len(model.merged)):
                model.graph, model.current = saved
    finally:
        del extractor.extract_pair
    whole, detect = 1000.0 * np.array(times), 1000.0 * np.array(detection)
    return float(np.median(whole)), float(np.median(detect)), float(np.median(whole - detect))


#: The timings of a :func:`latency_vs_map_size` row, all medians in ms per frame.
TIMINGS = ("track_ms", "loop_ms", "features_ms", "track_own_ms", "loop_own_ms")


def latency_vs_map_size(features: str, sizes: list[int], probes: int = 30, seed: int = 0,
                        params: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """Median ms per frame at each map size, for tracking and for loop closures.

    Each row holds :data:`TIMINGS`: ``track_ms`` and ``loop_ms`` are whole frames,
    ``features_ms`` the feature detection inside the tracked ones (it does not depend on the
    map), and ``track_own_ms``, ``loop_own_ms`` the recognizer's own work, each frame less its
    detection: the part that could grow with the map, and steadier than the whole on a machine
    whose speed drifts, because the detector's swings are taken out frame by frame.

    The map grows with one synthetic place per new image (512×128); after it reaches each size,
    ``probes`` frames of the current place and ``probes`` revisits of random earlier places are
    timed (they may update kernels, as in real use, but open no place). Every revisit starts
    from the newest place and its graph as they were: otherwise the loop-closure edges of the
    probes themselves would give the current place more neighbours to check on a small map than
    on a large one, and the sizes would not be compared on the same search.

    Args:
        features: local feature type.
        sizes: map sizes, in places, at which to time.
        probes: frames timed per size, for tracking and for loop closures each.
        seed: draws the probes' jitter and the revisited places.
        params: other constructor arguments of the recognizer (default: the paper's). Each
            synthetic place is one image, so with ``consolidate`` every tracked frame is on
            probation and pays the consolidation's check: its worst case.

    Returns:
        One row per size: ``features``, ``places`` and :data:`TIMINGS`.

    Examples:
        >>> from placeclust.latency import TIMINGS, latency_vs_map_size
        >>> rows = latency_vs_map_size("orb", [2, 3], probes=2)
        >>> [row["places"] for row in rows], all(key in rows[0] for key in TIMINGS)
        ([2, 3], True)
    """
    rng = np.random.default_rng(seed)
    model = OnlinePlaceClustering(features, **(params or {}))
    bases: list[np.ndarray] = []
    rows: list[dict[str, Any]] = []
    for size in sorted(sizes):
        while len(bases) < size:
            bases.append(textured(10_000 + len(bases)))
            model.learn_one(bases[-1])
        track, detect, track_own = _median_ms(
            model, [jitter(bases[-1], rng) for _ in range(probes)])
        revisits = [jitter(bases[int(rng.integers(len(bases) - 1))], rng) for _ in range(probes)]
        loop, _, loop_own = _median_ms(model, revisits, from_here=True)
        rows.append({"features": features, "places": model.n_places, "track_ms": track,
                     "loop_ms": loop, "features_ms": detect, "track_own_ms": track_own,
                     "loop_own_ms": loop_own})
    return rows


def best_of_sweeps(features: str, sizes: list[int], repeats: int = 3,
                   params: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """:func:`latency_vs_map_size` run ``repeats`` times, each on a fresh map (the same frames).

    Returns one row per size: each of :data:`TIMINGS` is the lowest of the sweeps' medians, and
    ``<timing>_max`` the highest. A shared machine slows down for seconds at a time, so one
    sweep can find one size slow; the sweeps lie half a minute apart, and the lowest figure is
    the machine's own speed (as ``timeit`` takes the best of its runs).

    Raises:
        ValueError: ``repeats`` is below 1.
    """
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, got {repeats}")
    sweeps = [latency_vs_map_size(features, sizes, params=params) for _ in range(repeats)]
    rows = []
    for points in zip(*sweeps):
        row = dict(points[0])
        for key in TIMINGS:
            values = [p[key] for p in points]
            row[key], row[f"{key}_max"] = min(values), max(values)
        rows.append(row)
    return rows


def _table(features: str, rows: list[dict[str, Any]]) -> list[str]:
    """Markdown rows for one feature type, and the last size over the first."""
    def cell(row: dict[str, Any], key: str) -> str:
        return f"{row[key]:.1f} ({row[key + '_max']:.1f})"

    lines = [f"| {features} | {r['places']} | {cell(r, 'track_ms')} | {cell(r, 'loop_ms')} | "
             f"{cell(r, 'features_ms')} | {r['track_own_ms']:.1f} / {r['loop_own_ms']:.1f} |"
             for r in rows]
    first, last = rows[0], rows[-1]
    ratio = {key: last[key] / first[key] for key in TIMINGS}
    lines.append(f"| {features} | {last['places']} / {first['places']} | "
                 f"{ratio['track_ms']:.2f}x | {ratio['loop_ms']:.2f}x | | "
                 f"{ratio['track_own_ms']:.2f}x / {ratio['loop_own_ms']:.2f}x |")
    return lines


def main(argv: list[str] | None = None, prog: str = "python -m placeclust.latency") -> int:
    """The latency sweep's command line (``placeclust latency``); the exit status."""
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--features", nargs="+", default=["sift", "orb"])
    p.add_argument("--sizes", nargs="+", type=int, default=[10, 50, 100, 250, 500])
    p.add_argument("--repeats", type=int, default=3,
                   help="sweeps, each on a fresh map; the lowest median per size is reported")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="a constructor argument of the recognizer (repeatable); the default "
                   "is the paper's recognizer")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's "
                   "'latency' section (docs/benchmarks.md), or --section's")
    p.add_argument("--section", default="latency", help="the section --docs writes")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    if min(args.sizes) < 2:
        p.error("--sizes must be at least 2 places")
    if args.repeats < 1:
        p.error("--repeats must be at least 1")
    try:
        params = literal_params(args.param)
        check_params("online", params)
    except ValueError as e:
        p.error(str(e))
    lines = [f"Median ms per frame over 30 frames, lowest (highest) of {args.repeats} sweeps; "
             "own: the recognizer's part of a frame, its detection taken out.", "",
             "| features | places | tracking ms | loop closure ms | detection ms | "
             "own ms: tracking / loop closure |", "|---|---|---|---|---|---|"]
    if params:
        lines.insert(1, "Recognizer: the paper's, with " + ", ".join(
            f"`{k}={v!r}`" for k, v in params.items()) + ".")
    print("\n".join(lines), flush=True)
    for feat in args.features:
        for line in _table(feat, best_of_sweeps(feat, args.sizes, args.repeats, params)):
            lines.append(line)
            print(line, flush=True)
    if args.docs:
        from placeclust.docs_section import write_section

        write_section(args.docs, args.section, "\n".join(lines),
                      shlex.join([*prog.split(), *argv]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
