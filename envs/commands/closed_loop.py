"""Errands in buildings never seen: one guided tour per building, then errands to named rooms.

Each building of a split gets one episode of ``PlaceNav-GuidedTour-v1``: the tour builds the
recognizer's map from nothing, then the agent runs ``goals`` errands on it. Nothing is trained
on the building and nothing is retrained when the recognizer changes, so the success rate
ranks recognizers by what their maps are worth to an agent.

    placeclust errands --split test --rooms 6 --recognizer panorama \\
        --goals-per-scene 5 --seed 0 --json runs/unseen.json
    placeclust errands --split val --recognizer mypackage.module:MyRecognizer \\
        [--preset panorama] [--param threshold=0.8]       # a recognizer of your own

A recognizer of your own is checked before any building is toured: a path that does not load,
a class that is not an online recognizer or fails :func:`placeclust.checks.check_recognizer`
on the given parameters stops the command with one line of error (exit status 2).

Examples:
    >>> from envs.commands.closed_loop import run_scene
    >>> row = run_scene(0, n_rooms=3, recognizer="oracle", goals=2, seed=0,
    ...                 tour_steps_per_room=40)
    >>> row["success_rate"], row["precision"]
    (1.0, 1.0)
"""

from __future__ import annotations

import argparse
import hashlib
import inspect
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from placeclust.argparsing import ArgumentParser
from placeclust.checks import check_recognizer
from placeclust.presets import PRESETS
from placeclust.progress import plural
from placeclust.progress import progress as progress_bar
from placeclust.runner import preset_params, recognizer_class

from ..agents.errands import ERRAND_AGENTS, POLICY, check_agent, check_goals, run_scene
from ..agents.learned import config_path
from ..tasks.errand_draws import ERRAND_STARTS
from ..tasks.recognizers import (
    RECOGNIZERS,
    is_own,
    localizes,
    make_recognizer,
)
from ..world.layout import room_count
from ..world.scene import LAYOUTS
from ..world.splits import add_scope_arguments, scope_seeds
from .pool import run_all
from .results import interval_text, policy_name, summarize, write_results
from .store import RunStore
from .suite import (
    TRACKS,
    library_versions,
    provenance,
    render_fingerprint,
    sources_fingerprint,
    track_task,
)

#: the slow recognizers first, so the last job to finish is a short one
COST = {"panorama": 0, "nested": 1, "panorama-orb": 2, "random": 3, "none": 4, "oracle": 5}
def check_closed_loop_recognizer(name: str, params: dict[str, Any] | None = None) -> None:
    """Check a recognizer before any building is toured, so a bad one costs no minutes.

    A name of :data:`~envs.tasks.recognizers.RECOGNIZERS` is built once with ``params``; a
    ``package.module:Class`` must load, be online and pass
    :func:`placeclust.checks.check_recognizer` with ``params``.

    Raises:
        ValueError: what is wrong, in one line.
    """
    make_recognizer(name, 6, params=params)
    if is_own(name):
        try:
            check_recognizer(recognizer_class(name), params)
        except AssertionError as exc:
            raise ValueError(f"{name} is not a recognizer placeclust can run: {exc}") from exc


def job_fingerprint(job: dict[str, Any]) -> str:
    """A hash of all the code that makes a job's result: the library, the world, the tasks
    and the agents (:func:`~envs.commands.suite.code_fingerprint`), this module, for a
    ``package.module:Class`` recognizer its module's source, and for ``ppo`` the policy
    file and its ``config.yml``. A kept row is reused only under the same fingerprint,
    library versions and render fingerprint (:func:`run_jobs`): an edit anywhere a result
    could come from, within one version of placeclust, runs the job again."""
    sources = [Path(__file__)]
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
_KEY_FIELDS = frozenset({"scene_seed", "n_rooms", "recognizer", "agent", "goals", "seed",
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
            f"-rooms{job['n_rooms']}-goals{job['goals']}-seed{job['seed']}")


def make_jobs(scene_seeds: list[int], recognizers: list[str], n_rooms: int, agent: str,
              goals: int, seed: int, policy: Path | None = None,
              params: dict[str, dict[str, Any]] | None = None,
              **task: Any) -> list[dict[str, Any]]:
    """One :func:`run_scene` job per recognizer and building; ``params`` maps a recognizer to
    its constructor arguments, ``task`` is more ``PlaceNav-GuidedTour-v1`` arguments."""
    extra = {"policy": str(policy)} if policy else {}
    params = params or {}
    return [{"scene_seed": s, "n_rooms": n_rooms, "recognizer": r, "agent": agent,
             "goals": goals, "seed": seed, **extra, **task,
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
                  key=lambda j: COST.get(j["recognizer"], 0))
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


#: the guided tour's length per room when a command is not told otherwise (the env's default)
TOUR_STEPS_PER_ROOM = 150


def tour_task(steps_per_room: int, errand_start: str = "continue", layout: str = "grid",
              doors: float | None = None, local_light: bool = False) -> dict[str, Any]:
    """The ``PlaceNav-GuidedTour-v1`` arguments a job adds for a tour length, errand start,
    layout, doors and local light: none for the defaults, so default jobs keep their plain
    file names."""
    task: dict[str, Any] = {}
    if steps_per_room != TOUR_STEPS_PER_ROOM:
        task["tour_steps_per_room"] = steps_per_room
    if errand_start != "continue":
        task["errand_start"] = errand_start
    if layout != "grid":
        task["layout"] = layout
    if doors is not None:
        task["doors"] = doors
    if local_light:
        task["local_light"] = True
    return task


def add_task_arguments(p: argparse.ArgumentParser, many_tracks: bool = False) -> None:
    """The options that say which errands run: ``--tour-steps-per-room``, ``--errand-start``,
    ``--layout``, a named ``--track`` (:mod:`envs.commands.suite`; several if
    ``many_tracks``, into ``args.tracks``) and ``--localize-only``."""
    p.add_argument("--tour-steps-per-room", type=int, default=TOUR_STEPS_PER_ROOM,
                   help="the guided tour's length per room (PlaceNav-GuidedTour-v1's)")
    p.add_argument("--errand-start", choices=ERRAND_STARTS, default="continue",
                   help="where each errand starts: where the last ended, or carried to a "
                   "random room (PlaceNav-GuidedTour-v1's errand_start)")
    p.add_argument("--layout", choices=LAYOUTS, default="grid",
                   help="the buildings: rooms of random sizes, or identical offices along a "
                   "corridor (--rooms counts the corridor)")
    p.add_argument("--doors", type=float, metavar="F", help="buildings with doors: F of the "
                   "doorways with an automatic door, every doorway framed and 0.8-1.0 m wide "
                   "(envs.world.doors; default: open 1 m doorways)")
    p.add_argument("--local-light", action="store_true", help="buildings with windows and "
                   "lamps, the light baked where it falls (envs.world.local_light)")
    if many_tracks:
        p.add_argument("--track", dest="tracks", nargs="+", choices=list(TRACKS),
                       metavar="TRACK", help="named tracks' errands (envs.commands.suite): "
                       f"{', '.join(TRACKS)}; tracks of one tour share it")
    else:
        p.add_argument("--track", choices=list(TRACKS), help="a named track's errands "
                       "(envs.commands.suite): changed-night, carried, corridor...")
    p.add_argument("--goal-kind", choices=("room", "image"), default="room", help="errands to a "
                   "named room, or to a picture of a spot (PlaceNav-ImageGoal-v0; the spot "
                   "agent)")
    p.add_argument("--success-radius", type=float, default=1.0, metavar="M", help="an image "
                   "goal is reached by stopping within M metres of walking of it (default 1)")
    p.add_argument("--localize-only", action="store_true", help="the map is the tour's and "
                   "stays fixed during the errands (localize_one); recognizers without it are "
                   "skipped")


def task_from_args(args: argparse.Namespace, track: str | None = None) -> dict[str, Any]:
    """The ``PlaceNav-GuidedTour-v1`` arguments of :func:`add_task_arguments`' options, for
    ``track`` (default: ``args.track``, if any).

    Raises:
        ValueError: an option that contradicts the track's own setting of it.
    """
    if args.doors is not None and not 0 <= args.doors <= 1:
        raise ValueError(f"--doors must be a fraction in [0, 1], got {args.doors}")
    task = tour_task(args.tour_steps_per_room, args.errand_start, args.layout, args.doors,
                     args.local_light)
    track = track or getattr(args, "track", None)
    if track:
        for key, value in track_task(track).items():
            if task.get(key, value) != value:
                raise ValueError(f"--track {track} sets {key}={value!r}; leave out the "
                                 f"option that sets it to {task[key]!r}")
            task[key] = value
    if args.localize_only:
        task["errand_learn"] = False
    if getattr(args, "goal_kind", "room") == "image":  # PlaceNav-ImageGoal-v0's errands
        if not args.success_radius > 0:
            raise ValueError(f"--success-radius must be positive metres, got "
                             f"{args.success_radius}")
        task.update(goal_kind="image", success_radius=args.success_radius)
    return task


#: the guided tour's arguments a track may set: tracks that agree on them share one tour
TOUR_KEYS = frozenset({"layout", "tour_steps_per_room", "doors", "local_light"})


def track_jobs(scene_seeds: list[int], recognizers: list[str], tasks: dict[str, dict[str, Any]],
               **common: Any) -> list[dict[str, Any]]:
    """:func:`make_jobs` for several tracks (name -> its full task): one job per recognizer,
    building and tour, serving every track of that tour (:func:`run_scene`'s ``tracks``)."""
    tours: dict[str, tuple[dict[str, Any], dict[str, dict[str, Any]]]] = {}
    for name, task in tasks.items():
        tour = {k: v for k, v in task.items() if k in TOUR_KEYS}
        key = json.dumps(tour, sort_keys=True)
        tours.setdefault(key, (tour, {}))[1][name] = {k: v for k, v in task.items()
                                                      if k not in TOUR_KEYS}
    return [job for tour, tracks in tours.values()
            for job in make_jobs(scene_seeds, recognizers, **common, **tour, tracks=tracks)]


def split_tracks(rows: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """Rows of :func:`track_jobs`' jobs as one list of rows per track (each a plain
    :func:`run_scene` row, with the job's ``key``)."""
    out: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        for name, track_row in row["tracks"].items():
            out.setdefault(name, []).append({**track_row, "key": row.get("key"),
                                             "policy": row.get("policy")})
    return out


def run_settings(args: argparse.Namespace, seeds: list[int], task: dict[str, Any],
                 track: str | None = None) -> dict[str, Any]:
    """What a results file's ``settings`` say a run measured (``placeclust compare`` pairs
    only runs whose settings agree), from a command's ``split``, ``rooms``,
    ``goals_per_scene``, ``seed`` and ``agent``."""
    return {"split": args.split, "scene_seeds": seeds, "rooms": args.rooms,
            "goals": args.goals_per_scene, "seed": args.seed, "agent": args.agent,
            "policy": None if getattr(args, "policy", None) is None else str(args.policy),
            "task": task, **({"track": track} if track else {})}


def add_recognizer_arguments(p: argparse.ArgumentParser, many: bool) -> None:
    """``--recognizer`` (``--recognizers`` if ``many``), ``--preset`` and ``--param``."""
    names = ", ".join(RECOGNIZERS)
    if many:
        p.add_argument("--recognizers", nargs="+", default=list(RECOGNIZERS), metavar="NAME",
                       help=f"{names} (default: all), or package.module:Class")
    else:
        p.add_argument("--recognizer", required=True, metavar="NAME",
                       help=f"one of {names}, or package.module:Class for an online "
                       "recognizer of your own (placeclust.checks)")
    p.add_argument("--preset", choices=sorted(PRESETS),
                   help="constructor arguments of a named configuration, for a "
                   "package.module:Class recognizer (e.g. placeclust.online:OnlinePlaceClustering)")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="a constructor argument of a package.module:Class recognizer "
                   "(repeatable; over the preset's), e.g. threshold=0.8 or features=orb")


def recognizer_params(names: list[str], preset: str | None, param: list[str] | None
                      ) -> dict[str, dict[str, Any]]:
    """The constructor arguments of each recognizer named, checked before any job runs:
    ``--preset`` and ``--param`` go to the ``package.module:Class`` ones.

    Raises:
        ValueError: a recognizer that does not load or check, or options with no recognizer
            of your own to take them.
    """
    given = preset_params(preset, param)
    own = [n for n in names if is_own(n)]
    if given and not own:
        raise ValueError("--preset and --param are for a package.module:Class recognizer; "
                         f"{names} are built in (their configurations are fixed)")
    params = {n: dict(given) if is_own(n) else {} for n in names}
    for name in names:
        check_closed_loop_recognizer(name, params[name])
    return params


def main(argv: list[str] | None = None, prog: str = "placeclust errands") -> int:
    """``placeclust errands ...``: one recognizer, one agent, a split; the exit status."""
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--task", choices=("unseen",), default="unseen",
                   help=argparse.SUPPRESS)  # for python -m train.evaluate --task unseen
    add_scope_arguments(p, n_scenes=8)
    p.add_argument("--rooms", type=room_count, default=6)
    add_recognizer_arguments(p, many=False)
    p.add_argument("--agent", choices=ERRAND_AGENTS, default="planner")
    p.add_argument("--policy", type=Path, help="the ppo agent's policy (default: shipped)")
    p.add_argument("--goals-per-scene", type=int, default=5)
    add_task_arguments(p)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", type=Path, help="also write the scores here")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--out", type=Path, help="keep each building's result here and resume")
    args = p.parse_args(argv)
    seeds = scope_seeds(args, p)
    if args.goals_per_scene < 1 or args.tour_steps_per_room < 1:
        p.error("--goals-per-scene and --tour-steps-per-room must be positive, got "
                f"{args.goals_per_scene} and {args.tour_steps_per_room}")
    try:
        check_agent(args.agent, args.policy)
        params = recognizer_params([args.recognizer], args.preset, args.param)
        task = task_from_args(args)
        check_goals(args.agent, task)
        if task.get("errand_learn") is False and not localizes(args.recognizer,
                                                                params[args.recognizer]):
            raise ValueError(f"{args.recognizer} cannot localize on a fixed map (no "
                             "localize_one); leave out --localize-only")
        jobs = make_jobs(seeds, [args.recognizer], args.rooms, args.agent,
                         args.goals_per_scene, args.seed, args.policy, params, **task)
        rows = run_jobs(jobs, args.out, args.workers)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    settings = run_settings(args, seeds, task, args.track)
    if args.json:
        doc = write_results(args.json, rows, [args.recognizer], settings, provenance(None))
        (summary,) = doc["summaries"]
    else:
        summary = summarize(rows)
    print(" ".join(f"{k}={v:.3f}" for k, v in summary.items() if isinstance(v, float)))
    print(" ".join(f"{k}={interval_text(summary, k, 3)}" for k in ("success_rate", "spl")))
    return 0
