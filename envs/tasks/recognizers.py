"""The closed loop's recognizers by name, and a recognizer of your own by ``package.module:Class``.

``PlaceNav-GuidedTour-v1``, ``placeclust errands`` and ``placeclust leaderboard`` take a name of
:data:`RECOGNIZERS` or a path, and build each building's recognizer with :func:`make_recognizer`.

Examples:
    >>> from envs.tasks.recognizers import make_recognizer
    >>> make_recognizer("panorama-orb", n_rooms=6).n_places
    0
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from placeclust import PANORAMA, PANORAMA_ORB, OnlinePlaceClustering
from placeclust.nested import NestedMapper
from placeclust.null import NoPlaces, RandomPlaces
from placeclust.protocol import can_localize, is_offline, reads_images
from placeclust.runner import check_params, make, recognizer_class

from .oracles import KINDS, TrueRooms, is_oracle_name, parse_oracle
from .place_id import Recognizer

#: recognizers by name: ``oracle`` gives the true room (the upper bound of room errands; its
#: calibration family ``oracle-noise:P``, ``oracle-split:K``, ``oracle-merge:P``,
#: ``oracle-cells:K``, ``oracle-door:D``, ``oracle-revisit:P`` errs by a known amount, and
#: ``oracle-pose``, the ceiling of image goals, knows the goal's pose too,
#: :mod:`envs.tasks.oracles`); ``panorama`` is seed
#: 000's online recognizer in its 360° configuration with SIFT (the preset ``panorama``,
#: :data:`placeclust.PANORAMA`), ``panorama-orb`` in ORB's (the preset ``panorama-orb``,
#: :data:`placeclust.PANORAMA_ORB`, with ORB); ``nested`` seed 001 on the forward camera;
#: ``random`` ids that mean nothing; ``none`` no ids at all. ``online`` is the paper's defaults
#: everywhere in placeclust (``placeclust bench --algos online``), so it is not a name here.
RECOGNIZERS = ("oracle", "panorama", "panorama-orb", "nested", "random", "none")
#: the names these recognizers had before placeclust 0.13.0, for the error that says so
RENAMED = {"online": "panorama", "online-orb": "panorama-orb"}


@dataclass(frozen=True)
class RecognizerName:
    """A closed-loop recognizer's name, parsed once (:func:`parse_recognizer`): which kind it
    is and what it needs, so that no caller dispatches on the name again.

    Attributes:
        name: as given.
        kind: ``"builtin"`` (one of :data:`RECOGNIZERS`), ``"oracle"`` (the true rooms or a
            calibration oracle, :mod:`envs.tasks.oracles`) or ``"own"``
            (``package.module:Class``).
        oracle: the :class:`~envs.tasks.oracles.TrueRooms` of an oracle name, else None.
    """

    name: str
    kind: str
    oracle: TrueRooms | None = None

    @property
    def camera(self) -> str:
        """The camera it reads: ``nested`` (seed 001) the forward one, a class of one's own its
        ``camera`` attribute (``placeclust.nested:NestedMapper``'s is ``"forward"``), the rest
        the panorama."""
        if self.kind == "own":
            return str(getattr(recognizer_class(self.name), "camera", "panorama"))
        return "forward" if self.name == "nested" else "panorama"

    def build(self, n_rooms: int, max_places: int = 64,
              params: Mapping[str, Any] | None = None) -> Recognizer | TrueRooms:
        """A fresh recognizer (:func:`make_recognizer`)."""
        params = dict(params or {})
        if self.kind == "own":
            return _own_recognizer(self.name, params)
        if params:
            raise ValueError(f"{self.name!r} is one configuration and takes no parameters, "
                             f"got {sorted(params)}; give package.module:Class with them "
                             "instead")
        if self.oracle is not None:
            return self.oracle
        if self.name == "panorama":
            return OnlinePlaceClustering("sift", **PANORAMA, max_places=max_places)
        if self.name == "panorama-orb":
            return OnlinePlaceClustering("orb", **PANORAMA_ORB, max_places=max_places)
        if self.name == "nested":
            return NestedMapper()
        if self.name == "random":
            return RandomPlaces(n_ids=2 * n_rooms)
        return NoPlaces()


def parse_recognizer(name: str) -> RecognizerName:
    """The one parse of a closed-loop recognizer's name.

    Raises:
        ValueError: a name that is none of :data:`RECOGNIZERS`, an oracle name with a value
            out of range, or a ``package.module:Class`` that does not load; the line names the
            choices.
    """
    if name in RECOGNIZERS and name != "oracle":
        return RecognizerName(name, "builtin")
    if is_oracle_name(name) or name.startswith("oracle-"):
        return RecognizerName(name, "oracle", parse_oracle(name))  # says what is wrong
    if ":" in name:
        recognizer_class(name)  # a ValueError naming a path or class that does not load
        return RecognizerName(name, "own")
    hint = f" ('{name}' was renamed '{RENAMED[name]}' in 0.13.0)" if name in RENAMED else ""
    raise ValueError(f"unknown recognizer {name!r}; choose one of {RECOGNIZERS}, "
                     f"oracle-pose, oracle-KIND:VALUE (KIND one of {', '.join(KINDS)}) or "
                     f"give package.module:Class{hint}")


def is_own(name: str) -> bool:
    """Whether ``name`` is a ``package.module:Class`` of the user's, not a built-in name (the
    calibration family's names have a colon too: ``oracle-noise:0.05``)."""
    return ":" in name and not is_oracle_name(name)


def make_recognizer(name: str, n_rooms: int, max_places: int = 64,
                    params: Mapping[str, Any] | None = None) -> Recognizer | TrueRooms:
    """A fresh recognizer for the closed loop: a :class:`~envs.tasks.oracles.TrueRooms` for
    ``oracle`` and its calibration family (the env binds it to the building).

    Args:
        name: one of :data:`RECOGNIZERS`, an ``oracle-<kind>:<value>`` (a calibration
            oracle) or ``oracle-pose``, or ``package.module:Class``, an online recognizer of
            your own (``learn_predict_one``, ``n_places``, ``graph``; see
            :mod:`placeclust.checks`), loaded as ``placeclust cluster --algo`` loads it.
        n_rooms: the building's rooms (``random`` draws ids from twice as many).
        max_places: the cap of ``panorama`` and ``panorama-orb``'s maps.
        params: a module path's constructor arguments (``features`` included). A name is one
            configuration, so it takes none: for another, name the class with the arguments,
            e.g. ``placeclust.online:OnlinePlaceClustering`` with ``PANORAMA``'s and yours.

    Raises:
        ValueError: an unknown name, a path that does not load or is not an online recognizer,
            or parameters with a name.
    """
    return parse_recognizer(name).build(n_rooms, max_places, params)


def _own_recognizer(path: str, params: dict[str, Any]) -> Recognizer:
    cls = recognizer_class(path)  # a ValueError that names a path or class that does not load
    if is_offline(cls):
        raise ValueError(f"{path} is an offline recognizer (fit_predict); the closed loop "
                         "needs an online one (learn_predict_one)")
    check_params(path, {k: v for k, v in params.items() if k != "features"})
    model = make(path, **params)
    if not isinstance(model, Recognizer):
        raise ValueError(f"{path} lacks what the closed loop reads of a recognizer: "
                         "learn_predict_one, predict_one, n_places and graph")
    return model


def check_recognizer_name(name: str) -> None:
    """A ``ValueError`` naming the choices if ``name`` is neither one of :data:`RECOGNIZERS`, an
    oracle name, nor a ``package.module:Class`` that loads (:func:`parse_recognizer`)."""
    parse_recognizer(name)


def localizes(name: str, params: Mapping[str, Any] | None = None) -> bool:
    """Whether recognizer ``name`` can run on a fixed map (``errand_learn=False``): it has
    ``localize_one``, or it reads no images (no map to fix), or it is the true rooms."""
    model = make_recognizer(name, 6, params=params)
    return isinstance(model, TrueRooms) or not reads_images(model) or can_localize(model)
