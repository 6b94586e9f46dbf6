"""``placeclust compare``: two recognizers paired on the same buildings, each difference with
its interval.

    placeclust compare runs/a/results.json runs/b/results.json [--a NAME] [--b NAME] [--force] \\
        [--plan ERRANDS ... [--plan-buildings N]] [--docs docs/benchmarks.md [--section NAME]]

Each file is a results file (:mod:`envs.runs.results`: ``placeclust leaderboard`` writes
``OUT/results.json``, ``placeclust errands --json FILE``); both may be one file with ``--a`` and
``--b`` naming two of its recognizers. For each metric the table gives both means, the paired
difference A − B with its 95% interval from a bootstrap over the shared buildings, and the
probability of improvement P(A > B) (:mod:`placeclust.stats`). A difference whose interval
holds 0 is not a difference the sample can decide, and the verdict line says so; ``--plan``
then reads the sample as a pilot (:mod:`placeclust.sizing`): how many buildings, at each count
of errands a building, would decide the success difference if it is what the pilot shows.

Results are comparable only from the same buildings, errands and tours, rendered and simulated
alike: files from different suites, settings or buildings, or with different render or physics
fingerprints (:func:`~envs.runs.suite.physics_fingerprint`), are refused (exit 2) with what
differs; ``--force`` compares them anyway on the buildings they share and prints every
difference as a ``FLAG`` line above the table (and in the docs section). Different package
versions (each one a ``note:`` line) or agents are noted, not refused: comparing two versions,
or two agents on one recognizer's maps, is what a change is judged by. Where the files differ in
agent or suite size, each side's name says which, e.g. ``panorama (long)`` against
``panorama (quick)``: the same maps after a long and a short tour, compared with ``--force``.

One suite score over tracks is ``placeclust score`` (:mod:`envs.commands.score`).
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from placeclust.sizing import POWER, plan
from placeclust.stats import (
    interval,
    paired_difference,
    probability_of_improvement,
)

from ..runs.results import (
    differences,
    groups,
    load_results,
    paired_rows,
    policy_name,
    seed_span,
    slug,
)

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
    p.add_argument("--plan", nargs="+", type=_positive, metavar="ERRANDS", help="also size "
                   "the success difference from this sample as a pilot (placeclust.sizing): "
                   "the buildings that decide it at each count of errands a building")
    p.add_argument("--plan-buildings", type=_positive, metavar="N", help="with --plan, the "
                   "half-width and chance of deciding at N buildings (default: this sample's)")
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
    if args.plan:
        body += "\n\n" + sizing(rows_a, rows_b, args.plan,
                                 args.plan_buildings or len(rows_a))
    print(body)
    if args.docs:
        pair = "-".join(slug(n) for n in (name_a, name_b))
        write_section(args.docs, args.section or f"compare-{pair}", body,
                      shlex.join([*prog.split(), *argv]))
    return 0


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a count: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive count, got {value}")
    return value


def sizing(rows_a: list[dict[str, Any]], rows_b: list[dict[str, Any]], errands: list[int],
           buildings: int) -> str:
    """One paragraph sizing the success difference from these rows as a pilot: the buildings
    that exclude 0 with :data:`~placeclust.sizing.POWER` chance at each count of ``errands``
    a building, and at ``buildings`` buildings the half-width and that chance."""
    try:
        p = plan(groups(rows_a, "success_rate"), groups(rows_b, "success_rate"))
    except ValueError as e:
        return f"Sizing: not possible from this sample ({e})."
    needs = [p.buildings_for(m) for m in errands]
    counts = ", ".join(f"{'no count' if n is None else n} at {m}"
                       for n, m in zip(needs, errands))
    widths = ", ".join(f"{p.half_width(buildings, m):.3f}" for m in errands)
    chances = ", ".join(f"{p.power(buildings, m):.2f}" for m in errands)
    return (f"Sizing the success difference from this sample (`placeclust.sizing`; spread "
            f"between buildings {p.between ** 0.5:.3f}, of one errand a side "
            f"{p.within ** 0.5:.3f}): to exclude 0 with chance {POWER:g} if it is "
            f"{p.difference:+.3f}, buildings needed at {', '.join(map(str, errands))} errands a "
            f"building: {counts}. At {buildings} buildings the half-width would be {widths} and "
            f"the chance of excluding 0 {chances}.")


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
    """The two sides' names, with the agent, its policy, the suite size or whether the map
    learned during the errands added where the files differ in it: the same recognizer under
    two agents, after a short and a long tour, or with its map fixed (``--localize-only``)."""
    for where, key in (("settings", "agent"), ("settings", "policy"), ("provenance", "size")):
        va, vb = a[where].get(key), b[where].get(key)
        if key == "policy":  # two policies of the learned agent; another agent has none
            if a["settings"].get("agent") != "ppo" or b["settings"].get("agent") != "ppo":
                continue
            va, vb = policy_name(va), policy_name(vb)
        if key == "size" and None in (va, vb):  # a run of no suite has no size to name
            continue
        if va != vb:
            name_a, name_b = f"{name_a} ({va})", f"{name_b} ({vb})"
    learns = [(d["settings"].get("task") or {}).get("errand_learn", True) for d in (a, b)]
    if learns[0] != learns[1]:
        name_a, name_b = (f"{n} ({'learning' if learn else 'map fixed'})"
                          for n, learn in zip((name_a, name_b), learns, strict=True))
    return name_a, name_b


if __name__ == "__main__":
    sys.exit(main())
