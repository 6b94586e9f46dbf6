"""Closed-loop jobs: one :func:`~envs.runs.tour_errands.run_scene` per recognizer and
building, run on a pool and kept in a store, each row stamped with the code that made it.

:func:`run_jobs` runs what the store lacks (or holds stale) and resumes an interrupted run:
``placeclust errands`` and ``placeclust leaderboard`` (:mod:`envs.commands`) and
``train.choose`` call it.

Examples:
    >>> from envs.runs.jobs import make_jobs, run_jobs
    >>> from envs.runs.task_spec import ErrandTask
    >>> jobs = make_jobs([0], ["oracle"], ErrandTask(n_errands=1, tour_steps_per_room=30),
    ...                  n_rooms=3, agent="planner", seed=0)
    >>> [row["success_rate"] for row in run_jobs(jobs, progress=False)]
    [1.0]
"""

from __future__ import annotations

import hashlib
import inspect
import json
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from placeclust.progress import plural
from placeclust.progress import progress as progress_bar
from placeclust.runner import recognizer_class

from ..agents.learned import config_path
from ..tasks.oracles import is_oracle_name
from ..tasks.recognizers import is_own
from .pool import run_all
from .results import policy_name
from .store import RunStore
from .suite import library_versions, render_fingerprint, sources_fingerprint
from .task_spec import ErrandTask
from .tour_errands import POLICY, run_scene

#: the slow recognizers first, so the last job to finish is a short one: a recognizer of
#: one's own with the slowest, the calibration oracles (which render nothing) with ``oracle``
COST = {"panorama": 0, "nested": 1, "panorama-orb": 2, "random": 3, "none": 4, "oracle": 5}


def _cost(job: dict[str, Any]) -> int:
    name = job["recognizer"]
    return COST.get(name, COST["oracle"] if is_oracle_name(name) else 0)


def job_fingerprint(job: dict[str, Any]) -> str:
    """A hash of all the code that makes a job's result: the library, the world, the tasks
    and the agents (:func:`~envs.commands.suite.code_fingerprint`), this module and the one
    that runs a building's tour and errands (:mod:`envs.commands.tour_errands`), for a
    ``package.module:Class`` recognizer its module's source, and for ``ppo`` the policy
    file and its ``config.yml``. A kept row is reused only under the same fingerprint,
    library versions and render fingerprint (:func:`run_jobs`): an edit anywhere a result
    could come from, within one version of placeclust, runs the job again."""
    sources = [Path(__file__), Path(inspect.getfile(run_scene))]
    if is_own(job.get("recognizer", "")):
        sources.append(Path(inspect.getfile(recognizer_class(job["recognizer"]))))
    if job["agent"] == "ppo":
        policy = Path(job.get("policy") or POLICY)
        if policy.is_file():  # a missing one is reported by the job itself
            sources.append(policy)
            config = config_path(policy)
            if config.is_file():  # what the policy observes, how often it acts
                sources.append(config)
    return sources_fingerprint(*sources)


#: the fields a job's file name spells out; any other is hashed into it
_KEY_FIELDS = frozenset({"scene_seed", "n_rooms", "recognizer", "agent", "n_errands", "seed",
                         "policy"})


def job_key(job: dict[str, Any]) -> str:
    """The file name of a job's result: everything that changes it."""
    policy = f"-{policy_name(job['policy'])}" if job.get("policy") else ""
    extra = {k: v for k, v in job.items() if k not in _KEY_FIELDS}
    if extra:  # recognizer_params, tour length...: a short hash, values need not make a name
        text = json.dumps(extra, sort_keys=True, default=repr)
        policy += f"-params{hashlib.sha256(text.encode()).hexdigest()[:8]}"
    recognizer = job["recognizer"].replace(":", "-")
    return (f"{recognizer}-{job['agent']}{policy}-scene{job['scene_seed']}"
            f"-rooms{job['n_rooms']}-errands{job['n_errands']}-seed{job['seed']}")


def make_jobs(scene_seeds: list[int], recognizers: list[str], task: ErrandTask, n_rooms: int,
              agent: str, seed: int, policy: Path | None = None,
              params: dict[str, dict[str, Any]] | None = None,
              tracks: Mapping[str, ErrandTask] | None = None) -> list[dict[str, Any]]:
    """One :func:`run_scene` job per recognizer and building, each the keyword arguments of
    :func:`run_scene`: ``task``'s (:meth:`~envs.runs.task_spec.ErrandTask.kwargs`), or with
    ``tracks`` (name -> task, each of ``task``'s tour and errand count) ``task``'s tour and
    each track's errands after it; ``params`` maps a recognizer to its constructor
    arguments."""
    extra: dict[str, Any] = {"policy": str(policy)} if policy else {}
    own = task.kwargs()
    if tracks is not None:  # the job is the tour; each track adds its errands' arguments
        extra["tracks"] = {name: t.errand_kwargs() for name, t in tracks.items()}
        own = {"n_errands": task.n_errands, **task.tour_kwargs()}
    params = params or {}
    return [{"scene_seed": s, "n_rooms": n_rooms, "recognizer": r, "agent": agent,
             "seed": seed, **extra, **own,
             **({"recognizer_params": params[r]} if params.get(r) else {})}
            for r in recognizers for s in scene_seeds]


def run_jobs(jobs: list[dict[str, Any]], out: Path | None = None, workers: int = 1,
             executor: str = "process", progress: bool = True) -> list[dict[str, Any]]:
    """Run :func:`run_scene` for each job (its keyword arguments); the rows.

    With ``out``, each row is kept in ``out/runs/<key>.json`` (a
    :class:`~envs.commands.store.RunStore`, the bench's) with its :func:`stamp`; a row
    already there is used again only if its stamp is this run's (the same code, library
    versions and rendering). Stale rows are run again, and counted on standard error.
    """
    store = None if out is None else RunStore(Path(out) / "runs", _memo(stamp))
    done: dict[str, dict[str, Any]] = {}
    if store is not None:
        kept = {job_key(job): store.get(job_key(job)) for job in jobs}
        done = {key: row for key, row in kept.items() if row is not None}
    if store is not None and store.stale:
        print(f"{len(store.stale)} kept results in {store.folder} are stale (code, libraries "
              "or rendering changed since) and run again", file=sys.stderr)
    todo = sorted((j for j in jobs if job_key(j) not in done),
                  key=_cost)
    if progress:  # at once: the first job's line comes only after its tour
        reused = f", {len(done)} kept from an earlier run in {out}" if done else ""
        print(f"errands: {plural(len(todo), 'job')} to run{reused} (a job: one recognizer's "
              f"guided tour of one building, then its errands; {workers} at a time)",
              file=sys.stderr, flush=True)
    bar = progress_bar(total=len(todo), enabled=progress, desc="errands", unit="job")
    finished = 0
    results = run_all(_run_job, todo, workers, executor)
    try:
        for job, row in results:
            row = {**row, "key": job_key(job), "policy": job.get("policy")}
            done[job_key(job)] = store.put(row) if store is not None else row
            finished += 1
            bar.update()
    except KeyboardInterrupt:
        bar.close()
        what = (f"{plural(len(done), 'finished job')} kept in {store.folder}; the same command "
                "resumes from them" if store is not None else
                f"{plural(finished, 'job')} of {len(todo)} finished, none kept (no output folder)")
        raise Interrupted(f"interrupted: {what}") from None
    finally:
        results.close()  # stops the pool's running jobs now, however this loop ended
    bar.close()
    return [done[job_key(j)] for j in jobs]


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`run_jobs`; its message says what was kept (the command line prints
    it as its one line, exit status 130)."""


def stamp(row: dict[str, Any]) -> dict[str, Any]:
    """What a kept row (or a job) must match to be used again: its code
    (:func:`job_fingerprint` of its recognizer, agent and policy), the library versions and
    the render fingerprint."""
    return {"code": job_fingerprint(row), "versions": library_versions(),
            "render_fingerprint": render_fingerprint()}


def _memo(fn: Callable[[dict[str, Any]], dict[str, Any]]
          ) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """``fn(row)`` computed once per recognizer, agent and policy within one command: hashing
    the sources for each of hundreds of rows would cost seconds."""
    seen: dict[tuple, dict[str, Any]] = {}

    def once(row: dict[str, Any]) -> dict[str, Any]:
        what = (row["recognizer"], row["agent"], row.get("policy"))
        if what not in seen:
            seen[what] = fn(row)
        return seen[what]
    return once


def _run_job(job: dict[str, Any]) -> dict[str, Any]:
    return run_scene(**job)


def track_jobs(scene_seeds: list[int], recognizers: list[str], tasks: Mapping[str, ErrandTask],
               **common: Any) -> list[dict[str, Any]]:
    """:func:`make_jobs` for several tracks (name -> its task): one job per recognizer,
    building and tour (:meth:`~envs.runs.task_spec.ErrandTask.tour_kwargs`), serving every
    track of that tour (:func:`run_scene`'s ``tracks``)."""
    tours: dict[str, dict[str, ErrandTask]] = {}
    for name, task in tasks.items():
        key = json.dumps(task.tour_kwargs(), sort_keys=True)
        tours.setdefault(key, {})[name] = task
    jobs = []
    for tracks in tours.values():
        counts = {t.n_errands for t in tracks.values()}
        if len(counts) > 1:
            raise ValueError(f"tracks of one tour run one count of errands, got {sorted(counts)}")
        jobs += make_jobs(scene_seeds, recognizers, next(iter(tracks.values())), **common,
                          tracks=tracks)
    return jobs


def split_tracks(rows: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """Rows of :func:`track_jobs`' jobs as one list of rows per track (each a plain
    :func:`run_scene` row, with the job's ``key``)."""
    out: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        for name, track_row in row["tracks"].items():
            out.setdefault(name, []).append({**track_row, "key": row.get("key"),
                                             "policy": row.get("policy")})
    return out
