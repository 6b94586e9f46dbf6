"""Runs any recognizer over a recorded sequence and scores it: the core of the CLI and demo."""

from __future__ import annotations

import inspect
import time
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from placeclust.baselines import KMeansPlaces, WPGMAPlaces
from placeclust.kunion import KAdjacentUnion
from placeclust.metrics import latency_summary, score
from placeclust.nested import NestedMapper
from placeclust.online import OnlinePlaceClustering

ALGORITHMS = ("online", "nested", "kunion", "wpgma", "kmeans")
ONLINE = {"online": OnlinePlaceClustering, "nested": NestedMapper}
OFFLINE = {"kunion": KAdjacentUnion, "wpgma": WPGMAPlaces, "kmeans": KMeansPlaces}


@dataclass
class Result:
    """Assignments (place per frame), per-frame latencies (s) and the fitted model."""

    assignments: np.ndarray
    latencies: np.ndarray
    model: object
    localized: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))


def recognizer_class(algo: str) -> type:
    """The class of ``algo`` (one of :data:`ALGORITHMS`), or a ``ValueError`` naming them."""
    cls = {**ONLINE, **OFFLINE}.get(algo)
    if cls is None:
        raise ValueError(f"unknown algorithm {algo!r}; choose one of {ALGORITHMS}")
    return cls


def check_params(algo: str, names: Iterable[str]) -> None:
    """A ``ValueError`` naming the first of ``names`` that ``algo``'s constructor does not take
    (``features`` is not a parameter: every recognizer is given it separately)."""
    known = [n for n in inspect.signature(recognizer_class(algo).__init__).parameters
             if n not in ("self", "features")]
    for name in names:
        if name not in known:
            raise ValueError(f"{algo} has no parameter {name!r}; it takes {known}")


def make(algo: str, features: str = "sift", **params: object) -> object:
    """A fresh recognizer ``algo`` (one of :data:`ALGORITHMS`) using ``features``."""
    return recognizer_class(algo)(features=features, **params)


def run(algo: str, frames: np.ndarray, features: str = "sift", progress: bool = False,
        **params: object) -> Result:
    """Run ``algo`` over ``frames`` (T, H, W[, C]); online ones one frame at a time."""
    model = make(algo, features, **params)
    if algo in OFFLINE:
        start = time.perf_counter()
        labels = np.asarray(model.fit_predict(frames), np.int64)
        per_frame = (time.perf_counter() - start) / max(1, len(frames))
        return Result(labels, np.full(len(frames), per_frame), model, np.ones(len(frames), bool))
    return _one_at_a_time(model, model.learn_predict_one, frames, progress, algo)


def localize(model: object, frames: np.ndarray, progress: bool = False) -> Result:
    """Track ``frames`` on ``model``'s fixed map (``localize_one``: no place is learnt)."""
    return _one_at_a_time(model, model.localize_one, frames, progress, "localize")


def _one_at_a_time(model: object, step, frames: np.ndarray, progress: bool, desc: str
                   ) -> Result:
    from tqdm import tqdm

    labels = np.empty(len(frames), np.int64)
    lat = np.empty(len(frames))
    localized = np.ones(len(frames), bool)
    for t, frame in enumerate(tqdm(frames, disable=not progress, desc=desc, unit="frame")):
        start = time.perf_counter()
        labels[t] = step(frame)
        lat[t] = time.perf_counter() - start
        localized[t] = getattr(model, "last_was_keyframe", True)
    return Result(labels, lat, model, localized)


def evaluate(result: Result, rooms: np.ndarray) -> dict[str, float]:
    """Metrics of :mod:`placeclust.metrics` plus latency for one run."""
    return {**score(result.assignments, rooms, result.localized),
            **latency_summary(result.latencies)}
