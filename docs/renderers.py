"""The renderer's part of the figures: the same measurements drawn by two renderers, paired.

    python -m docs.renderers runs/renderers [--store docs/runs/placenav-v4] \\
        [--docs docs/rendering.md]

Rendering is Mesa's llvmpipe, whose pixels depend on the CPU
(``envs.runs.suite.render_fingerprint``). ``make renderers`` measures on one machine with
llvmpipe as this CPU draws (``native``) and limited to SSE4.1 at 128 bits
(``GALLIUM_OVERRIDE_CPU_CAPS=sse4.1``, as on a CPU without AVX: ``sse41``), into
``FOLDER/native`` and ``FOLDER/sse41``: ``demo/metrics.json`` (``placeclust demo``),
``bench/results.csv`` (the README's open-loop ``test`` tours) and, for ``sse41``,
``placenav-v4/<track>/results.json`` (its best real recognizer, ``panorama-orb``). The native
closed-loop rows are the shipped store's (``--store``), which the pinned environment reproduces
row for row (``python -m envs.commands.reproduce``); ``none`` and ``oracle-pose`` read no
pixels, so they bound both.

The section ``renderers`` (``docs/rendering.md``, a dated record) gives each figure on both
renderers, the native one with its 95% interval over buildings, and their paired difference;
a figure *holds* where the second renderer's value lies within the native interval, and the
section names those that do not. Repository tooling, not in the wheel.
"""

from __future__ import annotations

import argparse
import csv
import json
import shlex
import sys
from collections import defaultdict
from pathlib import Path
from typing import Any

from envs.commands.bench_report import params_text
from envs.commands.score import load_tracks, pair_table, score_table
from placeclust import PRESETS
from placeclust.docs_section import write_section
from placeclust.stats import interval, paired_difference

#: the demo's rows, as the README's table names them
DEMO_ROWS = {"online (seed 000)": "online (seed 000)",
             "online, PANORAMA settings": "`PANORAMA`",
             "nested (seed 001)": "nested (seed 001)",
             "nested (seed 001), forward camera": "nested, forward",
             "online (seed 000), forward camera": "online, forward"}
#: the open-loop figures compared: the bench's bar (precision, NMI, places per room)
OPEN_LOOP = ("precision", "nmi", "places_per_room")
#: the suite score's floor and ceiling: they read no pixels, so their native rows bound both
#: renderers; the tracks are combined by their mean
BOUNDS = ("none", "oracle-pose", "mean")
#: the label's end of a recognizer's rows drawn by the second renderer
SECOND = " (sse4.1)"


def demo_table(native: Path, sse41: Path) -> str:
    """The demo's figures (precision / NMI / places) drawn by both renderers."""
    a = json.loads((native / "demo" / "metrics.json").read_text())
    b = json.loads((sse41 / "demo" / "metrics.json").read_text())
    lines = ["| demo row | native | sse4.1 | the same |", "|---|---|---|---|"]
    for row, label in DEMO_ROWS.items():
        cells = [f"{m[row]['precision']:.3f} / {m[row]['nmi']:.3f} / {m[row]['n_places']}"
                 for m in (a, b)]
        lines.append(f"| {label} | {cells[0]} | {cells[1]} | "
                     f"{'yes' if cells[0] == cells[1] else 'no'} |")
    return "\n".join(lines)


def _config(row: dict[str, str]) -> str:
    """A bench row's configuration as the README names it: its features and preset."""
    preset = next((name for name, params in PRESETS.items()
                   if params_text(params.items()) == row["params"]), row["params"])
    return ", ".join(filter(None, (row["algo"], row["features"], preset)))


def bench_rows(path: Path) -> dict[tuple[str, ...], dict[str, float]]:
    """A bench's ``results.csv``: (configuration, scene seed, rooms, tour seed) -> the
    figures. The scene seed is the unit resampled, as the bench's own tables do."""
    rows: dict[tuple[str, ...], dict[str, float]] = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            key = (_config(r), r["scene_seed"], r["world_rooms"], r["tour_seed"])
            rows[key] = {"precision": float(r["precision"]), "nmi": float(r["nmi"]),
                         "places_per_room": float(r["n_places"]) / float(r["n_rooms"])}
    return rows


def open_loop_table(native: Path, sse41: Path) -> tuple[str, list[str]]:
    """Each configuration's open-loop figures: the native mean with its 95% interval over
    buildings, the second renderer's, their paired difference (tour by tour, buildings
    resampled); and the figures whose second value falls outside the native interval."""
    a, b = bench_rows(native / "bench" / "results.csv"), bench_rows(sse41 / "bench" / "results.csv")
    shared = sorted(set(a) & set(b))
    if not shared:
        raise ValueError("the two benches share no tour")
    lines = ["| configuration | figure | native [95% interval] | sse4.1 | sse4.1 − native, "
             "paired | within the native interval |", "|---|---|---|---|---|---|"]
    moved = []
    for config in sorted({k[0] for k in shared}):
        keys = [k for k in shared if k[0] == config]
        for figure in OPEN_LOOP:
            by_building: dict[str, tuple[list[float], list[float]]] = defaultdict(
                lambda: ([], []))
            for k in keys:
                by_building[k[1]][0].append(a[k][figure])
                by_building[k[1]][1].append(b[k][figure])
            ga, gb = [v[0] for v in by_building.values()], [v[1] for v in by_building.values()]
            first, second = interval(ga), interval(gb)
            holds = not first.excludes(second.mean)
            lines.append(f"| {config} | {figure} | {first.text(3)} | {second.mean:.3f} | "
                         f"{paired_difference(gb, ga).text(3)} | {'yes' if holds else 'no'} |")
            if not holds:
                moved.append(f"{config} {figure} ({first.mean:.3f} against {second.mean:.3f})")
    tours = len(shared) // len({k[0] for k in shared})
    return ("\n".join(lines) + f"\n\n{tours} tours a configuration on "
            f"{len({k[1] for k in shared})} buildings (scene seeds)."), moved


def merged_tracks(store: Path, sse41: Path) -> dict[str, dict[str, Any]]:
    """Per track, the store's results with the second renderer's rows beside them, each of its
    recognizers named with ``SECOND`` at the end: one file a track, so :func:`pair_table`
    pairs them."""
    native = load_tracks(sorted(store.glob("*/results.json")))
    second = load_tracks(sorted((sse41 / store.name).glob("*/results.json")))
    merged = {}
    for track, doc in native.items():
        if track not in second:
            raise ValueError(f"the second renderer has no track {track!r} of {store}")
        other = second[track]
        # the native rows of the bounds and of what the second renderer drew, no others
        keep = {BOUNDS[0], BOUNDS[1], *(r["recognizer"] for r in other["buildings"])}
        renamed = [{**r, "recognizer": r["recognizer"] + SECOND} for r in other["buildings"]]
        summaries = [{**s, "recognizer": s["recognizer"] + SECOND} for s in other["summaries"]]
        merged[track] = {
            **doc, "buildings": [r for r in doc["buildings"] if r["recognizer"] in keep] + renamed,
            "summaries": [s for s in doc["summaries"] if s["recognizer"] in keep] + summaries}
    return merged


def closed_loop(store: Path, sse41: Path) -> tuple[str, list[str]]:
    """Every track's success and the suite score (``none`` 0, ``oracle-pose`` 1) of both
    renderers' rows; each recognizer drawn by both, paired; the ranking of the two that read
    pixels by each renderer."""
    docs = merged_tracks(store, sse41)
    drawn = sorted({r["recognizer"] for d in docs.values() for r in d["buildings"]
                    if r["recognizer"].endswith(SECOND)})
    table, scores = score_table(docs, *BOUNDS)
    parts, moved = [table], []
    for name in drawn:
        plain = name.removesuffix(SECOND)
        parts.append(pair_table(docs, name, plain, *BOUNDS)[0])
        first, second = scores[plain], scores[name]
        if not first["low"] <= second["mean"] <= first["high"]:
            moved.append(f"{plain}'s suite score ({first['mean']:.2f} against "
                         f"{second['mean']:.2f})")
    if len(drawn) == 2:  # the ranking of the two by each renderer
        plain = [n.removesuffix(SECOND) for n in drawn]
        parts.append(pair_table(docs, plain[0], plain[1], *BOUNDS)[0])
        parts.append(pair_table(docs, drawn[0], drawn[1], *BOUNDS)[0])
    return "\n\n".join(parts), moved


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m docs.renderers", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder", type=Path, help="make renderers' folder (native/, sse41/)")
    p.add_argument("--store", type=Path, default=Path("docs/runs/placenav-v4"))
    p.add_argument("--docs", metavar="FILE", help="also write the section renderers there "
                   "(docs/rendering.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    native, sse41 = args.folder / "native", args.folder / "sse41"
    try:
        demo = demo_table(native, sse41)
        bench, moved_open = open_loop_table(native, sse41)
        loop, moved_closed = closed_loop(args.store, sse41)
    except (OSError, ValueError, KeyError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    moved = moved_open + moved_closed
    verdict = ("Every figure above holds across the two renderers: the second renderer's "
               "value lies within the native figure's 95% interval." if not moved else
               "Figures the second renderer moves outside the native figure's 95% interval: "
               + "; ".join(moved) + ". Every other figure holds within its interval (a paired "
               "difference may still exclude 0: the renderer's part, smaller than the "
               "buildings' spread).")
    body = ("llvmpipe as this CPU draws it (`native`, AVX-512, 256 bits) against llvmpipe "
            "limited to SSE4.1 at 128 bits (`sse4.1`, `GALLIUM_OVERRIDE_CPU_CAPS=sse4.1`), "
            "in the pinned environment. **The demo** (scene 0, 4 rooms, 1000 frames: "
            "precision / NMI / places):\n\n" + demo
            + "\n\n**The open loop** (the README's `test` tours, paired tour by tour, "
            "buildings resampled):\n\n" + bench
            + f"\n\n**The closed loop** (`{args.store.name}`: the shipped store's rows "
            "against the pixel-reading recognizers' drawn by `sse4.1`; `none` and "
            "`oracle-pose` read no pixels and bound both):\n\n" + loop + "\n\n" + verdict)
    print(body)
    if args.docs:
        write_section(args.docs, "renderers", body,
                      shlex.join(["python", "-m", "docs.renderers", *argv]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
