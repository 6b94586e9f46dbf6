"""The simulator asked a real data set's question through the data set's camera: the
measuring half of ``placeclust like`` (:mod:`envs.commands.like` writes the report).

For a VPR-Bench data set (``ref/``, ``query/``, ground truth) each simulated building is made
into one like it (:func:`simulated_vpr_bench`): the forward camera at the data set's image
size, colour and field of view (:func:`placeclust.camera.camera_of`), with the sensor effects
asked for (:class:`envs.world.sensor.Sensor`); a reference drive and a query drive, the two
halves of one tour (a tour visits every room, then revisits them along other paths: the second
half traverses the first half's places again, as ``rtabmap-loop``'s second lap does), under one
light or, with ``query_conditions``, the query drive under others (the same route driven again
under another light, after furniture moved, or both: a real data set's second traversal is
another day's);
and VPR-Bench's ground truth from positions, each query's references being those within
``radius`` metres in its room that look the same way (heading within half the field of view:
a forward camera turned round sees another place). Every recognizer × feature configuration
then maps ``ref/`` and localizes ``query/`` on both sides through the same code
(:func:`placeclust.realdata.vpr_bench`), scored by top-1 above chance
(:func:`placeclust.vprbench.above_chance`): top-1 at the level of places is right by chance
as often as a map has few places (a map of one place is always right), so the raw figure
would rank a coarse map above a fine one that knows more.

For a labelled image folder the question is the folder's: one drive (the tour's first half)
clustered by every configuration and scored by NMI against its rooms, as the folder is against
its labels (:func:`placeclust.realdata.cluster_folder`).

Every building's figures are kept in ``OUT/sim/scene_S.json`` and the data set's in
``OUT/real.json``, stamped with the code (this module's and the simulator's) and the
settings: the same command resumes, and a change of either runs again.
"""

from __future__ import annotations

import functools
import json
import math
import tempfile
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from placeclust.atomic import write_atomic
from placeclust.camera import CameraSpec
from placeclust.datasets import ImageFolder
from placeclust.imagestats import image_stats, revisit_stats
from placeclust.loops import LoopClosures
from placeclust.realdata import cluster_folder, dataset_kind, fingerprint, open_queries, vpr_bench
from placeclust.strict_json import dumps
from placeclust.vprbench import VPRBench, above_chance, nearby_truth, query_chances

from ..agents.lap import drive_lap
from ..tasks.photo_textures import Photo, retextured_env
from ..tasks.tour import Tour, drive_tour
from ..world.conditions import CONDITIONS
from ..world.sensor import Sensor
from .pool import run_all
from .suite import sources_fingerprint

#: the recognizers that can take queries on a fixed map (``localize_one``): VPR-Bench's
#: question needs them; a labelled folder's (clustering) takes any of ``ALGORITHMS``
ALGOS = ("online", "nested")
#: the two questions and the score each ranks by: a VPR-Bench data set's (map ``ref/``,
#: localize ``query/``; top-1 at the level of places corrected for chance, since a map of few
#: places is right by chance more often) and a labelled image folder's (cluster it, NMI
#: against its labels)
QUESTIONS = {"vpr-bench": "top-1 above chance", "images": "NMI"}
#: every feature type both recognizers run with
FEATURES = ("sift", "kaze", "surf", "orb", "akaze")
#: how a VPR-Bench question's query drive is made: ``tour`` the tour's second half (its rooms
#: again, along other paths), ``lap`` the reference drive's own path driven again a little to
#: one side (:func:`envs.agents.lap.drive_lap`), as a real data set's second traversal is
QUERY_ROUTES = ("tour", "lap")


@dataclass(frozen=True)
class Matched:
    """One matched comparison's settings (every building runs the same); ``question`` is one
    of :data:`QUESTIONS`, the data set's (:func:`question_of`)."""

    camera: CameraSpec
    sensor: Sensor
    configs: tuple[tuple[str, str], ...]
    question: str = "vpr-bench"
    rooms: int = 4
    steps_per_room: int = 100
    stride: int = 1
    radius: float = 1.0
    doors: float | None = None
    params: tuple[tuple[str, Any], ...] = ()
    #: the query drive's conditions (names of :data:`~envs.world.conditions.CONDITIONS`, at
    #: most one lighting), applied together; none: the reference drive's
    query_conditions: tuple[str, ...] = ()
    #: surfaces with photographic statistics (:func:`envs.tasks.photo_textures.retexture`, a
    #: realism lever); none: the procedural textures as ``PlaceNav-v0`` draws them
    photo: Photo | None = None
    #: one of :data:`QUERY_ROUTES`
    query_route: str = "tour"

    def stamp(self) -> str:
        """What a kept figure must match to be reused: these settings and the code."""
        settings = json.dumps(asdict(self), sort_keys=True, default=str)
        return f"{sources_fingerprint(__file__)}:{settings}"


def question_of(dataset: str | Path) -> str:
    """The question a data set asks, one of :data:`QUESTIONS`: a VPR-Bench folder's or a
    loop-closure drive's (map, then localize queries) or a labelled folder's (cluster).

    Raises:
        DatasetError: the folder is none of them (named).
    """
    return "images" if dataset_kind(dataset) == "images" else "vpr-bench"


def condition_kwargs(names: tuple[str, ...]) -> dict[str, Any]:
    """``PlaceNav-v0``'s arguments for the conditions ``names`` together (night and moved
    furniture: ``("night", "moved")``).

    Raises:
        ValueError: an unknown name, or two that set the same thing (two lightings).
    """
    out: dict[str, Any] = {}
    for name in names:
        if name not in CONDITIONS:
            raise ValueError(f"unknown condition {name!r}; choose from {sorted(CONDITIONS)}")
        clash = sorted(set(out) & set(CONDITIONS[name]) - {"changes_seed"})
        if clash:
            raise ValueError(f"conditions {', '.join(names)} both set {', '.join(clash)}; "
                             "give one of each kind (a lighting, an appearance change)")
        out.update(CONDITIONS[name])
    return out


def config_name(algo: str, features: str) -> str:
    return f"{algo} ({features})"


def record(scene: int, m: Matched) -> tuple[Tour, Tour]:
    """The reference and query drives of ``scene`` through a forward camera like the data
    set's, every ``stride``-th frame kept. The reference is the first ``rooms *
    steps_per_room`` frames of a tour. With ``m.query_route`` ``tour`` the query is the same
    tour's next as many: a tour visits every room first and then revisits them along other
    paths, so its second half traverses the places of its first again; with ``lap`` it is the
    reference's path driven again (:func:`envs.agents.lap.drive_lap`). With
    ``m.query_conditions`` the query drive is driven under them (the tour rendered whole once
    more: the route up to its second half must be driven)."""
    sensor = replace(m.sensor, grey=m.sensor.grey or not m.camera.colour)
    half = m.rooms * m.steps_per_room

    def env(**condition: Any) -> gym.Env:
        return retextured_env(scene, m.rooms, m.photo, sensor, camera="forward",
                              image_width=m.camera.width, image_height=m.camera.height,
                              image_fov=m.camera.fov, doors=m.doors, **condition)

    def drive(steps: int, **condition: Any) -> Tour:
        made = env(**condition)
        try:
            return drive_tour(made, steps, seed=0)
        finally:
            made.close()

    def part(tour: Tour, start: int, n: int = half) -> Tour:
        keep = slice(start * m.stride, (start + n) * m.stride, m.stride)
        return Tour(tour.frames[keep], tour.room[keep], tour.pose[keep], tour.room_names)

    condition = condition_kwargs(m.query_conditions)
    if m.query_route == "lap":
        tour = drive(half * m.stride)
        made = env(**condition)
        try:  # at most twice the reference's steps: a lap that stalls still ends
            lap = drive_lap(made, tour.pose, 2 * half * m.stride)
        finally:
            made.close()
        return part(tour, 0), part(lap, 0, math.ceil(len(lap.pose) / m.stride))
    tour = drive(2 * half * m.stride)
    query = drive(2 * half * m.stride, **condition) if m.query_conditions else tour
    return part(tour, 0), part(query, half)


def matched_truth(ref: Tour, query: Tour, radius: float, fov: float) -> list[list[int]]:
    """Each query's references: within ``radius`` m in its room, heading within ``fov / 2``."""
    near = nearby_truth(ref.pose, query.pose, radius, ref.room, query.room)
    half = math.radians(fov) / 2
    return [[r for r in refs
             if abs(math.remainder(ref.pose[r, 2] - query.pose[q, 2], 2 * math.pi)) <= half]
            for q, refs in enumerate(near)]


def simulated_vpr_bench(scene: int, m: Matched, folder: Path
                        ) -> tuple[int, dict[str, float], dict[str, float]]:
    """Write building ``scene`` as a VPR-Bench data set like the real one to ``folder``;
    returns the number of queries that have a reference, the reference drive's image
    statistics (its rooms as places) and the queries' matches with their references
    (:func:`placeclust.imagestats.revisit_stats`)."""
    from placeclust.vprbench import write_vpr_bench

    ref, query = record(scene, m)
    truth = matched_truth(ref, query, m.radius, m.camera.fov)
    write_vpr_bench(folder, ref.frames, query.frames, truth)
    return (sum(1 for t in truth if t),
            image_stats(ref.frames, _places(ref.room), features="sift"),
            revisit_stats(ref.frames, query.frames, truth, features="sift"))


def _places(labels: np.ndarray | None) -> np.ndarray | None:
    """``labels`` where they name two places or more (image statistics' across-place pairs
    need two), else None."""
    if labels is None or len(np.unique(labels[labels >= 0])) < 2:
        return None
    return labels


def query_hits(run_: Any, data: VPRBench | LoopClosures) -> list[float]:
    """Per query with ground truth: 1 when its place holds one of its references (top-1)."""
    ref_places, query_places = run_.result.assignments, run_.query.assignments
    return [float(int(query_places[q]) in set(ref_places[truth].tolist()))
            for q, truth in enumerate(data.ground_truth) if len(truth)]


def score_configs(data: VPRBench | LoopClosures, m: Matched) -> dict[str, dict[str, Any]]:
    """Every configuration on one VPR-Bench question: per query its hit and its chance
    (:func:`placeclust.vprbench.query_chances`); the ``score`` ranked is top-1 above chance
    (:func:`placeclust.vprbench.above_chance`), with the raw ``top1`` and ``chance`` kept."""
    out = {}
    for algo, features in m.configs:
        run_ = vpr_bench(algo, data, features, **dict(m.params))
        hits = query_hits(run_, data)
        chances = query_chances(run_.result.assignments, data.ground_truth).tolist()
        out[config_name(algo, features)] = {
            "hits": hits, "chances": chances, "score": above_chance(hits, chances),
            "top1": float(np.mean(hits)) if hits else math.nan,
            "chance": float(np.mean(chances)) if chances else math.nan,
            "n_places": run_.metrics.get("n_places", 0)}
    return out


def cluster_configs(frames: Any, labels: np.ndarray, m: Matched, keep: bool = False
                    ) -> dict[str, dict[str, Any]]:
    """Every configuration clustering one labelled sequence: NMI against the labels (frames
    labelled -1 left out), precision, places; with ``keep`` each frame's place too."""
    out = {}
    for algo, features in m.configs:
        run_ = cluster_folder(algo, frames, features, labels=labels, **dict(m.params))
        out[config_name(algo, features)] = {
            "score": run_.metrics.get("nmi", math.nan),
            "precision": run_.metrics.get("precision", math.nan),
            "n_places": run_.metrics.get("n_places", 0),
            **({"places": run_.result.assignments.tolist()} if keep else {})}
    return out


def building_job(scene: int, m: Matched, out: str) -> dict[str, Any]:
    """One simulated building: record, write, score (a picklable pool job)."""
    path = Path(out) / "sim" / f"scene_{scene}.json"
    if path.exists():
        kept = json.loads(path.read_text())
        if kept.get("stamp") == m.stamp():
            return kept
    if m.question == "images":  # one drive, clustered and scored against its rooms
        ref, _ = record(scene, m)
        result = {"stamp": m.stamp(), "scene": scene, "queries": len(ref.frames),
                  "configs": cluster_configs(ref.frames, ref.room, m),
                  "image_stats": image_stats(ref.frames, _places(ref.room), features="sift")}
    else:
        with tempfile.TemporaryDirectory() as tmp:
            n_queries, stats, revisit = simulated_vpr_bench(scene, m, Path(tmp))
            result = {"stamp": m.stamp(), "scene": scene, "queries": n_queries,
                      "configs": score_configs(VPRBench(tmp), m), "image_stats": stats,
                      "revisit": revisit}
    path.parent.mkdir(parents=True, exist_ok=True)
    _write(path, result)
    return result


def real_side(dataset: str, m: Matched, out: Path) -> dict[str, Any]:
    """The data set's own figures, kept in ``OUT/real.json``: per configuration its score,
    and what the report resamples (each query's hit, or each frame's place and label)."""
    path = out / "real.json"
    # the simulator's textures and query route do not change the data set's figures: kept
    stamp = f"{replace(m, photo=None, query_route='tour').stamp()}:{fingerprint(dataset)}"
    if path.exists():
        kept = json.loads(path.read_text())
        if kept.get("stamp") == stamp:
            return kept
    if m.question == "images":
        folder = ImageFolder(dataset)
        assert folder.labels is not None  # dataset_kind checked
        result = {"stamp": stamp, "labels": folder.labels.tolist(),
                  "configs": cluster_configs(folder, folder.labels, m, keep=True),
                  "image_stats": image_stats(folder, _places(folder.labels), features="sift")}
    else:
        data = open_queries(dataset)
        result = {"stamp": stamp, "configs": score_configs(data, m),
                  "image_stats": image_stats(data.ref, features="sift"),
                  "revisit": revisit_stats(data.ref, data.query, data.ground_truth,
                                           features="sift")}
    out.mkdir(parents=True, exist_ok=True)
    _write(path, result)
    return result


def _write(path: Path, result: dict[str, Any]) -> None:
    text = dumps(result).encode()
    write_atomic(path, lambda f: f.write(text))


def run_matched(dataset: str, scenes: list[int], m: Matched, out: Path, workers: int = 1,
                executor: str = "process", address: str | None = None
                ) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The real side and every simulated building (resuming kept ones).

    Raises:
        ValueError: ``m.question`` is not the data set's kind, or no scene is given.
    """
    asks = question_of(dataset)  # reads the folder: once
    if asks != m.question:
        raise ValueError(f"{dataset} asks the {asks} question, not {m.question}'s")
    if not scenes:
        raise ValueError("no simulated buildings: give --scenes or --split")
    real = real_side(dataset, m, out)
    job = functools.partial(building_job, m=m, out=str(out))
    sims = [result for _, result in run_all(job, list(scenes), workers, executor, address)]
    return real, sorted(sims, key=lambda r: r["scene"])
