"""``placeclust compare`` and ``placeclust score``: recognizers paired on the same buildings, and
one suite score over tracks, each with its interval.

    placeclust compare runs/a/results.json runs/b/results.json [--a NAME] [--b NAME] [--force] \\
        [--docs docs/benchmarks.md [--section NAME]]

Each file is a results file (:mod:`envs.commands.results`: ``placeclust leaderboard`` writes
``OUT/results.json``, ``placeclust errands --json FILE``); both may be one file with ``--a`` and
``--b`` naming two of its recognizers. For each metric the table gives both means, the paired
difference A − B with its 95% interval from a bootstrap over the shared buildings, and the
probability of improvement P(A > B) (:mod:`placeclust.stats`). A difference whose interval
holds 0 is not a difference the sample can decide, and the verdict line says so.

Results are comparable only from the same buildings, errands and tours, rendered and simulated
alike: files from different suites, settings or buildings, or with different render or physics
fingerprints (:func:`~envs.commands.suite.physics_fingerprint`), are refused (exit 2) with what
differs; ``--force`` compares them anyway on the buildings they share and prints every
difference as a ``FLAG`` line above the table (and in the docs section). Different package
versions (each one a ``note:`` line) or agents are noted, not refused: comparing two versions,
or two agents on one recognizer's maps, is what a change is judged by. Where the files differ in
agent or suite size, each side's name says which, e.g. ``panorama (long)`` against
``panorama (quick)``: the same maps after a long and a short tour, compared with ``--force``.

    placeclust score runs/v2/continued/results.json runs/v2/carried/results.json ... \\
        [--floor none] [--ceiling oracle] [--aggregate mean|iqm] [--pair panorama panorama-orb] \\
        [--docs docs/benchmarks.md [--section NAME]]

Each file is one track's results (``placeclust leaderboard --track NAME --out DIR`` writes
``DIR/results.json``; :class:`~envs.commands.suite.Track`). Per track, every recognizer's errand
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

from .results import (
    calibration,
    groups,
    load_results,
    paired_rows,
    policy_name,
    seed_span,
    slug,
)

#: settings that say who acted, not what was measured: results differing in them compare
AGENT_KEYS = ("recognizers", "agent", "policy")

#: below this many buildings a bootstrap interval covers too little to decide on
FEW = 10
#: the rows of the table, in order
METRICS = ("success_rate", "spl", "mean_length", "precision", "nmi", "places_per_room")


def _pick(doc: dict[str, Any], name: str | None, path: Path, flag: str) -> str:
    names = [s["recognizer"] for s in doc["summaries"]]
    if name is None:
        if len(names) != 1:
            raise ValueError(f"{path} holds {names}; name one with {flag}")
        return names[0]
    if name not in names:
        raise ValueError(f"{path} has no recognizer {name!r}; it holds {names}")
    return name


def differences(a: dict[str, Any], b: dict[str, Any]) -> list[str]:
    """What makes two results files incomparable: suite, settings, render, physics."""
    found = []
    pa, pb = a["provenance"], b["provenance"]
    for key in ("suite", "size", "render_fingerprint", "physics_fingerprint"):
        if pa.get(key) != pb.get(key):  # older files record no physics fingerprint
            found.append(f"{key}: {pa.get(key, 'not recorded')} against "
                         f"{pb.get(key, 'not recorded')}")
    # what runs on the buildings, recognizer and agent, is what a comparison is about
    sa = {k: v for k, v in a["settings"].items() if k not in AGENT_KEYS}
    sb = {k: v for k, v in b["settings"].items() if k not in AGENT_KEYS}
    for key in sorted(set(sa) | set(sb)):
        if sa.get(key) != sb.get(key):
            found.append(f"settings {key}: {sa.get(key)} against {sb.get(key)}")
    return found


def version_notes(a: dict[str, Any], b: dict[str, Any]) -> list[str]:
    """The package versions two results files differ in, e.g. ``placeclust 0.15.0 against
    0.16.0``: noted, not refused (the fingerprints say whether they render and move alike)."""
    va, vb = (d["provenance"].get("versions", {}) for d in (a, b))
    return [f"{k} {va.get(k, '?')} against {vb.get(k, '?')}"
            for k in sorted(set(va) | set(vb)) if va.get(k) != vb.get(k)]


def table(rows_a: list[dict[str, Any]], rows_b: list[dict[str, Any]], name_a: str,
          name_b: str) -> tuple[str, dict[str, dict[str, float]]]:
    """The markdown table of paired differences, and its figures by metric: each side's mean
    with its own 95% interval over the shared buildings, then the paired difference."""
    lines = [f"| metric | A: {name_a} | B: {name_b} | A − B [95% interval] | P(A > B) |",
             "|---|---|---|---|---|"]
    figures = {}
    for metric in METRICS:
        ga, gb = groups(rows_a, metric), groups(rows_b, metric)
        diff = paired_difference(ga, gb)
        better = probability_of_improvement(ga, gb)
        mean_a, mean_b = diff.mean + _mean(gb), _mean(gb)
        digits = 0 if metric == "mean_length" else 3
        lines.append(f"| {metric} | {interval(ga).text(digits)} | {interval(gb).text(digits)} | "
                     f"{diff.text(digits)} | {better.text(2)} |")
        figures[metric] = {"a": mean_a, "b": mean_b, "difference": diff.mean,
                           "low": diff.low, "high": diff.high, "p_improvement": better.mean}
    return "\n".join(lines), figures


def _mean(group: list[list[float]]) -> float:
    values = [v for g in group for v in g]
    return sum(values) / len(values)


def verdict(figures: dict[str, dict[str, float]], name_a: str, name_b: str, n: int) -> str:
    """One line on errand success: which is better, or that the sample cannot decide; under
    :data:`FEW` buildings a caution that the interval is too narrow to rely on."""
    s = figures["success_rate"]
    if s["low"] > 0 or s["high"] < 0:
        best, worst = (name_a, name_b) if s["difference"] > 0 else (name_b, name_a)
        line = (f"On {n} buildings {best} succeeds more often than {worst}: the difference's "
                "interval excludes 0.")
    else:
        line = (f"On {n} buildings the sample cannot decide between {name_a} and {name_b} on "
                f"errand success: the difference's interval [{s['low']:.3f}, {s['high']:.3f}] "
                "holds 0.")
    if n < FEW:
        line += (f" With fewer than {FEW} buildings a bootstrap interval is too narrow (few "
                 "distinct resamples): read it as a pilot, not a decision.")
    return line


def main(argv: list[str] | None = None, prog: str = "placeclust compare") -> int:
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("a", type=Path, help="results file of recognizer A")
    p.add_argument("b", type=Path, help="results file of recognizer B (may be the same file)")
    p.add_argument("--a", dest="name_a", metavar="NAME", help="A's recognizer, if the file "
                   "holds several")
    p.add_argument("--b", dest="name_b", metavar="NAME", help="B's recognizer, likewise")
    p.add_argument("--force", action="store_true", help="compare results from different "
                   "suites, settings, renders or buildings, on the buildings they share")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's section "
                   "compare-<A>-<B> (docs/benchmarks.md)")
    p.add_argument("--section", help="the section's name instead of compare-<A>-<B>, e.g. "
                   "for the same pair on two sizes of a suite")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    try:
        a, b = load_results(args.a), load_results(args.b)
        name_a = _pick(a, args.name_a, args.a, "--a")
        name_b = _pick(b, args.name_b, args.b, "--b")
        found = differences(a, b)
        if found and not args.force:
            raise ValueError("these results are not comparable (--force to compare them "
                             "anyway): " + "; ".join(found))
        rows_a, rows_b = paired_rows(a, b, name_a, name_b)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for line in found:
        print(f"FLAG {line}")
    for line in version_notes(a, b):
        print(f"note: {line}")
    name_a, name_b = _labels(a, b, name_a, name_b)
    text, figures = table(rows_a, rows_b, name_a, name_b)
    # the task's settings, where both ran the same (a difference is a FLAG line already)
    task = a["settings"].get("task") or {}
    task = task if task == (b["settings"].get("task") or {}) else {}
    seeds = [r["scene_seed"] for r in rows_a]
    span = seed_span(seeds)
    flags = "".join(f"\n- compared anyway (--force): {line}" for line in found)
    body = (f"Paired on {len(rows_a)} buildings (scene seeds {span}), {_suite(a, b, task)}; "
            f"errand figures errand-weighted.{flags}\n\n{text}\n\n"
            f"{verdict(figures, name_a, name_b, len(rows_a))}")
    print(body)
    if args.docs:
        pair = "-".join(slug(n) for n in (name_a, name_b))
        write_section(args.docs, args.section or f"compare-{pair}", body,
                      shlex.join([*prog.split(), *argv]))
    return 0


def _suite(a: dict[str, Any], b: dict[str, Any], task: dict[str, Any]) -> str:
    """Which suite and sizes the files belong to, or that they belong to none, and the task's
    settings where they are not the defaults (e.g. carried errands)."""
    suite = a["provenance"].get("suite")
    if suite is None:
        text = "no suite"
    else:
        sizes = sorted({str(d["provenance"].get("size")) for d in (a, b)})
        text = f"suite {suite} ({' and '.join(sizes)})"
    if task:
        text += ", " + ", ".join(f"{k} {v}" for k, v in sorted(task.items()))
    return text


def _labels(a: dict[str, Any], b: dict[str, Any], name_a: str, name_b: str
            ) -> tuple[str, str]:
    """The two sides' names, with the agent, its policy or the suite size added where the
    files differ in it: the same recognizer under two agents, or after a short and a long
    tour."""
    for where, key in (("settings", "agent"), ("settings", "policy"), ("provenance", "size")):
        va, vb = a[where].get(key), b[where].get(key)
        if key == "policy":  # two policies of the learned agent; another agent has none
            if a["settings"].get("agent") != "ppo" or b["settings"].get("agent") != "ppo":
                continue
            va, vb = policy_name(va), policy_name(vb)
        if va != vb:
            name_a, name_b = f"{name_a} ({va})", f"{name_b} ({vb})"
    return name_a, name_b


# -- the suite score over tracks ------------------------------------------------------------


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


def score_main(argv: list[str] | None = None, prog: str = "placeclust score") -> int:
    """``placeclust score ...`` (the module's second command); the exit status."""
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
