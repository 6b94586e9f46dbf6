"""A recognizer on real image sequences: map a folder, localize queries, score, picture.

What ``placeclust cluster --images DIR [--query DIR]`` does, as functions of the library (no
simulator): :func:`cluster_folder` maps an :class:`~placeclust.datasets.ImageFolder` one frame
at a time and scores it against its labels when it has them; :func:`localize_queries` tracks a
second sequence on that fixed map and ranks places for recall at N; :func:`vpr_bench` does both
on a VPR-Bench dataset and scores it as VPR-Bench does (:func:`placeclust.vprbench.score_queries`);
:func:`save_place_strips` draws a strip of each place's frames, the picture for sequences
without poses.

Examples:
    >>> import tempfile
    >>> from placeclust.datasets import ImageFolder, write_image_folder
    >>> from placeclust.realdata import cluster_folder
    >>> from placeclust.synthetic import places
    >>> frames, truth = places(3)
    >>> folder = tempfile.mkdtemp()
    >>> paths = write_image_folder(folder, frames, labels=[f"room{r}" for r in truth])
    >>> run = cluster_folder("online", ImageFolder(folder), features="orb")
    >>> run.metrics["precision"], run.metrics["n_places"], run.metrics["frames"]
    (1.0, 2, 6)
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from placeclust import protocol, strict_json
from placeclust.datasets import DatasetError, ImageFolder
from placeclust.loops import TRUTH_FILE, LoopClosures, is_loop_closures
from placeclust.metrics import latency_summary
from placeclust.runner import Result, evaluate, localize, run
from placeclust.vprbench import VPRBench, is_vpr_bench, same_place_truth, score_queries

#: the N of recall at N
RECALL_AT = (1, 5, 10)


@dataclass
class SequenceRun:
    """A recognizer's run on a real sequence.

    Attributes:
        result: the mapping run (:func:`placeclust.runner.run`).
        metrics: places, edges and latency; every metric of :func:`placeclust.runner.evaluate`
            over the labelled frames when there are labels; ``query_*`` scores when queries
            were localized.
        query: the query run, when there was one.
        ranked: per query, places best first (empty lists where the recognizer cannot rank).
    """

    result: Result
    metrics: dict[str, float]
    query: Result | None = None
    ranked: list[list[int]] = field(default_factory=list)


def cluster_folder(algo: str, frames: ImageFolder | Sequence[np.ndarray], features: str = "sift",
                   labels: np.ndarray | None = None, progress: bool = False,
                   **params: Any) -> SequenceRun:
    """Map ``frames`` with ``algo`` and score it where labels are known.

    Args:
        algo: a recognizer name or ``package.module:Class`` (:func:`placeclust.runner.run`).
        frames: the sequence; an :class:`ImageFolder` brings its own labels.
        features: the local feature type.
        labels: a label per frame (-1: none), overriding the folder's.
        progress: show a progress bar.
        **params: the recognizer's constructor arguments.

    Returns:
        The run; ``metrics`` holds ``frames``, ``n_places``, ``edges``, latency, and with
        labels ``labelled_frames`` and the clustering metrics over them.
    """
    result = run(algo, frames, features, progress=progress, **params)
    graph = getattr(result.model, "graph", None)
    metrics: dict[str, float] = {
        "frames": len(frames), "n_places": int(len(np.unique(result.assignments[
            result.assignments >= 0]))), "edges": graph.number_of_edges() if graph else 0,
        **latency_summary(result.latencies)}
    truth = labels if labels is not None else getattr(frames, "labels", None)
    if truth is not None:
        known = np.asarray(truth) >= 0
        part = Result(result.assignments[known], result.latencies[known], result.model,
                      result.localized[known])
        metrics = {**metrics, **evaluate(part, np.asarray(truth)[known]),
                   "labelled_frames": int(known.sum())}
    return SequenceRun(result, metrics)


def localize_queries(model: object, query: ImageFolder | Sequence[np.ndarray],
                     rank: int = max(RECALL_AT), alone: bool = False, progress: bool = False
                     ) -> tuple[Result, list[list[int]]]:
    """Localize ``query`` on ``model``'s fixed map, frame by frame, and rank places for each.

    Args:
        model: a mapped recognizer with ``localize_one`` (:class:`placeclust.protocol.Localizer`).
        query: the query frames, in order.
        rank: how many places to rank per query, where ``model`` has ``rank_places``.
        alone: each query on its own (``reset_position`` before each), as VPR-Bench matches
            single images; by default the queries are tracked in order, as a robot would.
        progress: show a progress bar.

    Returns:
        The query run and, per query, its ranked places (empty lists if ``model`` cannot rank).

    Raises:
        ValueError: ``model`` cannot localize on a fixed map.
    """
    if not protocol.can_localize(model):
        raise ValueError(f"{type(model).__name__} cannot localize on a fixed map (it has no "
                         "localize_one), so it cannot take queries")
    protocol.reset_position(model)  # the queries start anywhere on the map
    ranker = getattr(model, "rank_places", None)
    if not alone and ranker is None:
        return localize(model, query, progress), [[] for _ in range(len(query))]
    from placeclust.progress import progress as progress_bar

    places = np.empty(len(query), np.int64)
    lat = np.empty(len(query))
    ranked: list[list[int]] = []
    frames = progress_bar(query, enabled=progress, desc="queries", unit="frame")
    for t, frame in enumerate(frames):
        if alone:
            protocol.reset_position(model)
        start = time.perf_counter()
        places[t] = model.localize_one(frame)  # type: ignore[attr-defined]
        lat[t] = time.perf_counter() - start
        ranked.append(list(ranker(frame, rank)) if ranker is not None else [])
    return Result(protocol.resolve(model, places), lat, model, np.ones(len(query), bool)), ranked


def score_localized(run_: SequenceRun, query: Result, ranked: list[list[int]],
                    ground_truth: Sequence[np.ndarray]) -> dict[str, float]:
    """The query scores of :func:`placeclust.vprbench.score_queries`, each named ``query_*``,
    plus the queries' latency."""
    scores = score_queries(run_.result.assignments, query.assignments, ground_truth,
                           ranked if any(ranked) else None, RECALL_AT)
    return {**{f"query_{k}": v for k, v in scores.items()},
            "query_ms_per_frame": latency_summary(query.latencies)["ms_per_frame"]}


def with_queries(run_: SequenceRun, mapped: ImageFolder, query: ImageFolder,
                 alone: bool = False, progress: bool = False) -> SequenceRun:
    """``run_`` (the map of ``mapped``) with ``query`` localized on it, scored by the labels
    both folders share: a query is right when its place holds a mapped frame of its label.

    Raises:
        ValueError: either folder has no ``labels.csv``, or they share no label.
    """
    for folder in (mapped, query):
        if folder.labels is None:
            raise ValueError(f"{folder.path} has no labels.csv, so the queries cannot be scored")
    assert mapped.labels is not None and query.labels is not None  # checked above
    ids = {name: i for i, name in enumerate(mapped.label_names)}
    if not ids.keys() & set(query.label_names):
        raise ValueError(f"{query.path} and {mapped.path} share no label, so no query can be "
                         "right")
    query_ids = np.array([ids.get(query.label_names[q], -1) if q >= 0 else -1
                          for q in query.labels], np.int64)
    truth = [np.asarray(t, np.int64) for t in same_place_truth(mapped.labels, query_ids)]
    result, ranked = localize_queries(run_.result.model, query, alone=alone, progress=progress)
    run_.metrics.update(score_localized(run_, result, ranked, truth))
    run_.query, run_.ranked = result, ranked
    return run_


def vpr_bench(algo: str, data: VPRBench | LoopClosures, features: str = "sift",
              alone: bool = False, progress: bool = False, **params: Any) -> SequenceRun:
    """Map ``data.ref``, localize ``data.query`` on that map, score as VPR-Bench does.

    Returns:
        The run; its ``metrics`` add ``query_top1``, ``query_recall@N`` (where the recognizer
        ranks places), ``query_chance``, ``query_unknown_rate`` to the map's.
    """
    run_ = cluster_folder(algo, data.ref, features, progress=progress, **params)
    result, ranked = localize_queries(run_.result.model, data.query, alone=alone,
                                      progress=progress)
    run_.metrics.update(score_localized(run_, result, ranked, data.ground_truth))
    run_.query, run_.ranked = result, ranked
    return run_


def dataset_kind(path: str | Path) -> str:
    """``"vpr-bench"`` for a VPR-Bench folder, ``"loop-closures"`` for a drive with a revisit
    matrix (:mod:`placeclust.loops`), ``"images"`` for a labelled image folder.

    Raises:
        DatasetError: none of them (an image folder without ``labels.csv`` cannot be scored).
    """
    if is_vpr_bench(path):
        return "vpr-bench"
    if is_loop_closures(path):
        return "loop-closures"
    folder = ImageFolder(path)
    if folder.labels is None:
        raise DatasetError(f"{path} has no labels.csv: a benchmark data set needs labels, "
                           f"VPR-Bench's layout or a loop-closure matrix ({TRUTH_FILE})")
    return "images"


def open_queries(path: str | Path) -> VPRBench | LoopClosures:
    """A data set that asks VPR-Bench's question (a VPR-Bench or loop-closure folder), open.

    Raises:
        DatasetError: it is neither, or damaged (named).
    """
    return LoopClosures(path) if is_loop_closures(path) else VPRBench(path)


def run_dataset(algo: str, path: str | Path, features: str = "sift", progress: bool = False,
                **params: Any) -> tuple[SequenceRun, np.ndarray]:
    """``algo`` on a data set as ``placeclust bench --dataset`` runs it: a labelled image
    folder is mapped and scored (:func:`cluster_folder`); a VPR-Bench folder is mapped from
    ``ref/`` and its queries localized and scored (:func:`vpr_bench`).

    Returns:
        The run and the per-frame truth its rows store (the folder's labels; for VPR-Bench,
        ``-1`` for every reference, which has no place label).
    """
    if dataset_kind(path) != "images":
        data = open_queries(path)
        return (vpr_bench(algo, data, features, progress=progress, **params),
                np.full(len(data.ref), -1, np.int64))
    folder = ImageFolder(path)
    assert folder.labels is not None  # dataset_kind checked
    return cluster_folder(algo, folder, features, progress=progress, **params), folder.labels


def fingerprint(path: str | Path) -> str:
    """A short hash of a data set folder's file names, sizes and modification times: a kept
    benchmark run of a folder that changed since is not reused."""
    import hashlib

    root = Path(path)
    files = sorted(p for p in root.rglob("*") if p.is_file())
    text = "\n".join(f"{p.relative_to(root)}:{p.stat().st_size}:{p.stat().st_mtime_ns}"
                     for p in files)
    return hashlib.sha1(text.encode()).hexdigest()[:12]


def save_place_strips(frames: Sequence[np.ndarray], places: np.ndarray, path: str | Path,
                      per_place: int = 6, height: int = 72, max_places: int = 40) -> None:
    """One row per place (the ``max_places`` with most frames), ``per_place`` of its frames
    spread over its visits, each ``height`` pixels high, labelled with the place id; written
    with OpenCV. Frames are read again from ``frames`` as needed (a folder is not held)."""
    places = np.asarray(places)
    ids, counts = np.unique(places[places >= 0], return_counts=True)
    rows = []
    for place in ids[np.argsort(-counts, kind="stable")][:max_places]:
        members = np.flatnonzero(places == place)
        picks = members[np.linspace(0, len(members) - 1, min(per_place, len(members))).astype(int)]
        tiles = [_tile(frames[int(t)], height) for t in picks]
        row = cv2.hconcat(tiles)
        cv2.putText(row, f"{place} ({len(members)})", (4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.5,
                    (255, 255, 0), 1, cv2.LINE_AA)
        rows.append(row)
    if not rows:
        return
    width = max(r.shape[1] for r in rows)
    rows = [cv2.copyMakeBorder(r, 0, 2, 0, width - r.shape[1], cv2.BORDER_CONSTANT) for r in rows]
    cv2.imwrite(str(path), cv2.cvtColor(cv2.vconcat(rows), cv2.COLOR_RGB2BGR))


def _tile(frame: np.ndarray, height: int) -> np.ndarray:
    image = np.asarray(frame)
    if image.ndim == 2:
        image = cv2.cvtColor(image, cv2.COLOR_GRAY2RGB)
    width = max(1, round(image.shape[1] * height / image.shape[0]))
    tile = cv2.resize(np.ascontiguousarray(image[..., :3]), (width, height),
                      interpolation=cv2.INTER_AREA)
    return cv2.copyMakeBorder(tile, 0, 0, 0, 2, cv2.BORDER_CONSTANT)


def write_run(out: str | Path, run_: SequenceRun, mapped: Sequence[np.ndarray],
              query: Sequence[np.ndarray] | None, meta: dict[str, object]) -> None:
    """Write a run's report into folder ``out`` (made here, after the run, so a run that
    fails writes nothing): ``metrics.json`` (``meta`` and the metrics), ``assignments.npy``
    (the place of each mapped frame), ``query_assignments.npy`` with queries, and
    ``places.png`` (:func:`save_place_strips` of the mapped frames)."""

    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    np.save(folder / "assignments.npy", run_.result.assignments)
    if run_.query is not None:
        np.save(folder / "query_assignments.npy", run_.query.assignments)
    (folder / "metrics.json").write_text(strict_json.dumps({**meta, **run_.metrics}, indent=2))
    save_place_strips(mapped, run_.result.assignments, folder / "places.png")
