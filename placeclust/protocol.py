"""The recognizer protocol in one place: what every recognizer has, and what some add.

A recognizer is a class whose constructor arguments are its parameters, and which is one of

- :class:`OnlineRecognizer`: ``learn_predict_one(frame) -> int`` (learn and name the place),
  ``predict_one(frame) -> int`` (name it without learning), ``n_places`` and a networkx
  ``graph`` of its places; what the simulator's wrapper, the closed loop and ``placeclust
  cluster`` run;
- :class:`OfflineRecognizer`: ``fit_predict(frames) -> (T,) int``, the whole sequence at once.

An online recognizer may add, and the commands dispatch on, these optional parts:

- :class:`Localizer`: ``localize_one(frame) -> int``, naming a place on a fixed map; it takes
  part in cross-condition runs (``placeclust bench --conditions day>night``) and in
  ``PlaceIdWrapper(learn=False)``; others are reported as skipped or refused;
- :class:`Ranker`: ``rank_places(frame, n) -> [int]``, its places best first for a frame,
  learning nothing; ``placenav-v5`` names a goal picture's place by it (below the threshold
  too) and ``placeclust bench`` scores recall at N with it;
- :class:`Repositionable`: ``reset_position()``, forget where the robot was (it was carried);
- :class:`Merging`: ``resolve(ids) -> ids``, the place each id it gave belongs to now (ids that
  consolidation merged away); scores use it;
- ``map_full`` (bool): the map holds all the places it may;
- ``reads_images = False`` (class attribute): it never looks at a frame, so a simulator need
  not render one and may pass ``None`` (:mod:`placeclust.null`);
- ``view`` (``"full"`` or ``"sides"``): which part of a 360° panorama it keeps.

:mod:`placeclust.checks` tests the required parts (and ``resolve`` where present) as a battery.

Examples:
    >>> from placeclust.online import OnlinePlaceClustering
    >>> from placeclust.kunion import KAdjacentUnion
    >>> from placeclust.protocol import can_localize, is_offline, is_online
    >>> is_online(OnlinePlaceClustering), can_localize(OnlinePlaceClustering)
    (True, True)
    >>> is_offline(KAdjacentUnion), can_localize(KAdjacentUnion)
    (True, False)
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import networkx as nx
import numpy as np


@runtime_checkable
class OnlineRecognizer(Protocol):
    """Learns one frame at a time and names its place (required parts)."""

    graph: nx.Graph

    def learn_predict_one(self, frame: np.ndarray) -> int: ...

    def predict_one(self, frame: np.ndarray) -> int: ...

    @property
    def n_places(self) -> int: ...


@runtime_checkable
class OfflineRecognizer(Protocol):
    """Sees the whole sequence at once."""

    def fit_predict(self, frames: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class Localizer(Protocol):
    """Names a place on a fixed map, learning nothing."""

    def localize_one(self, frame: np.ndarray) -> int: ...


@runtime_checkable
class Repositionable(Protocol):
    """Can forget where the robot was."""

    def reset_position(self) -> None: ...


@runtime_checkable
class Merging(Protocol):
    """Merges places after naming them; says where each id went."""

    def resolve(self, places: np.ndarray) -> np.ndarray: ...


def _has(obj: object, name: str) -> bool:
    return callable(getattr(obj, name, None))


def is_online(obj: object) -> bool:
    """Whether a recognizer (class or instance) learns one frame at a time."""
    return _has(obj, "learn_predict_one")


def is_offline(obj: object) -> bool:
    """Whether a recognizer (class or instance) sees the whole sequence at once and is not
    online too."""
    return not is_online(obj) and _has(obj, "fit_predict")


def can_localize(obj: object) -> bool:
    """Whether a recognizer (class or instance) can name places on a fixed map."""
    return _has(obj, "localize_one")


@runtime_checkable
class Ranker(Protocol):
    """Ranks its places for a frame, best first, learning nothing: a picture always gets an
    answer, below the recognizer's threshold too (placenav-v5's goals, recall at N)."""

    def rank_places(self, frame: np.ndarray, n: int = 10) -> list[int]: ...


def can_rank(obj: object) -> bool:
    """Whether a recognizer (class or instance) can rank its places for a frame."""
    return _has(obj, "rank_places")


def reset_position(model: object) -> None:
    """Tell ``model`` the robot was carried away, if it keeps a position (else nothing)."""
    if isinstance(model, Repositionable):
        model.reset_position()


def resolve(model: object, places: np.ndarray) -> np.ndarray:
    """The places ``model``'s ids belong to now (:class:`Merging`), or the ids as they are."""
    ids = np.asarray(places, np.int64)
    return np.asarray(model.resolve(ids), np.int64) if isinstance(model, Merging) else ids


def place_of(model: object, frame: np.ndarray, rank: bool = True) -> int:
    """The place ``model`` names for a picture taken anywhere on its map, learning nothing
    and leaving ``model`` as it was: asked of a copy that has forgotten where the robot is
    (:func:`reset_position`), so the whole map is searched and the robot's own tracking does
    not move. Its best-ranked place where it ranks and ``rank`` (an answer below its
    threshold too; -1 for an empty map), else ``localize_one`` (the fixed map's query, with
    its own threshold), else ``predict_one``. The one way a goal picture is localized: by the
    image-goal envs and by an agent given a goal panorama.

    >>> from placeclust.online import OnlinePlaceClustering
    >>> rng = np.random.default_rng(0)
    >>> frames = rng.integers(0, 255, size=(2, 32, 64, 3), dtype=np.uint8)
    >>> model = OnlinePlaceClustering(features="orb")
    >>> [model.learn_predict_one(f) for f in frames] == [place_of(model, f) for f in frames]
    True
    """
    import copy

    model = copy.deepcopy(model)
    reset_position(model)
    if rank and can_rank(model):
        ranked = model.rank_places(frame, n=1)  # type: ignore[attr-defined]
        return int(ranked[0]) if len(ranked) else -1
    if can_localize(model):
        return int(model.localize_one(frame))  # type: ignore[attr-defined]
    return int(model.predict_one(frame))  # type: ignore[attr-defined]


def reads_images(model: object) -> bool:
    """Whether ``model`` looks at frames (``reads_images``, default True)."""
    return bool(getattr(model, "reads_images", True))


def map_full(model: object) -> bool:
    """Whether ``model``'s map holds all the places it may (``map_full``, default False)."""
    return bool(getattr(model, "map_full", False))


def view(model: object) -> Any:
    """The part of a panorama ``model`` keeps (``view``, default ``"full"``)."""
    return getattr(model, "view", "full")
