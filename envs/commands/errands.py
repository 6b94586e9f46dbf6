"""Errands in buildings never seen: one guided tour per building, then errands to named rooms.

Each building of a split gets one episode of ``PlaceNav-GuidedTour-v1``: the tour builds the
recognizer's map from nothing, then the agent runs ``--errands`` errands on it. Nothing is trained
on the building and nothing is retrained when the recognizer changes, so the success rate
ranks recognizers by what their maps are worth to an agent.

    placeclust errands --split test --rooms 6 --recognizer panorama \\
        --errands 5 --seed 0 --json runs/unseen.json
    placeclust errands --split val --recognizer mypackage.module:MyRecognizer \\
        [--preset panorama] [--param threshold=0.8]       # a recognizer of your own

A recognizer of your own is checked before any building is toured: a path that does not load,
a class that is not an online recognizer or fails :func:`placeclust.checks.check_recognizer`
on the given parameters stops the command with one line of error (exit status 2).

Examples:
    >>> from envs.runs.tour_errands import run_scene
    >>> row = run_scene(0, n_rooms=3, recognizer="oracle", n_errands=2, seed=0,
    ...                 tour_steps_per_room=40)
    >>> row["success_rate"], row["precision"]
    (1.0, 1.0)
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from placeclust.argparsing import ArgumentParser
from placeclust.checks import check_recognizer
from placeclust.presets import PRESETS
from placeclust.runner import preset_params, recognizer_class

from ..runs.jobs import make_jobs, run_jobs
from ..runs.results import interval_text, summarize, write_results
from ..runs.suite import TRACKS, provenance, track_task
from ..runs.task_spec import GOAL_KINDS, ErrandTask
from ..runs.tour_errands import ERRAND_AGENTS, check_agent, check_goals
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


class _OldName(argparse.Action):
    """Stores the value; an option's old spelling (its second) also prints one line that
    names the new one (placeclust 0.19.0 renamed ``--goals-per-scene`` ``--errands``)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        if option_string == self.option_strings[-1]:
            print(f"note: {option_string} is now {self.option_strings[0]}", file=sys.stderr)
        setattr(namespace, self.dest, values)


def add_task_arguments(p: argparse.ArgumentParser, many_tracks: bool = False) -> None:
    """The options that say which errands run (:class:`~envs.runs.task_spec.ErrandTask`):
    ``--errands``, ``--tour-steps-per-room``, ``--errand-start``, ``--layout``, ``--doors``,
    ``--local-light``, a named ``--track`` (:mod:`envs.runs.suite`; several if
    ``many_tracks``, into ``args.tracks``), ``--goal-kind``, ``--success-radius`` and
    ``--localize-only``."""
    default = ErrandTask()
    p.add_argument("--errands", "--goals-per-scene", dest="errands", type=int,
                   action=_OldName, default=default.n_errands, metavar="N",
                   help="errands after each building's tour (the env's n_errands; "
                   "--goals-per-scene is its old name)")
    p.add_argument("--tour-steps-per-room", type=int, default=default.tour_steps_per_room,
                   help="the guided tour's length per room (PlaceNav-GuidedTour-v1's)")
    p.add_argument("--errand-start", choices=ERRAND_STARTS, default=default.errand_start,
                   help="where each errand starts: where the last ended, or carried to a "
                   "random room (PlaceNav-GuidedTour-v1's errand_start)")
    p.add_argument("--layout", choices=LAYOUTS, default=default.layout,
                   help="the buildings: rooms of random sizes, or identical offices along a "
                   "corridor (--rooms counts the corridor)")
    p.add_argument("--doors", type=float, metavar="F", help="buildings with doors: F of the "
                   "doorways with an automatic door, every doorway framed and 0.8-1.0 m wide "
                   "(envs.world.doors; default: open 1 m doorways)")
    p.add_argument("--local-light", action="store_true", help="buildings with windows and "
                   "lamps, the light baked where it falls (envs.world.local_light)")
    if many_tracks:
        p.add_argument("--track", dest="tracks", nargs="+", choices=list(TRACKS),
                       metavar="TRACK", help="named tracks' errands (envs.runs.suite): "
                       f"{', '.join(TRACKS)}; tracks of one tour share it")
    else:
        p.add_argument("--track", choices=list(TRACKS), help="a named track's errands "
                       "(envs.runs.suite): changed-night, carried, corridor...")
    p.add_argument("--goal-kind", choices=GOAL_KINDS, default=default.goal_kind,
                   help="errands to a named room, or to a picture of a spot "
                   "(PlaceNav-ImageGoal-v0; the spot agent)")
    p.add_argument("--success-radius", type=float, default=default.success_radius,
                   metavar="M", help="an image goal is reached by stopping within M metres of "
                   "walking of it (default 1)")
    p.add_argument("--localize-only", action="store_true", help="the map is the tour's and "
                   "stays fixed during the errands (localize_one); recognizers without it are "
                   "skipped")


def task_from_args(args: argparse.Namespace, track: str | None = None) -> ErrandTask:
    """The errands :func:`add_task_arguments`' options ask for, for ``track`` (default:
    ``args.track``, if any).

    Raises:
        ValueError: a bad value, or an option that contradicts the track's own setting of it.
    """
    radius = args.success_radius if args.goal_kind == "image" else ErrandTask().success_radius
    if args.goal_kind == "image" and not radius > 0:  # the option's name, not the field's
        raise ValueError(f"--success-radius must be positive metres, got {radius}")
    if args.doors is not None and not 0 <= args.doors <= 1:
        raise ValueError(f"--doors must be a fraction in [0, 1], got {args.doors}")
    if args.errands < 1 or args.tour_steps_per_room < 1:
        raise ValueError("--errands and --tour-steps-per-room must be positive, got "
                         f"{args.errands} and {args.tour_steps_per_room}")
    task = ErrandTask(n_errands=args.errands, tour_steps_per_room=args.tour_steps_per_room,
                      errand_start=args.errand_start, layout=args.layout, doors=args.doors,
                      local_light=args.local_light, goal_kind=args.goal_kind,
                      success_radius=radius)
    track = track or getattr(args, "track", None)
    if track:
        task = task.with_settings(track_task(track), f"--track {track}")
    if args.localize_only:
        task = replace(task, errand_learn=False)
    return task


def run_settings(args: argparse.Namespace, seeds: list[int], task: ErrandTask,
                 track: str | None = None) -> dict[str, Any]:
    """What a results file's ``settings`` say a run measured (``placeclust compare`` pairs
    only runs whose settings agree): the command's ``split``, ``rooms``, ``seed``, ``agent``
    and ``policy``, the buildings, and the task's errand count and other env arguments."""
    kwargs = task.kwargs()
    return {"split": args.split, "scene_seeds": seeds, "rooms": args.rooms,
            "n_errands": kwargs.pop("n_errands"), "seed": args.seed, "agent": args.agent,
            "policy": None if getattr(args, "policy", None) is None else str(args.policy),
            "task": kwargs, **({"track": track} if track else {})}


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
    add_scope_arguments(p, n_scenes=8)
    p.add_argument("--rooms", type=room_count, default=6)
    add_recognizer_arguments(p, many=False)
    p.add_argument("--agent", choices=ERRAND_AGENTS, default="planner")
    p.add_argument("--policy", type=Path, help="the ppo agent's policy (default: shipped)")
    add_task_arguments(p)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", type=Path, help="also write the scores here")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--out", type=Path, help="keep each building's result here and resume")
    args = p.parse_args(argv)
    seeds = scope_seeds(args, p)
    try:
        check_agent(args.agent, args.policy)
        params = recognizer_params([args.recognizer], args.preset, args.param)
        task = task_from_args(args)
        check_goals(args.agent, [task])
        if not task.errand_learn and not localizes(args.recognizer, params[args.recognizer]):
            raise ValueError(f"{args.recognizer} cannot localize on a fixed map (no "
                             "localize_one); leave out --localize-only")
        jobs = make_jobs(seeds, [args.recognizer], task, args.rooms, args.agent, args.seed,
                         args.policy, params)
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
