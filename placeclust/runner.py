"""Runs any recognizer over a recorded sequence and scores it: the core of the CLI and demo.

Online recognizers (:data:`ONLINE`) see one frame at a time and are timed per frame; offline
ones (:data:`OFFLINE`) see the whole sequence, and their total time is spread over the frames.
"""

from __future__ import annotations

import ast
import inspect
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from placeclust.baselines import KMeansPlaces, WPGMAPlaces
from placeclust.kunion import KAdjacentUnion
from placeclust.metrics import latency_summary, score
from placeclust.nested import NestedMapper
from placeclust.online import OnlinePlaceClustering
from placeclust.presets import PRESETS
from placeclust.protocol import is_offline, is_online, reset_position, resolve
from placeclust.stream import StreamPlaces

ALGORITHMS = ("online", "nested", "kunion", "wpgma", "kmeans", "stream")
ONLINE = {"online": OnlinePlaceClustering, "nested": NestedMapper, "stream": StreamPlaces}
OFFLINE = {"kunion": KAdjacentUnion, "wpgma": WPGMAPlaces, "kmeans": KMeansPlaces}


@dataclass
class Result:
    """The outcome of :func:`run` or :func:`localize`.

    Attributes:
        assignments: place per frame, (T,) int64, -1 for unknown. A recognizer that merges
            places (``resolve``) has its ids given as its final map holds them.
        latencies: seconds per frame, (T,).
        model: the recognizer, with its map.
        localized: (T,) bool, the frames the method localized itself (the nested mapper's key
            frames; every frame for the others).
    """

    assignments: np.ndarray
    latencies: np.ndarray
    model: object
    localized: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))


def recognizer_class(algo: str) -> type:
    """The class of ``algo``: one of :data:`ALGORITHMS`, or ``package.module:Class``.

    A ``package.module:Class`` path loads a recognizer of your own: an online one with
    ``learn_predict_one``, ``predict_one``, ``n_places`` and ``graph``, or an offline one with
    ``fit_predict`` (:mod:`placeclust.checks` checks the rest). An online recognizer that merges
    places may also have ``resolve(ids)``, the place each id it returned belongs to now;
    :func:`run` scores its final map through it. Like ``uvicorn``, the loader looks in the
    working folder too.

    Raises:
        ValueError: an unknown name, a path that cannot be imported, or a class that follows
            neither protocol; the message says which.

    Examples:
        >>> from placeclust.runner import recognizer_class
        >>> recognizer_class("kunion").__name__
        'KAdjacentUnion'
        >>> recognizer_class("placeclust.nested:NestedMapper").__name__
        'NestedMapper'
    """
    cls = {**ONLINE, **OFFLINE}.get(algo)
    if cls is None and ":" in algo:
        cls = _load(algo)
    if cls is None:
        raise ValueError(f"unknown algorithm {algo!r}; choose one of {ALGORITHMS} or give "
                         "package.module:Class")
    return cls


def _load(path: str) -> type:
    import importlib
    import os
    import sys

    module_name, _, name = path.partition(":")
    if os.getcwd() not in sys.path:
        sys.path.append(os.getcwd())
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:  # any import failure is the user's path or module: say so
        raise ValueError(f"cannot import {module_name!r} for {path!r}: {exc}") from exc
    cls = getattr(module, name, None)
    if not isinstance(cls, type):
        raise ValueError(f"{module_name!r} has no class {name!r}")
    if not (is_online(cls) or is_offline(cls)):
        raise ValueError(f"{path} is not a recognizer: it has neither learn_predict_one "
                         "(online) nor fit_predict (offline)")
    return cls


def check_params(algo: str, names: Iterable[str] | Mapping[str, object]) -> None:
    """Check parameter names, and values where given, against ``algo``'s constructor before
    running anything.

    ``features`` is not a parameter here: every recognizer is given it separately. A value
    given as text (``--param threshold=abc`` parses to the string ``"abc"``) where the
    constructor's default is a number or a flag, or where its annotation admits no string, is
    refused: it would reach the constructor and fail deep inside it.

    Raises:
        ValueError: naming the first of ``names`` that ``algo``'s constructor does not take, or
            the first value of the wrong type.

    Examples:
        >>> from placeclust.runner import check_params
        >>> check_params("online", ["t_new_cluster", "scale"])
        >>> check_params("kmeans", ["t_new_cluster"])  # doctest: +ELLIPSIS
        Traceback (most recent call last):
            ...
        ValueError: kmeans has no parameter 't_new_cluster'; it takes ['n_clusters', ...]
    """
    signature = inspect.signature(recognizer_class(algo)).parameters
    known = [n for n in signature if n != "features"]
    for name in names:
        if name not in known:
            raise ValueError(f"{algo} has no parameter {name!r}; it takes {known}")
    if isinstance(names, Mapping):
        for name, value in names.items():
            if name != "features" and not _fits(signature[name], value):
                default = signature[name].default
                wanted = (type(default).__name__ if default not in (None, inspect.Parameter.empty)
                          else str(signature[name].annotation))
                raise ValueError(f"{algo}'s {name} must be {wanted}, got {value!r}")


def _fits(parameter: inspect.Parameter, value: object) -> bool:
    """Whether ``value`` may go to ``parameter``: only text is doubted, as what a
    ``NAME=VALUE`` that did not parse leaves behind."""
    if not isinstance(value, str):
        return True
    default = parameter.default
    if default not in (None, inspect.Parameter.empty):
        return isinstance(default, str)
    annotation = str(parameter.annotation)
    return parameter.annotation is inspect.Parameter.empty or "str" in annotation \
        or "Any" in annotation or "object" in annotation


def literal_params(items: list[str] | None) -> dict[str, object]:
    """``NAME=VALUE`` strings as a dict of constructor arguments.

    Values are Python literals (``0.9``, ``None``, ``True``) or else plain strings (``clahe``).
    Raises ``ValueError`` naming a malformed item.
    """
    params: dict[str, object] = {}
    for item in items or []:
        name, sep, text = item.partition("=")
        if not sep or not name:
            raise ValueError(f"--param takes NAME=VALUE, got {item!r}")
        try:
            params[name] = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            params[name] = text
    return params


def preset_params(preset: str | None, items: list[str] | None) -> dict[str, object]:
    """The arguments of recognizer preset ``preset`` (:data:`~placeclust.presets.PRESETS`, or
    none), with ``NAME=VALUE`` ``items`` (:func:`literal_params`) overriding them."""
    return {**(PRESETS[preset] if preset else {}), **literal_params(items)}


def make(algo: str, features: str = "sift", **params: object) -> object:
    """A fresh recognizer ``algo`` using ``features``.

    Args:
        algo: one of :data:`ALGORITHMS` or ``package.module:Class``.
        features: local feature type (:data:`~placeclust.features.FEATURES`), given to
            recognizers whose constructor takes ``features``.
        **params: other constructor arguments.
    """
    cls = recognizer_class(algo)
    if "features" in inspect.signature(cls).parameters:
        params = {"features": features, **params}
    return cls(**params)


def run(algo: str, frames: np.ndarray | Sequence[np.ndarray], features: str = "sift",
        progress: bool = False, **params: object) -> Result:
    """Run ``algo`` over ``frames``; online ones one frame at a time (``learn_predict_one``).

    Args:
        algo: one of :data:`ALGORITHMS` or ``package.module:Class``.
        frames: (T, H, W[, C]) images, or a sequence of them read as needed (an
            :class:`~placeclust.datasets.ImageFolder`: online recognizers hold one frame at a
            time; offline ones are given the sequence whole).
        features: local feature type.
        progress: show a progress bar.
        **params: other constructor arguments of the recognizer.

    Returns:
        The place per frame, the latencies and the fitted model.

    Examples:
        >>> from placeclust import runner
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(3)
        >>> result = runner.run("online", frames, features="orb")
        >>> result.assignments.tolist(), result.latencies.shape
        ([0, 0, 0, 1, 1, 1], (6,))
        >>> metrics = runner.evaluate(result, rooms=truth)
        >>> metrics["precision"], metrics["n_places"], round(metrics["nmi"], 3)
        (1.0, 2, 1.0)

        The learnt map can then track another sequence without changing:

        >>> runner.localize(result.model, frames[::-1]).assignments.tolist()
        [1, 1, 1, 0, 0, 0]
    """
    model = make(algo, features, **params)
    if is_offline(type(model)):
        if not isinstance(frames, np.ndarray):  # a lazy sequence: offline methods see it whole
            frames = np.stack(list(frames))
        start = time.perf_counter()
        labels = np.asarray(_method(model, "fit_predict")(frames), np.int64)
        per_frame = (time.perf_counter() - start) / max(1, len(frames))
        return Result(labels, np.full(len(frames), per_frame), model, np.ones(len(frames), bool))
    return _one_at_a_time(model, _method(model, "learn_predict_one"), frames, progress, algo)


def localize(model: object, frames: np.ndarray | Sequence[np.ndarray], progress: bool = False
             ) -> Result:
    """Track ``frames`` on ``model``'s fixed map (``localize_one``: no place is learnt).

    Args:
        model: a recognizer with ``localize_one``, such as
            :class:`~placeclust.online.OnlinePlaceClustering`.
        frames: (T, H, W[, C]) images.
        progress: show a progress bar.
    """
    return _one_at_a_time(model, _method(model, "localize_one"), frames, progress, "localize")


def _method(model: object, name: str) -> Callable[..., Any]:
    """``model``'s method ``name``. Recognizers are duck-typed (any class with the protocol's
    methods, see :func:`recognizer_class`), so the runner looks their methods up by name; a
    missing one raises ``AttributeError``."""
    method: Callable[..., Any] = getattr(model, name)
    return method


def _one_at_a_time(model: object, step: Callable[[np.ndarray], int],
                   frames: np.ndarray | Sequence[np.ndarray], progress: bool, desc: str
                   ) -> Result:
    from placeclust.progress import progress as progress_bar

    labels = np.empty(len(frames), np.int64)
    lat = np.empty(len(frames))
    localized = np.ones(len(frames), bool)
    for t, frame in enumerate(progress_bar(frames, enabled=progress, desc=desc, unit="frame")):
        start = time.perf_counter()
        labels[t] = step(frame)
        lat[t] = time.perf_counter() - start
        localized[t] = getattr(model, "last_was_keyframe", True)
    labels = resolve(model, labels)  # ids of places merged since, as the final map holds them
    return Result(labels, lat, model, localized)


def evaluate(result: Result, rooms: np.ndarray) -> dict[str, float]:
    """Metrics of :mod:`placeclust.metrics` plus latency for one run.

    Args:
        result: a :func:`run` or :func:`localize` result.
        rooms: ground-truth room per frame.

    Returns:
        :func:`~placeclust.metrics.score` (``matching_rate`` over ``result.localized``) and
        :func:`~placeclust.metrics.latency_summary` in one dict.

    Examples:
        >>> import numpy as np
        >>> from placeclust.runner import Result, evaluate
        >>> result = Result(assignments=np.array([0, 0, 1, 1]), model=None,
        ...                 latencies=np.array([0.01, 0.02, 0.02, 0.03]),
        ...                 localized=np.ones(4, bool))
        >>> metrics = evaluate(result, rooms=np.array([4, 4, 7, 7]))
        >>> metrics["precision"], metrics["n_rooms"], metrics["ms_per_frame"]
        (1.0, 2, 20.0)
    """
    return {**score(result.assignments, rooms, result.localized),
            **latency_summary(result.latencies)}


def matched_k(params: dict, features: str, frames: np.ndarray, room: np.ndarray,
              online_places: dict[str, int]) -> dict:
    """``params`` with ``n_clusters="rooms"`` or ``"online"`` made a number for this tour.

    Purity rewards more clusters, so the offline methods are compared with the online one at
    matched numbers of places: the rooms the tour visited, or the places the online
    recognizer (with its defaults and the same features) opened on it; ``online_places``
    keeps that number per feature type across calls on the same tour.
    """
    k = params.get("n_clusters")
    if k == "rooms":
        params["n_clusters"] = int(len(np.unique(room[room >= 0])))
    elif k == "online":
        if features not in online_places:
            model = run("online", frames, features).model
            assert isinstance(model, OnlinePlaceClustering)  # what run("online") makes
            online_places[features] = model.n_places
        params["n_clusters"] = online_places[features]
    return params


def cross_condition(algo: str, frames: np.ndarray, room: np.ndarray, test_frames: np.ndarray,
                    test_room: np.ndarray, features: str = "sift", **params: Any
                    ) -> tuple[np.ndarray, dict[str, float]]:
    """Map ``frames`` with ``algo``, then localize ``test_frames`` (the same route under
    another condition) on the fixed map (:func:`localize`).

    Returns:
        The place of every test frame and the test tour's metrics, with ``precision`` against
        the rooms the places were mapped in (not the test tour's own majority) and
        ``map_precision``, the map's own.
    """
    from placeclust.metrics import place_to_room

    mapped = run(algo, frames, features, **params)
    rooms_of = place_to_room(mapped.assignments, room)
    reset_position(mapped.model)  # the test tour starts anywhere on the map
    tested = localize(mapped.model, test_frames)
    pred, metrics = tested.assignments, evaluate(tested, test_room)
    metrics["precision"] = float(np.mean([rooms_of.get(int(p), -1) == r
                                          for p, r in zip(pred, test_room)]))
    metrics["map_precision"] = score(mapped.assignments, room)["precision"]
    return pred, metrics
