"""``placeclust bench``: the reproducible benchmark matrix.

recognizers × feature types × worlds (scene seed, rooms, condition) × tour seeds. Each *run* is
one recognizer with one feature type on one recorded tour; its configuration, its metrics and the
versions of everything that produced it become one row of ``results.csv``.

How it is run:

- Runs are grouped by tour: a *job* records one tour in the simulator (frames are never stored,
  so the full matrix needs no disk) and runs every recognizer on it that the matrix asks for.
  Jobs go to a local process pool (``spawn``, one process per core by default) or to Ray
  (``executor="ray"``, the optional ``ray`` extra). Both call the same :func:`run_tour_job`, so
  they give the same rows; only the timings differ.
- Every finished run is written at once to ``OUT/runs/<key>.json`` (atomically), where ``key``
  hashes its configuration, with a stamp (:func:`run_stamp`: the code, library versions and
  rendering that made it). Started again with the same matrix, the benchmark skips finished
  runs whose stamp is still this run's: an interrupted benchmark resumes where it stopped, and
  a stale run is run again and counted, never reused silently.
- A condition is a lighting or an appearance change (:data:`envs.world.conditions.CONDITIONS`).
  One written ``"day>night"`` is a cross-condition run:
  a recognizer maps the ``day`` tour, then localizes on the ``night`` tour of the same route
  with the map fixed (``localize_one``, as :meth:`OnlinePlaceClustering.localize_one`), scored
  with the places' day rooms. Every recognizer that can localize takes part (``online``,
  ``nested``, one of your own with ``localize_one``); the others cannot fix their maps, and
  the report names them as skipped (:meth:`Matrix.skipped`).
- ``latency`` rows time the online recognizer as its map grows on synthetic places
  (:func:`placeclust.latency.latency_vs_map_size`), for the latency vs map-size plot.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import json
import os
import sys
from collections.abc import Iterator
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from placeclust import __version__, protocol
from placeclust.features import FEATURES
from placeclust.progress import plural
from placeclust.realdata import dataset_kind, fingerprint
from placeclust.runner import ALGORITHMS, check_params, recognizer_class

from ..runs.pool import run_all
from ..runs.store import RunStore
from ..runs.suite import library_versions, render_fingerprint, sources_fingerprint
from ..world.conditions import CONDITIONS
from .bench_report import write_report


@dataclass(frozen=True)
class RunSpec:
    """One run: a recognizer with a feature type on one tour of one world."""

    algo: str
    features: str
    scene_seed: int
    world_rooms: int
    condition: str
    tour_seed: int
    steps_per_room: int
    width: int = 512
    height: int = 128
    params: tuple[tuple[str, object], ...] = ()
    #: a real data set's folder instead of a simulated tour (the world fields then unused),
    #: and its :func:`~placeclust.realdata.fingerprint`
    dataset: str = ""
    dataset_hash: str = ""
    #: the building's doors (``PlaceNav-v0``'s ``doors``; None: open doorways)
    doors: float | None = None
    #: windows and lamps (``PlaceNav-v0``'s ``local_light``)
    local_light: bool = False

    @property
    def key(self) -> str:
        """A short hash of the configuration and the placeclust version: the run's file name
        and resume key (a new version never reuses an old version's results)."""
        fields = {k: v for k, v in asdict(self).items()  # options off keep the keys they had
                  if k not in ("dataset", "dataset_hash", "doors", "local_light")
                  or v not in ("", None, False)}
        text = json.dumps({**fields, "placeclust": __version__}, sort_keys=True)
        return hashlib.sha1(text.encode()).hexdigest()[:16]

    @property
    def tour(self) -> tuple:
        """What fixes the tour's frames: runs with the same ``tour`` share one recording (or
        one data set)."""
        return (self.scene_seed, self.world_rooms, self.condition, self.tour_seed,
                self.steps_per_room, self.width, self.height, self.dataset, self.doors,
                self.local_light)


@dataclass(frozen=True)
class Matrix:
    """The benchmark's axes; :meth:`runs` is their product."""

    algos: tuple[str, ...] = ALGORITHMS
    features: tuple[str, ...] = ("sift", "orb")
    scenes: tuple[int, ...] = (0, 1, 2)
    rooms: tuple[int, ...] = (4,)
    conditions: tuple[str, ...] = ("day", "day>night")
    tour_seeds: tuple[int, ...] = (0,)
    steps_per_room: int = 100
    latency_features: tuple[str, ...] = ("sift", "orb")
    latency_sizes: tuple[int, ...] = (10, 50, 100)
    width: int = 512
    height: int = 128
    #: constructor arguments given to every recognizer of the matrix, as ``(name, value)``
    params: tuple[tuple[str, object], ...] = ()
    #: real data sets beside the simulated tours: labelled image folders, VPR-Bench folders
    datasets: tuple[str, ...] = ()
    #: the simulated buildings' doors (:mod:`envs.world.doors`; None: open doorways)
    doors: float | None = None
    #: the simulated buildings' windows and lamps (:mod:`envs.world.local_light`)
    local_light: bool = False

    def __post_init__(self) -> None:
        # each algo is a name of ALGORITHMS or package.module:Class (check_params loads it,
        # naming one it cannot) whose recognizer takes every param of the matrix
        for algo in self.algos:
            # n_clusters="rooms" or "online" is made a number per tour (placeclust.runner.matched_k)
            check_params(algo, {k: 1 if k == "n_clusters" and v in ("rooms", "online") else v
                                for k, v in self.params})
        _check_choices("features", self.features + self.latency_features, FEATURES)
        for condition in self.conditions:
            _check_choices("conditions", tuple(condition.split(">")), tuple(CONDITIONS))
            if condition.count(">") > 1:
                raise ValueError(f"condition {condition!r}: write one change, as 'day>night'")
        for name in ("scenes", "rooms", "tour_seeds", "latency_sizes"):
            if not all(isinstance(v, int) and v >= 0 for v in getattr(self, name)):
                raise ValueError(f"{name} must be non-negative integers, got {getattr(self, name)}")
        if min(self.rooms, default=1) < 1 or self.steps_per_room < 1:
            raise ValueError("rooms and steps_per_room must be at least 1")
        if min(self.latency_sizes, default=2) < 2:
            raise ValueError("latency_sizes must be at least 2 places")
        _ = self._datasets  # a folder it cannot score is named now, before any run
        if self.doors is not None and not 0 <= self.doors <= 1:
            raise ValueError(f"doors must be a fraction in [0, 1], got {self.doors}")

    @property
    def latency_sweeps(self) -> tuple[str, ...]:
        """The feature types swept for the latency plot (none without map sizes)."""
        return self.latency_features if self.latency_sizes else ()

    def runs(self) -> list[RunSpec]:
        """Every run of the matrix, in table order (cross-condition runs only for the
        recognizers that can localize, :func:`can_localize`)."""
        out = []
        for condition in self.conditions:
            for algo in self.algos:
                if ">" in condition and not can_localize(algo):
                    continue
                for feat in self.features:
                    for scene in self.scenes:
                        for n in self.rooms:
                            for seed in self.tour_seeds:
                                out.append(RunSpec(algo, feat, scene, n, condition, seed,
                                                   self.steps_per_room, self.width, self.height,
                                                   self.params, doors=self.doors,
                                                   local_light=self.local_light))
        return out + self._dataset_runs()

    @functools.cached_property
    def _datasets(self) -> tuple[tuple[str, str, str], ...]:
        """``(path, condition, fingerprint)`` of each data set, read once: checking a folder
        opens every image's header."""
        return tuple((path, DATASET_CONDITION[dataset_kind(path)], fingerprint(path))
                     for path in self.datasets)

    def _dataset_runs(self) -> list[RunSpec]:
        """A run per recognizer, feature type and data set: ``images`` for a labelled folder,
        ``ref>query`` for VPR-Bench (recognizers that can localize only)."""
        out = []
        for path, condition, digest in self._datasets:
            for algo in self.algos:
                if ">" in condition and not can_localize(algo):
                    continue
                out += [RunSpec(algo, feat, -1, 0, condition, 0, 0, 0, 0, self.params, path,
                                digest) for feat in self.features]
        return out

    def skipped(self) -> list[str]:
        """The cross-condition runs the matrix leaves out, each as ``algo on condition``:
        recognizers that cannot localize on a fixed map."""
        conditions = [*self.conditions, *(condition for _, condition, _ in self._datasets)]
        return [f"{algo} on {condition}" for condition in dict.fromkeys(conditions)
                if ">" in condition for algo in self.algos if not can_localize(algo)]


#: the condition a data set's runs are reported under, by :func:`dataset_kind`
DATASET_CONDITION = {"images": "images", "vpr-bench": "ref>query", "loop-closures": "ref>query"}


def can_localize(algo: str) -> bool:
    """Whether ``algo``'s recognizer can localize on a fixed map
    (:class:`placeclust.protocol.Localizer`), the mode a cross-condition run needs."""
    return protocol.can_localize(recognizer_class(algo))


def _check_choices(name: str, values: tuple[str, ...], allowed: tuple[str, ...]) -> None:
    bad = [v for v in values if v not in allowed]
    if bad:
        raise ValueError(f"unknown {name} {bad}; choose from {list(allowed)}")


#: the matrix's default axes by size (``placeclust bench --size``)
SIZES: dict[str, Matrix] = {
    # minutes on 2 cores: every recognizer, two feature types, three 4-room worlds, day>night
    "quick": Matrix(),
    # every axis: hours on 2 cores, resumable
    "full": Matrix(features=("sift", "kaze", "orb"), scenes=(0, 1, 2), rooms=(4, 8, 12),
                   conditions=("day", "night", "day>night", "day>moved", "day>noisy"),
                   tour_seeds=(0, 1),
                   steps_per_room=250, latency_features=("sift", "kaze", "orb"),
                   latency_sizes=(10, 50, 100, 250, 500)),
}


# -- the stamp of finished runs ---------------------------------------------------------------

@functools.cache
def run_stamp(algo: str) -> dict[str, Any]:
    """What a kept run of ``algo`` must match to be used again: the library and simulator's
    code (:func:`~envs.runs.suite.code_fingerprint`), this module, the source of a
    ``package.module:Class`` recognizer, the library versions and the render fingerprint."""
    sources = [Path(__file__)]
    if ":" in algo:
        sources.append(Path(inspect.getfile(recognizer_class(algo))))
    return {"code": sources_fingerprint(*sources), "versions": library_versions(),
            "render_fingerprint": render_fingerprint()}


LATENCY_ALGO = "online"  # the recognizer the latency sweeps time


def row_stamp(row: dict[str, Any]) -> dict[str, Any]:
    """The stamp a bench row gets and must keep (:class:`~envs.runs.store.RunStore`):
    :func:`run_stamp` of its recognizer (a latency sweep's: :data:`LATENCY_ALGO`)."""
    return run_stamp(row.get("algo", LATENCY_ALGO))


# -- jobs ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Job:
    """One unit of work: ``"tour"`` (the runs that share one tour, ``specs``) or
    ``"latency"`` (a latency sweep of ``features`` over map ``sizes``)."""

    kind: str
    specs: tuple[RunSpec, ...] = ()
    features: str = ""
    sizes: tuple[int, ...] = ()


def plan_jobs(matrix: Matrix, store: RunStore) -> tuple[list[Job], int]:
    """Jobs for the runs not yet in ``store``; also returns how many runs were already done."""
    todo: dict[tuple, list[RunSpec]] = {}
    done = 0
    for spec in matrix.runs():
        if store.get(spec.key) is not None:
            done += 1
        else:
            todo.setdefault(spec.tour, []).append(spec)
    jobs = [Job("tour", tuple(specs)) for specs in todo.values()]
    for feat in matrix.latency_sweeps:
        if store.get(latency_key(feat, matrix.latency_sizes)) is None:
            jobs.append(Job("latency", features=feat, sizes=tuple(matrix.latency_sizes)))
        else:
            done += 1
    return jobs, done


def latency_key(features: str, sizes: tuple[int, ...]) -> str:
    """The store key of one latency sweep."""
    text = json.dumps({"latency": features, "sizes": sorted(sizes), "placeclust": __version__})
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def run_job(job: Job, store_dir: str | None = None) -> list[dict]:
    """Run one job (in a worker process or a Ray task) and return its rows.

    With ``store_dir`` each run is also recorded there as soon as it finishes, so an interrupt
    loses at most the run in progress; Ray tasks on other machines pass None and the driver
    records their rows.
    """
    store = RunStore(Path(store_dir), row_stamp) if store_dir else None
    rows = []
    for row in (_latency_rows(job) if job.kind == "latency" else _tour_rows(job.specs)):
        if store is not None:
            store.put(row)
        rows.append(row)
    return rows


def _latency_rows(job: Job) -> Iterator[dict]:
    from placeclust.latency import latency_vs_map_size

    points = latency_vs_map_size(job.features, list(job.sizes))
    yield {"key": latency_key(job.features, job.sizes), "kind": "latency",
           "features": job.features, "points": points, **library_versions()}


def _tour_rows(specs: tuple[RunSpec, ...]) -> Iterator[dict]:
    from placeclust.runner import cross_condition, evaluate, matched_k, run

    first = specs[0]
    if first.dataset:
        yield from _dataset_rows(specs)
        return
    mapped, cross = first.condition.partition(">")[::2]
    frames, room = _record(replace(first, condition=mapped))
    if cross:
        test_frames, test_room = _record(replace(first, condition=cross))
    online_places: dict[str, int] = {}  # per feature type, for n_clusters="online"
    for spec in specs:
        if cross:
            pred, metrics = cross_condition(spec.algo, frames, room, test_frames, test_room,
                                            spec.features, **dict(spec.params))
            truth = test_room
        else:
            params = matched_k(dict(spec.params), spec.features, frames, room, online_places)
            result = run(spec.algo, frames, spec.features, **params)
            pred, truth, metrics = result.assignments, room, evaluate(result, room)
        # params as JSON gives them back from the store, so every executor returns equal rows
        yield {"key": spec.key, "kind": "run", **asdict(spec), **metrics, **library_versions(),
               "params": [list(p) for p in spec.params], "assignments": pred, "truth": truth}


def _dataset_rows(specs: tuple[RunSpec, ...]) -> Iterator[dict]:
    """The runs of one data set (:func:`placeclust.realdata.run_dataset`)."""
    from placeclust.realdata import run_dataset

    for spec in specs:
        params: dict[str, Any] = dict(spec.params)  # checked against the recognizer by Matrix
        run_, truth = run_dataset(spec.algo, spec.dataset, spec.features, **params)
        yield {"key": spec.key, "kind": "run", **asdict(spec), **run_.metrics,
               **library_versions(), "params": [list(p) for p in spec.params],
               "assignments": run_.result.assignments, "truth": truth}


def _record(spec: RunSpec) -> tuple[np.ndarray, np.ndarray]:
    from ..tasks.tour import record_tour

    steps = spec.steps_per_room * spec.world_rooms
    tour, _ = record_tour(spec.scene_seed, spec.world_rooms, steps, spec.tour_seed, spec.width,
                          spec.height, progress=False, doors=spec.doors,
                          local_light=spec.local_light,
                          **CONDITIONS[spec.condition])
    return tour.frames, tour.room


# -- executing jobs -----------------------------------------------------------------------------

def execute(jobs: list[Job], store: RunStore, workers: int = 0, executor: str = "process",
            ray_address: str | None = None, progress: bool = True) -> Iterator[dict]:
    """Run ``jobs`` in parallel and yield their rows as jobs finish (recorded in ``store``).

    Args:
        workers: processes (or Ray CPUs of a local Ray instance); 0 means one per core.
        executor: ``"process"`` (a local ``spawn`` pool, the default) or ``"ray"``.
        ray_address: with ``"ray"``, the cluster to join (None starts a local instance).
    """
    from placeclust.progress import progress as progress_bar

    if executor not in ("process", "ray"):
        raise ValueError(f"unknown executor {executor!r}; choose 'process' or 'ray'")
    workers = workers or os.cpu_count() or 1
    # the biggest tours first, so the last job to finish is a short one
    jobs = sorted(jobs, key=lambda j: -sum(s.world_rooms for s in j.specs))
    bar = progress_bar(total=len(jobs), enabled=progress, desc="bench", unit="job")
    # local workers record their own runs; Ray's may not share this disk, so the driver does
    on_ray = executor == "ray"
    run = functools.partial(run_job, store_dir=None if on_ray else str(store.folder))
    try:
        for _, rows in run_all(run, jobs, workers, executor, ray_address):
            for row in rows if on_ray else ():
                store.put(row)
            bar.update()
            yield from rows
    finally:
        bar.close()


def run_bench(matrix: Matrix, out: str | os.PathLike, workers: int = 0, executor: str = "process",
              ray_address: str | None = None, progress: bool = True) -> list[dict]:
    """Run the benchmark ``matrix`` into folder ``out`` (resuming) and write its report.

    Writes ``config.json`` (the matrix and versions), ``runs/`` (one JSON per finished run),
    ``results.csv``, ``results.md`` (also printed), ``precision.png`` and ``latency.png``.
    Returns the rows of ``results.csv``.
    """

    folder = Path(out)
    store = RunStore(folder / "runs", row_stamp)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "config.json").write_text(json.dumps(
        {"matrix": asdict(matrix), "versions": library_versions()}, indent=1))
    jobs, done = plan_jobs(matrix, store)
    if progress:
        print(f"{plural(done, 'run')} already done in {folder}; {plural(len(jobs), 'job')} to go")
    if store.stale:
        print(f"{len(store.stale)} kept runs in {store.folder} are stale (code, libraries or "
              "rendering changed since) and run again", file=sys.stderr)
    for _ in execute(jobs, store, workers, executor, ray_address, progress):
        pass
    rows = [store.get(spec.key) for spec in matrix.runs()]
    latency = [store.get(latency_key(f, matrix.latency_sizes)) for f in matrix.latency_sweeps]
    return write_report([r for r in rows if r], [r for r in latency if r], folder,
                        ["key", *RunSpec.__dataclass_fields__], progress, matrix.skipped())
