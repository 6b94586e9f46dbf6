"""Seed 001's experiment as its paper ran it: a forward camera, key frames, Tables 2 and 3.

Elgayar et al. mapped COLD-Stockholm with one forward-looking camera and scored the *key frames
of the mapping drive*: a location is labelled with the room most of its key frames were taken
in, and a key frame is correctly matched when its location's label is its own room (Table 2's
matching rate; its Right and Left columns are the stereo pair's two cameras, each mapped on its
own). Table 3 scores the same key frames room by room, one room against the rest: accuracy
``AC``, recall ``TP`` and precision ``P``, averaged over the rooms.

Per building, :func:`run_scene`:

1. drives a scripted tour (:mod:`envs.tasks.tour`) seen by the forward camera; the nested mapper
   (:class:`~placeclust.nested.NestedMapper`, the paper's parameters unless ``params`` say
   otherwise) maps it, and its key frames give Tables 2 and 3;
2. drives the same route again under ``second`` (by default another camera's noise and blur,
   :data:`envs.world.conditions.CONDITIONS`) and relocalizes it on the first drive's map, fixed
   (:meth:`~placeclust.nested.NestedMapper.localize_one`): a key frame is correct when its
   location's label is its room; no location counts as wrong;
3. runs seed 000's online recognizer (library defaults) on the same drives, scored on the
   nested mapper's key frames of each, so the two seeds are compared on the same frames;
4. measures why the locations fall where they do: the share of each key frame's view taken by
   the robot's own room (:mod:`envs.world.visibility`), and the matches with the best location at
   the key frames where the room changes, against the ``min_matches`` that would open a location.

``placeclust seed001 --split test`` prints the table beside the paper's figures.
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.argparsing import ArgumentParser

from ..world.conditions import CONDITIONS
from ..world.layout import room_count


def map_drive(frames: np.ndarray, params: dict[str, Any]) -> tuple[Any, np.ndarray, dict]:
    """Map one drive with the nested mapper; returns it, the locations and per-frame facts.

    The facts are ``key`` (the frame was a key frame) and ``matches`` (a key frame's matches with
    the best location it was compared with, whether it joined it or opened a new one; 0 for the
    other frames), both (T,).
    """
    from placeclust.nested import NestedMapper

    model = NestedMapper(**params)
    labels = np.empty(len(frames), np.int64)
    key, matches = np.zeros(len(frames), bool), np.zeros(len(frames), np.int64)
    for t, frame in enumerate(frames):
        labels[t] = model.learn_predict_one(frame)
        key[t] = model.last_was_keyframe
        matches[t] = model.last_matches if key[t] else 0
    return model, labels, {"key": key, "matches": matches}


def relocalize(model: Any, frames: np.ndarray, rooms: np.ndarray, labels: dict[int, int],
               key: np.ndarray | None = None) -> tuple[dict[str, float], np.ndarray]:
    """The share of a second drive's key frames localized in a location labelled with their room.

    Args:
        model: a mapped recognizer with ``localize_one`` and ``reset_position``.
        frames, rooms: the second drive.
        labels: location -> the room it was labelled with on the first drive.
        key: the frames to score; by default the model's own key frames
            (``last_was_keyframe``), or every frame for a model without them.

    Returns:
        ``rate`` (correct key frames) and ``unknown`` (key frames given no location), and the
        key-frame mask that was scored.
    """
    from placeclust.runner import localize

    model.reset_position()
    result = localize(model, frames)
    pred, key = result.assignments, result.localized if key is None else key
    correct = [labels.get(int(p), -1) == r for p, r in zip(pred[key], rooms[key])]
    return {"rate": float(np.mean(correct)), "unknown": float(np.mean(pred[key] < 0))}, key


def _median(values: np.ndarray) -> float:
    return float(np.median(values)) if len(values) else 0.0


def table2(model: Any, labels: np.ndarray, rooms: np.ndarray, key: np.ndarray,
           label: dict[int, int], kinds: list[str]) -> dict[str, dict[str, int]]:
    """Table 2 of the paper for one drive: per room kind, images, key frames, locations, views
    and correctly matched key frames.

    A location counts for the kind of the room it is labelled with (its key frames' majority).

    Args:
        model: the mapper, for its locations' views.
        labels: its location of every frame.
        rooms: the room of every frame.
        key: the key frames.
        label: location -> the room it stands for (:func:`~placeclust.metrics.place_to_room`
            of the key frames).
        kinds: the kind of every room of the building.
    """
    out: dict[str, dict[str, int]] = {}
    for room in np.unique(rooms).tolist():
        row = out.setdefault(kinds[room], dict.fromkeys(
            ("images", "key_frames", "locations", "views", "correct"), 0))
        mine = rooms == room
        row["images"] += int(mine.sum())
        row["key_frames"] += int((mine & key).sum())
        locs = [loc for loc, r in label.items() if r == room and loc >= 0]
        row["locations"] += len(locs)
        row["views"] += sum(len(model.locations[loc].views) for loc in locs)
        row["correct"] += int(sum(label.get(int(p), -1) == room for p in labels[mine & key]))
    return out


def run_scene(scene_seed: int, n_rooms: int = 6, steps_per_room: int = 150, seed: int = 0,
              second: str = "noisy", params: dict[str, Any] | None = None,
              doors: float | None = None) -> dict[str, Any]:
    """Seed 001's experiment on one building (steps 1-4 of the module docstring); ``doors``:
    the building's doors (``PlaceNav-v0``'s, :mod:`envs.world.doors`; None: open doorways).

    Returns:
        A row: ``map`` (matching rate, AC, TP, P, NMI, locations, views, key frames),
        ``table2`` (per room kind), ``relocalization``, ``online`` (seed 000 on the same key
        frames) and ``why`` (the view's own-room share, matches where the room changes).
    """
    from placeclust.metrics import place_to_room, score
    from placeclust.online import OnlinePlaceClustering
    from placeclust.runner import run

    from ..tasks.tour import record_tour
    from ..world.visibility import own_room_share

    steps = steps_per_room * n_rooms
    world: dict[str, Any] = {"camera": "forward", "progress": False, "doors": doors}
    drive, plan = record_tour(scene_seed, n_rooms, steps, seed, **world)
    again, _ = record_tour(scene_seed, n_rooms, steps, seed, **world, **CONDITIONS[second])
    model, labels, facts = map_drive(drive.frames, params or {})
    key, rooms = facts["key"], drive.room
    scores, label = score(labels[key], rooms[key]), place_to_room(labels[key], rooms[key])
    relocated, again_key = relocalize(model, again.frames, again.room, label)
    online = run("online", drive.frames)
    assert isinstance(online.model, OnlinePlaceClustering)  # what run("online") makes
    online_scores = score(online.assignments[key], rooms[key])
    online_relocated, _ = relocalize(online.model, again.frames, again.room,
                                     place_to_room(online.assignments[key], rooms[key]),
                                     again_key)
    return {
        "scene_seed": scene_seed, "rooms": int(len(np.unique(rooms))),
        "map": {"matching_rate": scores["precision"], "AC": scores["mean_AC"],
                "TP": scores["mean_TP"], "P": scores["mean_P"], "nmi": scores["nmi"],
                "locations": model.n_places, "key_frames": int(key.sum()),
                "views": sum(len(loc.views) for loc in model.locations.values())},
        "table2": table2(model, labels, rooms, key, label, [r.kind for r in plan.rooms]),
        "relocalization": relocated,
        "online": {"matching_rate": online_scores["precision"], "nmi": online_scores["nmi"],
                   "places": online.model.n_places,
                   **{f"relocalization_{k}": v for k, v in online_relocated.items()}},
        "why": why(facts, rooms, own_room_share(plan, drive.pose[key], rooms[key]),
                   model.min_matches),
    }


def why(facts: dict[str, np.ndarray], rooms: np.ndarray, share: np.ndarray, min_matches: int
        ) -> dict[str, float]:
    """What decides where locations fall: the view, and the matches where the room changes.

    Args:
        facts: :func:`map_drive`'s per-frame ``key`` and ``matches``.
        rooms: the room of every frame.
        share: the own-room share of each key frame's view (:mod:`envs.world.visibility`).
        min_matches: the matches below which a key frame opens a location.
    """
    key = facts["key"]
    later, moved = np.flatnonzero(key)[1:], np.diff(rooms[key]) != 0
    at_change, within = later[moved], later[~moved]  # key frames in another room than the last
    matches = facts["matches"]
    return {"looks_elsewhere": float(np.mean(share < 0.5)),
            "matches_at_room_change": _median(matches[at_change]),
            "matches_within_room": _median(matches[within]),
            "new_location_at_room_change":
                float(np.mean(matches[at_change] < min_matches)) if len(at_change) else 0.0}


def summarize(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Each figure's mean over buildings with its 95% bootstrap interval over buildings
    (:func:`placeclust.stats.interval`, every building weighing the same), its worst
    building, and Table 2 summed over the buildings.

    Returns:
        ``{figure: (mean, worst, low, high), ..., "buildings": n, "table2": {...}}``.
    """
    from placeclust.stats import interval

    def spread(values: list[float], worst=min) -> tuple[float, float, float, float]:
        est = interval([[v] for v in values])
        return est.mean, float(worst(values)), est.low, est.high

    def figure(part: str, name: str, worst=min) -> tuple[float, float, float, float]:
        return spread([r[part][name] for r in rows], worst)

    kinds: dict[str, dict[str, int]] = {}
    for r in rows:
        for kind, row in r["table2"].items():
            total = kinds.setdefault(kind, dict.fromkeys(row, 0))
            for k, v in row.items():
                total[k] += v
    return {
        "buildings": len(rows),
        "matching_rate": figure("map", "matching_rate"),
        "locations_per_room": spread([r["map"]["locations"] / r["rooms"] for r in rows], max),
        **{k: figure("map", k) for k in ("AC", "TP", "P", "nmi")},
        "views_per_key_frame": spread(
            [r["map"]["views"] / r["map"]["key_frames"] for r in rows], max),
        "relocalization": figure("relocalization", "rate"),
        "relocalization_unknown": figure("relocalization", "unknown", max),
        "online_matching_rate": figure("online", "matching_rate"),
        "online_places_per_room": spread(
            [r["online"]["places"] / r["rooms"] for r in rows], max),
        "online_relocalization": figure("online", "relocalization_rate"),
        "looks_elsewhere": figure("why", "looks_elsewhere", max),
        "matches_at_room_change": figure("why", "matches_at_room_change"),
        "matches_within_room": figure("why", "matches_within_room"),
        "new_location_at_room_change": figure("why", "new_location_at_room_change"),
        "table2": kinds,
    }


_ROWS = (  # (label, summary key, the paper's figure)
    ("matching rate (key frames of the mapping drive)", "matching_rate", "0.938 / 0.902"),
    ("locations per room (worst: most)", "locations_per_room", "5.0 / 3.7"),
    ("AC, mean over rooms", "AC", "0.968"),
    ("TP (recall), mean over rooms", "TP", "0.77"),
    ("P (precision), mean over rooms", "P", "0.76"),
    ("NMI", "nmi", "-"),
    ("views per key frame (worst: most)", "views_per_key_frame", "0.213 / 0.192"),
    ("second drive relocalized on the map", "relocalization", "-"),
    ("second drive: key frames with no location (worst: most)", "relocalization_unknown", "-"),
    ("seed 000 online, matching rate on the same key frames", "online_matching_rate", "-"),
    ("seed 000 online, places per room (worst: most)", "online_places_per_room", "-"),
    ("seed 000 online, second drive relocalized", "online_relocalization", "-"),
    ("key frames looking mostly into another room (worst: most)", "looks_elsewhere", "-"),
    ("matches with the best location where the room changes (median)",
     "matches_at_room_change", "-"),
    ("matches with the best location within a room (median)", "matches_within_room", "-"),
    ("room changes that opened a location", "new_location_at_room_change", "-"),
)


def format_report(summary: dict[str, Any], scope: str) -> str:
    """The markdown tables: the figures beside the paper's, then Table 2 by room kind."""
    from placeclust.stats import Estimate

    lines = [f"{scope}; mean over buildings with its 95% bootstrap interval over buildings, "
             "and the worst building. The paper: COLD-Stockholm, right / left camera; its "
             "Table 3 means include the Toilet row, which had no key frames.", "",
             "| figure | here: mean [95%] | here: worst | paper |", "|---|---|---|---|"]
    for label, key, paper in _ROWS:
        mean, worst, low, high = summary[key]
        here = Estimate(mean, low, high, summary["buildings"]).text(3)
        lines.append(f"| {label} | {here} | {worst:.3f} | {paper} |")
    lines += ["", "Table 2, summed over the buildings:", "",
              "| room kind | images | key frames | locations | views | correct | rate |",
              "|---|---|---|---|---|---|---|"]
    for kind, row in sorted(summary["table2"].items()):
        rate = row["correct"] / row["key_frames"] if row["key_frames"] else 0.0
        lines.append(f"| {kind} | {row['images']} | {row['key_frames']} | {row['locations']} | "
                     f"{row['views']} | {row['correct']} | {rate:.3f} |")
    return "\n".join(lines)


def _job(job: tuple) -> dict[str, Any]:
    return run_scene(*job)


def main(argv: list[str] | None = None, prog: str = "placeclust seed001"
         ) -> int:
    """``placeclust seed001``: seed 001's experiment over the buildings of a split."""
    from placeclust.runner import check_params, literal_params

    from ..runs.pool import run_all
    from ..world.splits import add_scope_arguments, scope_seeds

    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_scope_arguments(p, n_scenes=4)
    p.add_argument("--rooms", type=room_count, default=6)
    p.add_argument("--steps-per-room", type=int, default=150)
    p.add_argument("--seed", type=int, default=0, help="the tour's start and route")
    p.add_argument("--second", choices=list(CONDITIONS), default="noisy",
                   help="the condition of the second drive of the same route")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="a NestedMapper argument (default: the paper's)")
    p.add_argument("--doors", type=float, metavar="F",
                   help="buildings with doors: F of the doorways with an automatic door, every "
                   "doorway framed and 0.8-1.0 m wide (default: open 1 m doorways)")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--json", type=Path, help="also write every building's row here")
    p.add_argument("--docs", type=Path, help="write the tables into this markdown file")
    p.add_argument("--section", default="seed001", help="the section of --docs")
    args = p.parse_args(argv)
    seeds = scope_seeds(args, p)
    try:
        params = literal_params(args.param)
        check_params("nested", params)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if args.steps_per_room < 1:
        p.error(f"--steps-per-room must be positive, got {args.steps_per_room}")
    if args.doors is not None and not 0 <= args.doors <= 1:
        print(f"error: --doors must be a fraction in [0, 1], got {args.doors}", file=sys.stderr)
        return 2
    jobs = [(s, args.rooms, args.steps_per_room, args.seed, args.second, params, args.doors)
            for s in seeds]
    try:
        rows = sorted((row for _, row in run_all(_job, jobs, args.workers)),
                      key=lambda r: r["scene_seed"])
    except ValueError as e:  # a building the simulator refuses (e.g. --rooms 0)
        print(f"error: {e}", file=sys.stderr)
        return 2
    scope = (f"Split {args.split or 'none'}, scene seeds {', '.join(map(str, seeds))}, "
             f"{args.rooms} rooms, {args.steps_per_room} frames per room, tour seed {args.seed}, "
             f"second drive {args.second}, nested mapper {params or 'with the paper parameters'}"
             + ("" if args.doors is None else f", doors {args.doors}"))
    summary = summarize(rows)
    report = format_report(summary, scope)
    print(report)
    if args.json:
        args.json.write_text(json.dumps({"summary": summary, "buildings": rows}, indent=1))
    if args.docs:
        from placeclust.docs_section import write_section

        write_section(args.docs, args.section, report,
                      shlex.join([*prog.split(), *(argv or sys.argv[1:])]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
