"""``placeclust score``: one suite score over closed-loop tracks, with its interval, and
recognizers paired on it.

    placeclust score runs/v2/continued/results.json runs/v2/carried/results.json ... \\
        [--floor none] [--ceiling oracle] [--aggregate mean|iqm] [--pair panorama panorama-orb] \\
        [--docs docs/benchmarks.md [--section NAME]]

Each file is one track's results (``placeclust leaderboard --track NAME --out DIR`` writes
``DIR/results.json``; :class:`~envs.runs.suite.Track`). Per track, every recognizer's errand
success is normalized between the ``--floor`` recognizer's (0: no place ids) and the ``--ceiling``'s
(1: the true rooms) on that track, and the suite score is the mean (or interquartile mean) of
the normalized tracks, with a 95% interval from a bootstrap stratified by track that resamples
each track's buildings (rliable's aggregate, :func:`placeclust.stats.suite_score`). A
``--pair A B`` adds the paired difference of the two scores on the buildings each track shares,
and rliable's probability of improvement averaged over tracks. A recognizer a track skipped
(``--localize-only`` without ``localize_one``) has no suite score, only its tracks'.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from placeclust.stats import (
    AGGREGATES,
    interval,
    paired_difference,
    probability_of_improvement,
    suite_score,
)

from ..runs.decomposition import decomposition_table
from ..runs.results import calibration, groups, load_results, paired_rows, slug


def track_of(doc: dict[str, Any], path: Path) -> str:
    """The track a results file ran: its settings' ``track``, else the file's folder name."""
    return doc["settings"].get("track") or path.parent.name


def load_tracks(paths: list[Path]) -> dict[str, dict[str, Any]]:
    """Results files by track; a ``ValueError`` where two files claim one track."""
    docs: dict[str, dict[str, Any]] = {}
    for path in paths:
        doc = load_results(path)
        track = track_of(doc, path)
        if track in docs:
            raise ValueError(f"two files of track {track!r}: give each track once ({path})")
        docs[track] = doc
    return docs


def recognizer_rows(doc: dict[str, Any], name: str) -> list[dict[str, Any]]:
    """``name``'s rows in a results file, by scene seed."""
    return sorted((r for r in doc["buildings"] if r["recognizer"] == name),
                  key=lambda r: r["scene_seed"])


def bounds(docs: dict[str, dict[str, Any]], floor: str, ceiling: str
           ) -> tuple[dict[str, float], dict[str, float]]:
    """Each track's floor and ceiling: the two recognizers' mean success on it."""
    lows: dict[str, float] = {}
    highs: dict[str, float] = {}
    for track, doc in docs.items():
        for name, out in ((floor, lows), (ceiling, highs)):
            rows = recognizer_rows(doc, name)
            if not rows:
                raise ValueError(f"track {track!r} has no {name!r} rows to normalize by; run "
                                 f"it with --recognizers {floor} {ceiling} ...")
            out[track] = interval(groups(rows, "success_rate")).mean
    return lows, highs


def score_table(docs: dict[str, dict[str, Any]], floor: str, ceiling: str, aggregate: str
                ) -> tuple[str, dict[str, Any]]:
    """The markdown table: each recognizer's success per track with its interval, and its
    normalized suite score; and the scores by recognizer (``None`` where a track skipped it)."""
    lows, highs = bounds(docs, floor, ceiling)
    tracks = list(docs)
    names = list(dict.fromkeys(s["recognizer"] for d in docs.values() for s in d["summaries"]))
    lines = ["| recognizer | " + " | ".join(tracks) + f" | suite score ({aggregate}) |",
             "|---|" + "---|" * (len(tracks) + 1)]
    scores: dict[str, Any] = {}
    for name in names:
        per = {t: recognizer_rows(docs[t], name) for t in tracks}
        cells = [interval(groups(rows, "success_rate")).text(2) if rows else "skipped"
                 for rows in per.values()]
        if all(per.values()):
            est = suite_score({t: groups(rows, "success_rate") for t, rows in per.items()},
                              lows, highs, aggregate=aggregate)
            scores[name] = est.as_dict()
            cells.append(est.text(2))
        else:
            scores[name] = None
            cells.append("–")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines), scores


def pair_table(docs: dict[str, dict[str, Any]], a: str, b: str, floor: str, ceiling: str,
               aggregate: str) -> tuple[str, dict[str, Any]]:
    """``a`` against ``b``, paired on each track's shared buildings: per track the success
    difference and P(A > B), then the suite scores' difference and the mean P(A > B)."""
    lows, highs = bounds(docs, floor, ceiling)
    lines = ["| track | A − B success [95% interval] | P(A > B) | buildings |",
             "|---|---|---|---|"]
    ga: dict[str, Any] = {}
    gb: dict[str, Any] = {}
    better = []
    for track, doc in docs.items():
        rows_a, rows_b = paired_rows(doc, doc, a, b)
        ga[track], gb[track] = groups(rows_a, "success_rate"), groups(rows_b, "success_rate")
        norm = highs[track] - lows[track]
        diff = paired_difference(ga[track], gb[track])  # as placeclust compare gives it
        p = probability_of_improvement(ga[track], gb[track])
        better.append(p.mean)
        lines.append(f"| {track} | {diff.text(3)} (normalized {diff.mean / norm:+.3f}) | "
                     f"{p.text(2)} | {len(rows_a)} |")
    total = suite_score(ga, lows, highs, against=gb, aggregate=aggregate)
    lines.append(f"| **suite score** | **{total.text(3)}** (normalized) | "
                 f"{np.mean(better):.2f} (mean over tracks) | |")
    decided = total.excludes(0.0)
    verdict = (f"{a} − {b} on the suite score: {total.text(3)}; "
               + ("the interval excludes 0." if decided else
                  "the interval holds 0: this sample cannot rank them."))
    return "\n".join(lines) + "\n\n" + verdict, {"a": a, "b": b, **total.as_dict(),
                                                 "p_improvement": float(np.mean(better))}


def main(argv: list[str] | None = None, prog: str = "placeclust score") -> int:
    """``placeclust score ...``; the exit status."""
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("results", type=Path, nargs="+", help="one results file per track")
    p.add_argument("--floor", default="none", help="the recognizer scored 0 on every track "
                   "(default none)")
    p.add_argument("--ceiling", default="oracle", help="the recognizer scored 1 (default "
                   "oracle)")
    p.add_argument("--aggregate", choices=AGGREGATES, default="mean",
                   help="how the tracks' normalized scores combine (iqm: rliable's "
                   "interquartile mean)")
    p.add_argument("--pair", action="append", nargs=2, default=[], metavar=("A", "B"),
                   help="compare two recognizers paired on the suite score (repeatable)")
    p.add_argument("--docs", metavar="FILE", help="also write the tables into FILE's section "
                   "score-<tracks> (docs/benchmarks.md)")
    p.add_argument("--section", help="the section's name instead of score-<tracks>")
    p.add_argument("--decompose", action="store_true", help="also where each recognizer "
                   "lost its errands to pictures (placenav-v5's records): goals unknown, named "
                   "in the right room, within 1 m, a spot within 1 m, success there (the "
                   "driving), first-step stops (envs.runs.decomposition)")
    p.add_argument("--calibration", type=Path, metavar="PNG", help="also each calibration "
                   "recognizer's difference from the ceiling and each track's resolution, and "
                   "their curves of success against the injected error drawn into PNG")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    try:
        docs = load_tracks(args.results)
        text, _ = score_table(docs, args.floor, args.ceiling, args.aggregate)
        compared = [pair_table(docs, a, b, args.floor, args.ceiling, args.aggregate)[0]
                    for a, b in args.pair]
        if args.calibration:
            compared.append(_calibrate(docs, args.ceiling, args.calibration))
        if args.decompose:
            compared.append(decomposition_table(docs))
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    n = sorted({len(d["settings"]["scene_seeds"]) for d in docs.values()})
    body = (f"{len(docs)} tracks ({', '.join(docs)}), {'/'.join(map(str, n))} "
            f"building{'s' if n != [1] else ''} a track. Each track's errand success with its "
            f"95% interval over buildings; the suite score is each track's success normalized "
            f"between `{args.floor}` (0) and `{args.ceiling}` (1), combined by the "
            f"{args.aggregate} over tracks, with a bootstrap stratified by track.\n\n" + text
            + "".join(f"\n\n{c}" for c in compared))
    print(body)
    if args.docs:
        write_section(args.docs, args.section or "score-" + "-".join(slug(t) for t in docs),
                      body, shlex.join([*prog.split(), *argv]))
    return 0



def _calibrate(docs: dict[str, dict[str, Any]], ceiling: str, path: Path) -> str:
    """:func:`calibration`'s markdown, its curves drawn into ``path``."""
    from .figures import calibration_curves  # matplotlib only when a figure is asked for

    text, points = calibration(docs, ceiling)
    if not points:
        raise ValueError(f"no calibration recognizer (oracle-KIND:VALUE) in {list(docs)}")
    # the true rooms are the family's no-error point; a ceiling that knows more (oracle-pose)
    # is drawn as a line of its own
    calibration_curves(points, {t: interval(groups(recognizer_rows(d, ceiling), "success_rate"))
                                for t, d in docs.items()}, path, anchored=ceiling == "oracle")
    return text + f" Curves: `{path}`."


if __name__ == "__main__":
    sys.exit(main())
