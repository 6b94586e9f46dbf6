"""The closed-loop leaderboard: recognizers ranked by errand success in buildings never seen.

    placeclust leaderboard --suite placenav-v2 [--size full|quick] \\
        --out runs/leaderboard [--recognizers oracle panorama mypackage.module:Mine ...] \\
        [--preset NAME] [--param NAME=VALUE] [--agent planner] \\
        [--workers N] [--executor process|ray] [--docs docs/benchmarks.md]
    placeclust leaderboard --suite placenav-v5 --split val --n-scenes 4 ...  # other buildings
    placeclust leaderboard --split val --n-scenes 16 --rooms 6 --errands 10 ...

Every recognizer maps every building of the split from a guided tour, and the same agent
(the suite's: ``planner`` in v1, ``relocalizer`` in v2, ``spot`` in v3 and v4; ``planner``
without a suite) runs the same errands on each map
(:func:`envs.runs.tour_errands.run_scene`). A suite (:mod:`envs.runs.suite`) fixes the
buildings, rooms, errands, tour length and seed, so results are comparable across machines and
versions that render and simulate alike (the render and physics fingerprints every results file
records; :func:`~envs.runs.suite.provenance`). A suite with ``--split``/``--scene-seeds``
runs its settings (rooms, errands, tours, seed, agent, tracks) on the buildings named, and
its results say they are not the suite's buildings: a claim checked on more buildings, or
yours. Without a suite, ``--split``/``--scene-seeds`` and the other options say what runs
(one :class:`~envs.runs.task_spec.ErrandTask` a track), and the results belong to no suite.
The table puts task success beside the same maps' open-loop precision, NMI and places per
room, each a mean with its 95% interval from a bootstrap over buildings
(:mod:`placeclust.stats`), and ``success_vs_nmi.png`` plots one against the other.
``OUT/results.json`` (:mod:`envs.runs.results`) holds every building's errands, the
summaries and the provenance; ``placeclust compare`` pairs two recognizers from such files.
A ``package.module:Class`` among the recognizers is one of your own, with ``--preset`` and
``--param`` as its constructor arguments; it is checked before any job starts.

Each (recognizer, building) is one job on a ``spawn`` process pool or Ray; its result is kept in
``OUT/runs/``, so an interrupted run resumes where it stopped; a kept result is used again only
if the code, libraries and rendering that made it are this run's
(:func:`~envs.runs.jobs.stamp`). On one machine the jobs take ``--workers``
processes; ``--executor ray`` with Ray's ``RAY_ADDRESS`` set spreads them over that cluster
(every node with placeclust installed), and the rows come back to ``OUT`` here:

    RAY_ADDRESS=head-node:6379 placeclust leaderboard --suite placenav-v1 --executor ray
"""

from __future__ import annotations

import argparse
import math
import shlex
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from placeclust.progress import plural

from ..runs.jobs import make_jobs, run_jobs, split_tracks, track_jobs
from ..runs.results import (
    TARGET_HALF_WIDTH,
    interval_text,
    policy_name,
    seed_span,
    slug,
    write_results,
)
from ..runs.suite import SIZES, SUITES, TRACKS, get_suite, provenance
from ..runs.task_spec import ErrandTask
from ..runs.tour_errands import ERRAND_AGENTS, check_agent, check_goals
from ..tasks.recognizers import localizes
from ..world.layout import room_count
from ..world.splits import add_scope_arguments, scope_seeds
from .errands import (
    add_recognizer_arguments,
    add_task_arguments,
    recognizer_params,
    run_settings,
    task_from_args,
)
from .score import load_tracks, score_table


def leaderboard(summaries: list[dict[str, Any]]) -> str:
    """The summaries (:func:`~envs.runs.results.summarize`) as a markdown table, best
    first: each figure a mean with its 95% interval over buildings."""
    # image goals (PlaceNav-ImageGoal-v0) add the walking distance left at the errand's end
    left = all("final_distance" in s for s in summaries)
    lines = ["| recognizer | success | SPL |" + (" final distance (m) |" if left else "")
             + " worst building | steps per errand | precision | NMI | places per room |",
             "|---|---|---|---|---|---|---|---|" + ("---|" if left else "")]
    for s in sorted(summaries, key=lambda s: -s["success_rate"]):
        lines.append(f"| {s['recognizer']} | {interval_text(s, 'success_rate')} | "
                     f"{interval_text(s, 'spl')} | "
                     + (f"{interval_text(s, 'final_distance')} | " if left else "")
                     + f"{s['worst_scene_success']:.2f} | "
                     f"{s['mean_length']:.0f} | {interval_text(s, 'precision', 3)} | "
                     f"{interval_text(s, 'nmi', 3)} | {interval_text(s, 'places_per_room')} |")
    return "\n".join(lines)


def power_table(summaries: list[dict[str, Any]]) -> str:
    """How many buildings each recognizer needs for the target half-widths
    (:data:`~envs.runs.results.TARGET_HALF_WIDTH`), from this run's spread of buildings,
    and what one building costs it: the pilot that sizes a suite (``docs/design.md``)."""
    targets = ", ".join(f"{k} ±{v}" for k, v in TARGET_HALF_WIDTH.items())
    lines = [f"| recognizer | buildings for {targets} | half-widths now | core-seconds per "
             "building |", "|---|---|---|---|"]
    for s in summaries:
        needed = " / ".join(str(s.get(f"{k}_buildings_needed", "–")) for k in TARGET_HALF_WIDTH)
        # one building has no spread: no half-width, rather than nan
        now = " / ".join("–" if not all(map(math.isfinite, s[f"{k}_interval"])) else
                         f"{(s[f'{k}_interval'][1] - s[f'{k}_interval'][0]) / 2:.3f}"
                         for k in TARGET_HALF_WIDTH)
        lines.append(f"| {s['recognizer']} | {needed} | {now} | "
                     f"{s['seconds'] / len(s['scenes']):.0f} |")
    return "\n".join(lines)


def rank_agreement(summaries: list[dict[str, Any]]) -> float:
    """Spearman's rank correlation between the recognizers' success and their NMI (NaN for
    fewer than 3 recognizers)."""
    from placeclust import stats

    return stats.rank_agreement([s["success_rate"] for s in summaries],
                                [s["nmi"] for s in summaries]).mean


def plot(summaries: list[dict[str, Any]], path: Path) -> None:
    """Task success against open-loop NMI, one labelled point per recognizer."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    for i, s in enumerate(summaries):
        ax.scatter(s["nmi"], s["success_rate"])
        # recognizers with no information share a point: their labels go one under the other
        below = sum(abs(t["nmi"] - s["nmi"]) < 0.05 and abs(t["success_rate"]
                                                             - s["success_rate"]) < 0.05
                    for t in summaries[:i])
        ax.annotate(s["recognizer"], (s["nmi"], s["success_rate"]), textcoords="offset points",
                    xytext=(5, 5 - 12 * below))
    ax.set(xlabel="open-loop NMI of the tour's map", ylabel="errand success rate",
           xlim=(-0.05, 1.05), ylim=(-0.05, 1.05), title="Recognizers in closed loop")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


#: a run's plan: each track (``None``: no track) with its buildings and its errands
Plan = dict[str | None, tuple[list[int], ErrandTask]]

#: the options a suite fixes
SUITE_FIXES = ("--rooms", "--errands", "--goals-per-scene", "--seed", "--tour-steps-per-room",
               "--errand-start", "--layout", "--local-light", "--track", "--localize-only",
               "--goal-kind", "--success-radius")
#: the options that name other buildings than a suite's (--doors, buildings with doors, too)
BUILDINGS = ("--split", "--scene-seeds", "--n-scenes")


def _given(argv: list[str], options: tuple[str, ...]) -> list[str]:
    return [o for o in options if any(a == o or a.startswith(o + "=") for a in argv)]


def _plan(args: argparse.Namespace, p: argparse.ArgumentParser, argv: list[str]) -> Plan:
    """What a run measures for each of its tracks: the suite's buildings and errands, the
    suite's errands on the buildings the options name, or the options' own."""
    if args.suite is None:
        if args.size != "full":
            p.error("--size goes with --suite")
        args.agent = args.agent or "planner"
        seeds = scope_seeds(args, p)
        try:
            return {t: (seeds, task_from_args(args, t)) for t in (args.tracks or [None])}
        except ValueError as e:
            p.error(str(e))
    suite = get_suite(args.suite)
    if args.size not in suite.sizes:
        p.error(f"{suite.name} runs at the sizes {', '.join(suite.sizes)}"
                + ("; its long tours are the track 'long'" if suite.tracks else ""))
    fixed = _given(argv, SUITE_FIXES)
    if fixed:
        p.error(f"the suite {args.suite} fixes {' '.join(fixed)}; leave them out, or "
                "leave out --suite (the results then belong to no suite)")
    others = bool(_given(argv, BUILDINGS))
    args.named_buildings = others or args.doors is not None
    if others and args.size != "full":
        p.error("--size picks among the suite's buildings; --split/--scene-seeds name others")
    named = scope_seeds(args, p) if others else []
    if not others:
        args.split = suite.split
    args.rooms, args.seed = suite.n_rooms, suite.seed
    args.agent = args.agent or suite.agent
    args.tracks = suite.tracks_at(args.size) or None
    plan: Plan = {}
    for t in args.tracks or [None]:
        task = suite.task(args.size, t)
        if args.doors is not None:  # the suite's errands in buildings with doors
            try:
                task = replace(task, doors=args.doors)
            except ValueError as e:
                p.error(str(e).replace("doors must", "--doors must"))
        plan[t] = (named or suite.scene_seeds(args.size, t), task)
    return plan


def suite_jobs(plan: Plan, recognizers: list[str], **common: Any) -> list[dict[str, Any]]:
    """The jobs of several tracks whose buildings differ (a suite's tracks, each sized on its
    own): each building's tour serves every track that has that building
    (:func:`~envs.runs.jobs.track_jobs`), so a smaller track costs no tours."""
    serving: dict[int, list[str]] = {}
    for track, (seeds, _) in plan.items():
        for seed in seeds:
            serving.setdefault(seed, []).append(str(track))
    groups: dict[tuple[str, ...], list[int]] = {}
    for seed, tracks in serving.items():
        groups.setdefault(tuple(tracks), []).append(seed)
    return [job for tracks, seeds in groups.items()
            for job in track_jobs(seeds, recognizers, {t: plan[t][1] for t in tracks},
                                  **common)]


def main(argv: list[str] | None = None, prog: str = "placeclust leaderboard"
         ) -> int:
    # no abbreviations: the options a suite fixes are told by their full names
    p = ArgumentParser(prog=prog, description=__doc__, allow_abbrev=False,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--suite", choices=sorted(SUITES), help="run a frozen suite: its buildings, "
                   "rooms, errands, tours and seed (envs.runs.suite)")
    p.add_argument("--size", choices=SIZES, default="full", help="the suite's full size, its "
                   "quick check, or (placenav-v1) its long tours (default full)")
    add_scope_arguments(p, n_scenes=8, default_split="test")
    p.add_argument("--rooms", type=room_count, default=6)
    add_recognizer_arguments(p, many=True)
    p.add_argument("--agent", choices=ERRAND_AGENTS, help="the errand agent (default: the "
                   "suite's, relocalizer from placenav-v2 on; planner without a suite)")
    p.add_argument("--policy", type=Path, help="the ppo agent's policy (default: shipped)")
    add_task_arguments(p, many_tracks=True)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", type=Path, default=Path("runs/leaderboard"), help="where the "
                   "results go: OUT/results.json, or OUT/TRACK/results.json for each of "
                   "several tracks")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--executor", choices=("process", "ray"), default="process",
                   help="a local process pool, or Ray: a local instance of --workers CPUs, or "
                   "the cluster at RAY_ADDRESS if set")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's section "
                   "leaderboard-<suite or split>[-<size>][-<track>][-localize][-doors][-<agent>] "
                   "(docs/benchmarks.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    args.named_buildings = False
    plan = _plan(args, p, argv)
    tasks = [task for _, task in plan.values()]
    images = any(task.images for task in tasks)
    if images and not any(a.startswith("--recognizers") for a in argv):
        args.recognizers = ["oracle-pose", *args.recognizers]  # image goals' ceiling
    fixed = {t for t, (_, task) in plan.items() if not task.errand_learn}
    try:
        check_agent(args.agent, args.policy)
        check_goals(args.agent, tasks)
        params = recognizer_params(args.recognizers, args.preset, args.param)
        # a fixed map needs localize_one: one without it runs only where the map learns
        skipped = [r for r in args.recognizers if fixed and not localizes(r, params[r])]
        if skipped:
            where = f" (tracks {', '.join(sorted(map(str, fixed)))})" if len(fixed) < len(
                plan) else ""
            print(f"skipped on a fixed map (no localize_one): {', '.join(skipped)}{where}",
                  file=sys.stderr)
        runs = {t: [r for r in args.recognizers if t not in fixed or r not in skipped]
                for t in plan}
        if not any(runs.values()):
            raise ValueError("no recognizer left to run: none of them can localize on a "
                             "fixed map; leave out --localize-only")
        common = {"n_rooms": args.rooms, "agent": args.agent, "seed": args.seed,
                  "policy": args.policy, "params": params}
        if args.tracks and len(args.tracks) > 1:
            able = [r for r in args.recognizers if r not in skipped]
            learning = {t: v for t, v in plan.items() if t not in fixed}
            jobs = (suite_jobs(plan, able, **common) if able else []) + (
                suite_jobs(learning, skipped, **common) if skipped and learning else [])
            done = split_tracks(run_jobs(jobs, args.out, args.workers, args.executor))
            by_track: dict[str | None, list] = {t: done[t] for t in args.tracks}
        else:
            ((track, (seeds, task)),) = plan.items()
            jobs = make_jobs(seeds, runs[track], task, **common)
            by_track = {track: run_jobs(jobs, args.out, args.workers, args.executor)}
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    several = len(by_track) > 1
    for track, rows in by_track.items():
        out = args.out / track if several and track else args.out
        seeds, task = plan[track]
        gone = skipped if track in fixed else []
        _report(args, prog, argv, rows, {**run_settings(args, seeds, task, track),
                                         "recognizers": runs[track],
                                         **({"skipped": gone} if gone else {})},
                out, track, task)
    # image goals' ceiling knows the goal's pose; room goals' is the true rooms
    ceiling = "oracle-pose" if images else "oracle"
    if several and all({"none", ceiling} <= set(runs[t]) for t in by_track):
        try:
            print("\n" + score_table(load_tracks([args.out / str(t) / "results.json"
                                                   for t in by_track]), "none", ceiling,
                                     "mean")[0])
        except ValueError as e:  # the runs are kept: only the score cannot be formed
            print(f"no suite score: {e}", file=sys.stderr)
    return 0


def _report(args: argparse.Namespace, prog: str, argv: list[str], rows: list[dict[str, Any]],
            settings: dict[str, Any], out: Path, track: str | None, task: ErrandTask) -> None:
    """One track's results file, table, plot and docs section."""
    suite = None if args.suite is None else get_suite(args.suite)
    seeds = settings["scene_seeds"]
    doc = write_results(out / "results.json", rows, settings["recognizers"], settings,
                        provenance(suite, args.size, args.named_buildings))
    summaries = doc["summaries"]
    skipped = settings.get("skipped", [])
    body = (_describe(args, seeds, summaries, doc["provenance"], task, track)
            + "\n\n"
            + leaderboard(summaries)
            + (f"\n\nSkipped (no `localize_one`, so no fixed map to run on): "
               f"{', '.join(skipped)}." if skipped else "")
            + "\n\nSample size: the buildings a sample like this "
            "one needs for each target half-width, from its spread of buildings "
            "(`placeclust.stats.buildings_for`), and the cost of one building.\n\n"
            + power_table(summaries))
    print(body)
    plot(summaries, out / "success_vs_nmi.png")
    if args.docs:
        name = "leaderboard-" + (args.suite or args.split or "scenes")
        if args.suite and args.named_buildings:  # not the suite's buildings: its own table
            name += f"-{args.split or 'scenes'}"
        name += "" if args.size == "full" else f"-{args.size}"
        name += f"-{track}" if track else ""
        name += "-localize" if args.localize_only else ""
        name += "-doors" if args.doors is not None else ""  # another building: its own table
        name += "" if args.agent == (suite.agent if suite else "planner") else f"-{args.agent}"
        if args.agent == "ppo" and args.policy:  # two policies' boards keep their own sections
            name += "-" + slug(policy_name(str(args.policy)))
        write_section(args.docs, name, body, shlex.join([*prog.split(), *argv]))


def _describe(args: argparse.Namespace, seeds: list[int], summaries: list[dict[str, Any]],
              prov: dict[str, Any], task: ErrandTask, track: str | None = None) -> str:
    """The paragraph above the table: what ran, on what, for how long, and how sure."""
    rho = (f"{rank_agreement(summaries):.2f}" if len(summaries) > 2
           else "too few recognizers for one (3 at least)")
    minutes = sum(s["seconds"] for s in summaries) / 60
    where = f"{args.split} split, scene seeds" if args.split else "scene seeds"
    span = seed_span(seeds)
    suite = (f"Suite `{prov['suite']}` ({prov['size']}), placeclust "
             f"{prov['versions']['placeclust']}, MuJoCo {prov['versions']['mujoco']}, render "
             f"fingerprint `{prov['render_fingerprint']}`, physics fingerprint "
             f"`{prov['physics_fingerprint']}`. " if prov["suite"] else "")
    if prov.get("buildings") == "named":
        suite = suite.replace(f"`{prov['suite']}` ({prov['size']})",
                              f"`{prov['suite']}`'s settings on other buildings than its own "
                              "(named by the command, or with doors; not the suite's figures)")
    redrawn = sum(s["redrawn"] for s in summaries)
    where_from = f"Track `{track}`: {TRACKS[track].tests}. " if track else ""
    if not task.errand_learn:
        where_from += "The map is fixed after the tour (the recognizers only localize). "
    errands = sum(s["n_errands"] for s in summaries)
    buildings = "1 building" if len(seeds) == 1 else f"{len(seeds)} buildings"
    return (f"{suite}{where_from}{buildings} of {args.rooms} rooms ({where} {span}), "
            f"{task.n_errands} errands each after one guided tour, episode seed "
            f"{args.seed}, agent `{args.agent}`{_policy(args)}; "
            f"{plural(round(minutes), 'minute')} of one core in all. "
            f"Each figure: the mean over errands (tours for the map's figures) with its 95% "
            f"interval from a bootstrap over buildings. {redrawn} of {errands} errands were "
            f"redrawn to start {task.far_text()}. Spearman's rank "
            f"correlation of success with NMI ({len(summaries)} points, no interval): {rho}."
            + (" One building: no interval can be drawn from it." if len(seeds) < 2 else ""))


def _policy(args: argparse.Namespace) -> str:
    if args.agent != "ppo":
        return ""
    return f" (policy {policy_name(None if args.policy is None else str(args.policy))})"


if __name__ == "__main__":
    sys.exit(main())
