"""The recognizer protocol, as a battery of checks: run it first on a recognizer of your own.

Modelled on river's estimator checks. The protocol itself, its required and optional parts,
is :mod:`placeclust.protocol`: a recognizer is a class whose constructor arguments are its
parameters, and which is either *online* (``learn_predict_one(frame) -> int``,
``predict_one(frame) -> int``, ``n_places``, and a networkx ``graph`` of its places) or
*offline* (``fit_predict(frames) -> (T,) int``). Every built-in recognizer passes; the tests
run the battery over each of them.

Examples:
    >>> from placeclust.checks import check_recognizer
    >>> from placeclust.nested import NestedMapper
    >>> check_recognizer(NestedMapper)  # silent when every check passes
"""

from __future__ import annotations

import copy
import inspect
import pickle
from collections.abc import Callable, Mapping
from typing import cast

import networkx as nx
import numpy as np

from placeclust.online import UNKNOWN
from placeclust.protocol import (
    OfflineRecognizer,
    OnlineRecognizer,
    is_offline,
    is_online,
    resolve,
)
from placeclust.synthetic import places

Check = Callable[[type, dict, np.ndarray], None]


def check_recognizer(cls: type, params: Mapping[str, object] | None = None,
                     frames: np.ndarray | None = None) -> None:
    """Run every check of the protocol on recognizers ``cls(**params)``.

    Args:
        cls: the recognizer's class.
        params: constructor arguments for every instance made (default: none).
        frames: a short sequence to learn, ``(T, H, W[, C])`` (default: two synthetic places
            of three frames each, :func:`~placeclust.synthetic.places`).

    Raises:
        AssertionError: the first check that fails, named in the message.
    """
    params = dict(params or {})
    frames = places(3)[0] if frames is None else frames
    online = is_online(cls)
    assert online or is_offline(cls), (
        f"{cls.__name__} has neither learn_predict_one (online) nor fit_predict (offline)")
    checks = ONLINE_CHECKS if online else OFFLINE_CHECKS
    for check in (*COMMON_CHECKS, *checks):
        try:
            check(cls, params, frames)
        except AssertionError as exc:
            raise AssertionError(f"{cls.__name__} fails {check.__name__}: {exc}") from exc


def learn(model: object, frames: np.ndarray) -> np.ndarray:
    """The places ``model`` gives ``frames``: online one at a time, offline all at once."""
    if is_online(model):
        online = cast(OnlineRecognizer, model)
        return np.array([int(online.learn_predict_one(f)) for f in frames])
    assert is_offline(model), (  # check_recognizer checked that first
        f"{type(model).__name__} has neither learn_predict_one nor fit_predict")
    return np.asarray(cast(OfflineRecognizer, model).fit_predict(frames))


def clone(model: object) -> object:
    """A fresh recognizer with ``model``'s parameters, read back from its attributes."""
    names = [n for n in inspect.signature(type(model)).parameters]
    return type(model)(**{n: getattr(model, n) for n in names})


def check_parameters_are_attributes(cls: type, params: dict, frames: np.ndarray) -> None:
    """Each constructor argument is kept under its own name, and no default is mutable."""
    model = cls(**params)
    for name, p in inspect.signature(cls).parameters.items():
        assert p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD), f"*{name}: list the parameters"
        assert not isinstance(p.default, list | dict | set), f"{name}'s default is mutable"
        assert hasattr(model, name), f"constructor argument {name!r} is not an attribute"
        expected = params.get(name, p.default)
        if expected is not p.empty:
            assert getattr(model, name) == expected, f"{name} is not kept as given"


def check_deterministic(cls: type, params: dict, frames: np.ndarray) -> None:
    """Two fresh instances give the same places to the same frames; so does a clone."""
    first = learn(cls(**params), frames)
    assert np.array_equal(first, learn(cls(**params), frames)), "two runs differ"
    assert np.array_equal(first, learn(clone(cls(**params)), frames)), "a clone differs"


def check_input_not_mutated(cls: type, params: dict, frames: np.ndarray) -> None:
    """Learning leaves the caller's frames as they were."""
    before = frames.copy()
    learn(cls(**params), frames)
    assert np.array_equal(before, frames), "the frames were changed"


def check_places_are_ints(cls: type, params: dict, frames: np.ndarray) -> None:
    """One integer per frame, ``UNKNOWN`` (-1) or a place id from 0."""
    labels = learn(cls(**params), frames)
    assert labels.shape == (len(frames),), f"{labels.shape} places for {len(frames)} frames"
    assert np.issubdtype(labels.dtype, np.integer) and labels.min() >= UNKNOWN


def check_invalid_frames_raise(cls: type, params: dict, frames: np.ndarray) -> None:
    """A frame of the wrong shape, dtype or values is a ``ValueError``, not a crash or a guess."""
    bad = [np.zeros(100, np.uint8), frames[0].astype(np.int64),
           np.full(frames[0].shape, np.nan, np.float32)]
    for frame in bad:
        model = cls(**params)
        try:
            if is_online(model):
                model.learn_predict_one(frame)
            else:
                model.fit_predict(np.stack([frame, frame]))
        except ValueError:
            continue
        raise AssertionError(f"a {frame.dtype} frame of shape {frame.shape} was accepted")


def check_instances_are_independent(cls: type, params: dict, frames: np.ndarray) -> None:
    """What one instance learns does not reach another."""
    a, b = cls(**params), cls(**params)
    expected = learn(cls(**params), frames)
    learn(a, frames)
    assert np.array_equal(learn(b, frames), expected), "a second instance saw the first's map"


def check_online_protocol(cls: type, params: dict, frames: np.ndarray) -> None:
    """``predict_one`` names a place without learning; ``n_places`` and ``graph`` agree.

    A recognizer that merges places (``resolve``, as consolidation does) is judged by the
    places its ids resolve to now: a merged-away id is neither counted nor a node.
    """
    model = cls(**params)
    labels = learn(model, frames)
    given = set(resolve(model, labels).tolist()) - {UNKNOWN}
    n = model.n_places
    assert isinstance(n, int | np.integer), "n_places is not an int"
    assert n == len(given), "n_places differs from the places given"
    assert isinstance(model.graph, nx.Graph), "graph is not a networkx graph"
    assert set(model.graph.nodes) <= given, "graph has nodes that are not places"
    place = model.predict_one(frames[0])
    assert isinstance(place, int | np.integer) and model.n_places == n, "predict_one learnt"


def check_featureless_frames_are_unknown(cls: type, params: dict, frames: np.ndarray) -> None:
    """A blank frame is ``UNKNOWN`` and changes nothing."""
    model = cls(**params)
    learn(model, frames)
    n = model.n_places
    blank = np.zeros_like(frames[0])
    assert model.learn_predict_one(blank) == UNKNOWN, "a blank frame was given a place"
    assert model.n_places == n, "a blank frame changed the map"


def check_pickles(cls: type, params: dict, frames: np.ndarray) -> None:
    """A learnt recognizer survives ``pickle`` and ``deepcopy`` and answers as before."""
    model = cls(**params)
    learn(model, frames)
    for twin in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        assert twin.n_places == model.n_places, "a copy lost places"
        assert twin.predict_one(frames[-1]) == model.predict_one(frames[-1]), "a copy differs"


COMMON_CHECKS: tuple[Check, ...] = (
    check_parameters_are_attributes, check_places_are_ints, check_deterministic,
    check_input_not_mutated, check_invalid_frames_raise, check_instances_are_independent)
ONLINE_CHECKS: tuple[Check, ...] = (
    check_online_protocol, check_featureless_frames_are_unknown, check_pickles)
OFFLINE_CHECKS: tuple[Check, ...] = ()
