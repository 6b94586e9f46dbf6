"""Whether this install gives a shipped job store's rows again, row for row.

    python -m envs.commands.reproduce docs/runs/placenav-v4 [--recognizer nested] [--jobs 1]

A frozen suite's store (``docs/runs/<suite>/runs``, written by ``placeclust leaderboard
--suite``) keeps every job's row: one recognizer's guided tour of one building and its
errands on every track that building serves, stamped with the library versions and the render
fingerprint that made it. This command runs the ``--jobs`` cheapest stored jobs (by their
recorded seconds) again with today's code and compares every recorded field, errand by
errand: one line per job, ``same`` or the first fields that differ (exit 1 if any does).

Run from a clone (the store ships in ``docs/runs/``; not yet a ``placeclust`` subcommand, as
adding one moves every cited section's code fingerprint). Timings (``seconds``) are not
compared. A store this machine cannot reproduce is refused in
one line, exit 2, before anything runs: rows drawn by another render fingerprint (rendering
depends on the CPU) or driven by another MuJoCo (its physics differ between versions). A fresh
install from ``constraints.txt`` (what every make target installs) has the pinned MuJoCo, so
only the CPU can stand in the way.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import mujoco

from placeclust import strict_json
from placeclust.argparsing import ArgumentParser

from ..runs.suite import get_suite, render_fingerprint
from ..runs.tour_errands import run_scene
from .leaderboard import Plan, suite_jobs

#: fields that record how long a job took, not what it measured
TIMINGS = frozenset({"seconds"})
#: fields of the store's own bookkeeping
BOOKKEEPING = frozenset({"stamp", "key", "policy"})


def stored_rows(store: Path) -> list[dict[str, Any]]:
    """Every row of a job store (``store/runs/*.json``), cheapest first (recorded seconds)."""
    rows = [json.loads(p.read_text()) for p in sorted((store / "runs").glob("*.json"))]
    return sorted(rows, key=lambda r: (r.get("seconds", 0.0), r["key"]))


def store_suite(store: Path) -> str:
    """The suite a store's results files name (``provenance.suite``); a ``ValueError`` if none
    does."""
    for path in sorted(store.glob("*/results.json")) + [store / "results.json"]:
        if path.is_file():
            suite = json.loads(path.read_text()).get("provenance", {}).get("suite")
            if suite:
                return str(suite)
    raise ValueError(f"{store} holds no results file of a suite (placeclust leaderboard "
                     "--suite writes one per track)")


def unlike_here(row: dict[str, Any]) -> str | None:
    """Why this machine cannot reproduce ``row`` (its render fingerprint or MuJoCo differ), or
    None."""
    stamp = row.get("stamp", {})
    drawn, here = stamp.get("render_fingerprint"), render_fingerprint()
    if drawn != here:
        return (f"its rows were drawn by render fingerprint {drawn}, this machine draws {here} "
                "(rendering depends on the CPU)")
    driven = stamp.get("versions", {}).get("mujoco")
    if driven != mujoco.__version__:
        return (f"its rows were driven by MuJoCo {driven}, this install has "
                f"{mujoco.__version__} (install constraints.txt: make test does)")
    return None


def job_of(row: dict[str, Any], suite_name: str) -> dict[str, Any]:
    """Today's job (:func:`~envs.runs.tour_errands.run_scene`'s arguments) for a stored row of
    ``suite_name``'s store: the same recognizer and parameters, building and tracks. Matched by
    content, not by file name, so a row whose key was spelled by an older version is found."""
    suite = get_suite(suite_name)
    plan: Plan = {t: (suite.scene_seeds("full", t), suite.task("full", t))
                  for t in suite.tracks_at("full")}
    recognizer = row["recognizer"]
    jobs = suite_jobs(plan, [recognizer], n_rooms=suite.n_rooms, agent=row["agent"],
                      seed=suite.seed, policy=None,
                      params={recognizer: row.get("recognizer_params") or {}})
    tracks = set(row.get("tracks", {}))
    found = [j for j in jobs if j["scene_seed"] == row["scene_seed"]
             and set(j.get("tracks", {})) == tracks]
    if len(found) != 1:
        raise ValueError(f"{row['key']}: {suite_name} has no job of building "
                         f"{row['scene_seed']} serving the tracks {sorted(tracks)}")
    return found[0]


def differences(stored: Any, fresh: Any, path: str = "") -> list[str]:
    """The fields of ``stored`` whose value ``fresh`` does not repeat exactly (JSON values;
    timings and bookkeeping left out), each as ``path: stored -> fresh``. Fields only
    ``fresh`` has (a newer version records more) are not differences."""
    if isinstance(stored, dict) and isinstance(fresh, dict):
        found = []
        for key in sorted(set(stored) - TIMINGS - BOOKKEEPING):
            where = f"{path}.{key}" if path else key
            if key not in fresh:
                found.append(f"{where}: {_short(stored[key])} -> (missing)")
            else:
                found += differences(stored[key], fresh[key], where)
        return found
    if isinstance(stored, list) and isinstance(fresh, list) and len(stored) == len(fresh):
        return [d for i, (a, b) in enumerate(zip(stored, fresh))
                for d in differences(a, b, f"{path}[{i}]")]
    return [] if stored == fresh else [f"{path}: {_short(stored)} -> {_short(fresh)}"]


def _short(value: Any) -> str:
    text = json.dumps(value)
    return text if len(text) <= 60 else text[:57] + "..."


def run_again(job: dict[str, Any]) -> dict[str, Any]:
    """The row ``job`` (:func:`job_of`) gives today, as the store would read it back (JSON)."""
    return json.loads(strict_json.dumps(run_scene(**job)))


def main(argv: list[str] | None = None,
         prog: str = "python -m envs.commands.reproduce") -> int:
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("store", type=Path, help="a suite's job store (docs/runs/<suite>)")
    p.add_argument("--recognizer", help="only this recognizer's jobs (default: any)")
    p.add_argument("--jobs", type=int, default=1, help="how many jobs, cheapest first "
                   "(default 1)")
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    if args.jobs < 1:
        p.error(f"--jobs must be at least 1, got {args.jobs}")
    try:
        suite = store_suite(args.store)
        rows = [r for r in stored_rows(args.store)
                if args.recognizer in (None, r["recognizer"])][:args.jobs]
        if not rows:
            raise ValueError(f"{args.store}/runs holds no job" + (
                f" of {args.recognizer}" if args.recognizer else ""))
        unlike = next(filter(None, map(unlike_here, rows)), None)
        if unlike:
            raise ValueError(f"{args.store} cannot be reproduced here: {unlike}")
        jobs = [(row, job_of(row, suite)) for row in rows]  # every one found before any runs
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    differing = 0
    for row, job in jobs:
        found = differences(row, run_again(job))
        differing += bool(found)
        print(f"{row['key']}: " + ("same" if not found else
                                   f"{len(found)} fields differ, first: " + "; ".join(found[:3])))
    print(f"{len(jobs) - differing} of {len(jobs)} stored jobs of {suite} reproduced row for row")
    return 1 if differing else 0


if __name__ == "__main__":
    raise SystemExit(main())
