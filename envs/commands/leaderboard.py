"""The closed-loop leaderboard: recognizers ranked by errand success in buildings never seen.

    placeclust leaderboard --split test --rooms 6 --goals-per-scene 5 --seed 0 \\
        --out runs/leaderboard [--recognizers oracle panorama mypackage.module:Mine ...] \\
        [--preset NAME] [--param NAME=VALUE] [--agent planner] \\
        [--workers N] [--executor process|ray] [--docs docs/benchmarks.md]

Every recognizer maps every building of the split from a guided tour, and the same agent
(:mod:`envs.agents.teach_repeat` by default) runs the same errands on each map
(:func:`envs.commands.closed_loop.run_scene`). The table puts task success beside the same maps'
open-loop precision, NMI and places per room, and ``success_vs_nmi.png`` plots one against the
other. A ``package.module:Class`` among the recognizers is one of your own, with ``--preset``
and ``--param`` as its constructor arguments; it is checked before any job starts.

Each (recognizer, building) is one job on a ``spawn`` process pool or Ray; its result is kept in
``OUT/runs/``, so an interrupted run resumes where it stopped; a kept result is used again only
if the agent that made it is the same (:func:`~envs.commands.closed_loop.agent_fingerprint`).
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path
from typing import Any

from placeclust.docs_section import write_section

from ..world.splits import add_scope_arguments, scope_seeds
from .closed_loop import (
    ERRAND_AGENTS,
    add_recognizer_arguments,
    make_jobs,
    recognizer_params,
    run_jobs,
    summarize,
)


def leaderboard(summaries: list[dict[str, Any]]) -> str:
    """The summaries (:func:`~envs.commands.closed_loop.summarize`) as a markdown table, best
    first."""
    lines = ["| recognizer | success | worst building | SPL | steps per errand | precision | "
             "NMI | places per room |", "|---|---|---|---|---|---|---|---|"]
    for s in sorted(summaries, key=lambda s: -s["success_rate"]):
        lines.append(f"| {s['recognizer']} | {s['success_rate']:.2f} | "
                     f"{s['worst_scene_success']:.2f} | {s['spl']:.2f} | "
                     f"{s['mean_length']:.0f} | {s['precision']:.3f} | {s['nmi']:.3f} | "
                     f"{s['places_per_room']:.2f} |")
    return "\n".join(lines)


def rank_agreement(summaries: list[dict[str, Any]]) -> float:
    """Spearman's rank correlation between the recognizers' success and their NMI."""
    from scipy.stats import spearmanr

    rho = spearmanr([s["success_rate"] for s in summaries], [s["nmi"] for s in summaries])
    return float(rho.statistic)


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


def main(argv: list[str] | None = None, prog: str = "placeclust leaderboard"
         ) -> int:
    p = argparse.ArgumentParser(prog=prog, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    add_scope_arguments(p, n_scenes=8, default_split="test")
    p.add_argument("--rooms", type=int, default=6)
    add_recognizer_arguments(p, many=True)
    p.add_argument("--agent", choices=ERRAND_AGENTS, default="planner")
    p.add_argument("--policy", type=Path, help="the ppo agent's policy (default: shipped)")
    p.add_argument("--goals-per-scene", type=int, default=5)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", type=Path, default=Path("runs/leaderboard"))
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--executor", choices=("process", "ray"), default="process")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's section "
                   "leaderboard-<split>[-<agent>] (docs/benchmarks.md)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    seeds = scope_seeds(args, p)
    try:
        params = recognizer_params(args.recognizers, args.preset, args.param)
        jobs = make_jobs(seeds, args.recognizers, args.rooms, args.agent,
                         args.goals_per_scene, args.seed, args.policy, params)
        rows = run_jobs(jobs, args.out, args.workers, args.executor)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    summaries = [summarize([r for r in rows if r["recognizer"] == rec])
                 for rec in args.recognizers]
    table = leaderboard(summaries)
    rho = rank_agreement(summaries) if len(summaries) > 2 else float("nan")
    minutes = sum(s["seconds"] for s in summaries) / 60
    split = f"{args.split} split, scene seeds" if args.split else "scene seeds"
    body = (f"{len(seeds)} buildings of {args.rooms} rooms ({split} {seeds}), "
            f"{args.goals_per_scene} errands each after one guided tour, episode seed "
            f"{args.seed}, agent `{args.agent}`; {minutes:.0f} minutes of one core in all. "
            f"Spearman's rank correlation of success with NMI: {rho:.2f}.\n\n{table}")
    print(body)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "leaderboard.json").write_text(json.dumps(summaries, indent=1))
    plot(summaries, args.out / "success_vs_nmi.png")
    if args.docs:
        name = "leaderboard-" + (args.split or "scenes")
        name += "" if args.agent == "planner" else f"-{args.agent}"
        write_section(args.docs, name, body, shlex.join([*prog.split(), *argv]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
