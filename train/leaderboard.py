"""The closed-loop leaderboard: recognizers ranked by errand success in buildings never seen.

    python -m train.leaderboard --split test --rooms 6 --goals-per-scene 5 --seed 0 \\
        --out runs/leaderboard [--recognizers oracle online ...] [--agent planner] \\
        [--workers N] [--executor process|ray] [--docs docs/benchmarks.md]

Every recognizer maps every building of the split from a guided tour, and the same agent
(:mod:`train.tour_planner` by default) runs the same errands on each map
(:func:`train.unseen.run_scene`). The table puts task success beside the same maps' open-loop
precision, NMI and places per room, and ``success_vs_nmi.png`` plots one against the other.
Each (recognizer, building) is one job on a ``spawn`` process pool or Ray; its result is kept in
``OUT/runs/``, so an interrupted run resumes where it stopped; a kept result is used again only
if the agent that made it is the same (:func:`agent_fingerprint`).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import shlex
import sys
from pathlib import Path
from typing import Any

from envs.guided_tour import RECOGNIZERS
from envs.pool import run_all
from envs.splits import add_scope_arguments, scope_seeds
from placeclust import __version__
from placeclust.atomic import write_atomic
from placeclust.docs_section import write_section
from placeclust.progress import progress as progress_bar
from train.unseen import AGENTS, POLICY, run_scene, summarize

#: the slow recognizers first, so the last job to finish is a short one
COST = {"online": 0, "nested": 1, "online-orb": 2, "random": 3, "none": 4, "oracle": 5}
#: the source files an agent's errands depend on, besides the placeclust version
AGENT_SOURCES = ("train/unseen.py", "train/tour_planner.py", "train/planner.py",
                 "train/errand_agent.py", "envs/tour.py")
_ROOT = Path(__file__).resolve().parent.parent


def agent_fingerprint(job: dict[str, Any]) -> str:
    """A hash of what drives a job's agent: :data:`AGENT_SOURCES` and, for ``ppo``, the
    policy file. A planner edited or a policy trained again within one version of placeclust
    would otherwise be scored by the rows its predecessor left in ``OUT/runs/``."""
    digest = hashlib.sha256()
    for name in AGENT_SOURCES:
        digest.update((_ROOT / name).read_bytes())
    if job["agent"] == "ppo":
        policy = Path(job.get("policy") or POLICY)
        if policy.is_file():  # a missing one is reported by the job itself
            digest.update(policy.read_bytes())
    return digest.hexdigest()[:16]


def job_key(job: dict[str, Any]) -> str:
    """The file name of a job's result: everything that changes it."""
    policy = f"-{Path(job['policy']).stem}" if job.get("policy") else ""
    return (f"{job['recognizer']}-{job['agent']}{policy}-scene{job['scene_seed']}"
            f"-rooms{job['n_rooms']}-goals{job['goals']}-seed{job['seed']}")


def make_jobs(scene_seeds: list[int], recognizers: list[str], n_rooms: int, agent: str,
              goals: int, seed: int, policy: Path | None = None) -> list[dict[str, Any]]:
    """One :func:`~train.unseen.run_scene` job per recognizer and building."""
    extra = {"policy": str(policy)} if policy else {}
    return [{"scene_seed": s, "n_rooms": n_rooms, "recognizer": r, "agent": agent,
             "goals": goals, "seed": seed, **extra} for r in recognizers for s in scene_seeds]


def run_jobs(jobs: list[dict[str, Any]], out: Path | None = None, workers: int = 1,
             executor: str = "process", progress: bool = True) -> list[dict[str, Any]]:
    """Run :func:`~train.unseen.run_scene` for each job (its keyword arguments); the rows.

    With ``out``, each row is kept in ``out/runs/<key>.json`` and a row already there from
    this version of placeclust and the same agent (:func:`agent_fingerprint`) is not run again.
    """
    store = None if out is None else Path(out) / "runs"
    agents = {job_key(job): agent_fingerprint(job) for job in jobs}
    done = {}
    if store is not None:
        store.mkdir(parents=True, exist_ok=True)
        for job in jobs:
            path = store / f"{job_key(job)}.json"
            if path.is_file():
                row = json.loads(path.read_text())
                if (row.get("version"), row.get("agent_fingerprint")) == (
                        __version__, agents[job_key(job)]):
                    done[job_key(job)] = row
    todo = sorted((j for j in jobs if job_key(j) not in done),
                  key=lambda j: COST.get(j["recognizer"], 0))
    bar = progress_bar(total=len(todo), enabled=progress, desc="errands", unit="building")
    for job, row in run_all(_run_job, todo, workers, executor):
        row["version"], row["agent_fingerprint"] = __version__, agents[job_key(job)]
        done[job_key(job)] = row
        if store is not None:
            write_atomic(store / f"{job_key(job)}.json",
                         lambda f, row=row: f.write(json.dumps(row, indent=1).encode()))
        bar.update()
    bar.close()
    return [done[job_key(j)] for j in jobs]


def _run_job(job: dict[str, Any]) -> dict[str, Any]:
    return run_scene(**job)


def leaderboard(summaries: list[dict[str, Any]]) -> str:
    """The summaries (:func:`~train.unseen.summarize`) as a markdown table, best first."""
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


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m train.leaderboard", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    add_scope_arguments(p, n_scenes=8, default_split="test")
    p.add_argument("--rooms", type=int, default=6)
    p.add_argument("--recognizers", nargs="+", choices=RECOGNIZERS, default=list(RECOGNIZERS))
    p.add_argument("--agent", choices=AGENTS, default="planner")
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
    jobs = make_jobs(seeds, args.recognizers, args.rooms, args.agent, args.goals_per_scene,
                     args.seed, args.policy)
    try:
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
        write_section(args.docs, name, body, shlex.join(["python", "-m", "train.leaderboard",
                                                         *argv]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
