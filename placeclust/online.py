"""Online sequential place clustering: seed 000 (Tang, Hamami, Karasfi, Nakhaeinia), Sec. IV.

:class:`OnlinePlaceClustering` turns a stream of frames into a topological map of places, one
frame at a time; :data:`PANORAMA` holds its settings for 360° panoramas.

Examples:
    :data:`PANORAMA` is read-only, so that one caller's change cannot leak into another's
    recognizer; derive a variant with ``dict``:

    >>> from placeclust import PANORAMA, OnlinePlaceClustering
    >>> model = OnlinePlaceClustering(**PANORAMA)
    >>> model.view, model.kernel_capacity, model.scene_change, model.scale
    ('sides', 600, 0.25, 0.75)
    >>> OnlinePlaceClustering(**dict(PANORAMA, scale=1.0)).scale
    1.0
    >>> PANORAMA["scale"] = 1.0
    Traceback (most recent call last):
        ...
    TypeError: 'mappingproxy' object does not support item assignment
"""

from __future__ import annotations

import inspect
import os
from collections.abc import Mapping
from types import MappingProxyType
from typing import NamedTuple

import networkx as nx
import numpy as np

from placeclust.features import FeatureExtractor
from placeclust.frames import check_size, to_gray
from placeclust.index import PlaceIndex
from placeclust.kernel import UnionKernel
from placeclust.mapfile import load_map, save_map
from placeclust.matching import dice_eq4, normalize
from placeclust.scene_change import SceneChangeGate

UNKNOWN = -1


class _Compared(NamedTuple):
    """One place compared with a frame: Eq. 4 as a distance, and the correspondences."""

    place: int
    distance: float
    matches: tuple[np.ndarray, np.ndarray]


_NONE = _Compared(UNKNOWN, np.inf, (np.zeros(0, np.int64), np.zeros(0, np.int64)))

#: Settings for 360° panoramas with the heading at the centre column (``envs.panorama``): side
#: views, kernels of half the size for half the features, the scene-change gate, and detection
#: on a 0.75 copy of the frame. The thresholds stay the defaults.
#: ``OnlinePlaceClustering(**PANORAMA)``; on the CLI, ``--param view=sides --param
#: kernel_capacity=600 --param scene_change=0.25 --param scale=0.75``. Read-only, so that one
#: caller's change cannot leak into another's recognizer.
#:
#: Why ``scale=0.75``: SIFT is most of a frame's time, and OpenCV's SIFT doubles its input for
#: its first octave, so a 0.75 copy still yields nearly all the features, faster, with the same
#: quality on the simulator's tours (``docs/benchmarks.md``). Its price is poorer reuse
#: under another condition (light, furniture, noise), which the gate already makes poor;
#: ``dict(PANORAMA, scale=1.0)`` gives the full-size detection back.
PANORAMA: Mapping[str, object] = MappingProxyType(
    {"view": "sides", "kernel_capacity": 600, "scene_change": 0.25, "scale": 0.75})

#: Named configurations of :class:`OnlinePlaceClustering` (the CLI's ``--preset``): ``paper``
#: is seed 000's recognizer with the library's defaults, ``panorama`` is :data:`PANORAMA`.
PRESETS: Mapping[str, Mapping[str, object]] = MappingProxyType(
    {"paper": MappingProxyType({}), "panorama": PANORAMA})


class OnlinePlaceClustering:
    """Unsupervised, online place recognition with union-of-features kernels.

    Implements the online sequential place clustering of seed 000 (Sec. IV). Each frame's local
    features are matched (Eq. 3) with the kernels (:class:`~placeclust.kernel.UnionKernel`,
    Sec. III.B) of the current place and its graph neighbours (step 4), and the nearest place
    decides (steps 5-8). Eq. 4 is a similarity (a Dice coefficient) that the paper calls a
    distance and minimises, so this class uses ``distance = 1 - Eq. 4``, which keeps the
    paper's ordering ``T_Update_Cluster < T_New_Cluster < 1``:

    - ``distance > t_new_cluster``: a new place, connected to the current one (step 6);
    - ``t_new_cluster >= distance > t_update_cluster``: the place's kernel absorbs the frame
      (``Union_Of_Cluster``, step 7);
    - ``distance <= t_update_cluster``: recognised, the kernel is left as it is (step 8).

    Where the paper is silent, or would fail, this class adds (the reasons are in
    ``docs/design.md``, "Choices the papers leave open"):

    - **Tracking first.** A frame the current place recognises is not compared with the
      neighbours, so tracking costs one match however many neighbours the place has.
    - **Loop closure.** When no neighbour is within ``t_new_cluster``, a
      :class:`~placeclust.index.PlaceIndex` shortlists places of the whole map, checked with
      Eq. 4; ``relocalize=False`` gives the paper's neighbour-only search.
    - **Scene-change gate** (``scene_change``, off by default). A place opens only within
      ``scene_window`` frames after a scene change
      (:class:`~placeclust.scene_change.SceneChangeGate`, the online form of Sec. III.C step
      1); any other frame beyond ``t_new_cluster`` is absorbed by the current place. Such
      maps localize worse under other conditions: leave the gate off for a map that must
      serve under them.
    - **Featureless frames**, with fewer than ``min_features`` features (a black image, a
      blank wall), are :data:`UNKNOWN` (-1) and change nothing.

    Args:
        features: local feature type, see :mod:`placeclust.features` (the paper uses SURF-64).
        max_features: features kept per frame.
        t_new_cluster: ``T_New_Cluster`` on ``1 - Eq. 4``; the paper gives no values for
            either threshold. ``0.9`` and ``0.5`` (with ``scale=0.75``) score higher under one
            light but worse when the map is reused under another light or after changes, so
            the defaults stay.
        t_update_cluster: ``T_Update_Cluster`` on ``1 - Eq. 4``.
        kernel_capacity: the most features a kernel keeps (Sec. III.B pruning).
        max_places: the most places, or ``None`` for no limit (the paper). A full map stops
            growing: a frame that would open a place is localized instead, as by
            :meth:`localize_one`. With capped kernels this bounds memory and latency for any
            run (ORB keeps opening places on new paths through known rooms, see
            ``envs.longrun``).
        ratio: Lowe's ratio for correspondences (Eq. 3).
        relocalize: search the whole map when no neighbour matches (see above).
        shortlist: places checked exactly after an index query.
        index_features: features per place in the relocalization index.
        min_features: fewer features than this make a frame featureless.
        t_localize: distance above which :meth:`localize_one` reports :data:`UNKNOWN`; looser
            than ``t_new_cluster``, since on a fixed map the question is "which place is this
            most like", not "is this a new place".
        normalize: contrast normalization before detection
            (:class:`~placeclust.features.FeatureExtractor`). The paper works on raw images;
            CLAHE is this project's addition for COLD-like light changes.
        scale: resize factor in (0, 1] before detection; saved maps record it.
        view: ``"full"`` (any camera) or ``"sides"`` for 360° panoramas with the heading at the
            centre column: only the features within 45° of the robot's left and right
            (:data:`~placeclust.features.VIEWS`), which change room as the robot passes the
            door, where a whole panorama sees the next room early and the last one late.
            Saved maps record it.
        scene_change: similarity threshold of the scene-change gate (see above), or ``None``
            for the paper's behaviour, a new place whenever no place is within
            ``t_new_cluster``.
        scene_lag: frames between the two frames the gate compares (10 frames are 40 cm of the
            simulator's scripted tours).
        scene_window: frames after a scene change during which a place may open.

    Raises:
        ValueError: unless ``0 <= t_update_cluster < t_new_cluster < 1``, or if ``max_places``
            is below 1.

    Examples:
        Three jittered views of one synthetic place, then three of another:

        >>> import numpy as np
        >>> from placeclust import OnlinePlaceClustering
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(3)
        >>> model = OnlinePlaceClustering()
        >>> [model.learn_predict_one(f) for f in frames]
        [0, 0, 0, 1, 1, 1]
        >>> model.n_places, sorted(model.graph.edges)
        (2, [(0, 1)])

        :meth:`predict_one` and :meth:`localize_one` leave the map as it is; a featureless
        frame is :data:`UNKNOWN`:

        >>> model.predict_one(frames[0]), model.localize_one(frames[4])
        (0, 1)
        >>> model.predict_one(np.zeros((128, 512), np.uint8))
        -1

        With the scene-change gate no place opens before the gate has seen ``scene_lag``
        frames, so here the second place's frames are absorbed by the first:

        >>> gated = OnlinePlaceClustering(scene_change=0.25)
        >>> [gated.learn_predict_one(f) for f in frames]
        [0, 0, 0, 0, 0, 0]
    """

    def __init__(
        self,
        features: str = "sift",
        max_features: int = 500,
        t_new_cluster: float = 0.85,
        t_update_cluster: float = 0.6,
        kernel_capacity: int = 1200,
        max_places: int | None = None,
        ratio: float = 0.8,
        relocalize: bool = True,
        shortlist: int = 3,
        index_features: int = 64,
        min_features: int = 10,
        t_localize: float = 0.98,
        normalize: str | None = "clahe",
        scale: float = 1.0,
        view: str = "full",
        scene_change: float | None = None,
        scene_lag: int = 10,
        scene_window: int = 10,
    ) -> None:
        if not 0.0 <= t_update_cluster < t_new_cluster < 1.0:
            raise ValueError(
                "need 0 <= t_update_cluster < t_new_cluster < 1 (Sec. IV), got "
                f"t_update_cluster={t_update_cluster}, t_new_cluster={t_new_cluster}")
        if max_places is not None and max_places < 1:
            raise ValueError(f"max_places must be at least 1 or None, got {max_places}")
        self.features = features
        self.max_features = max_features
        self.t_new_cluster = t_new_cluster
        self.t_update_cluster = t_update_cluster
        self.kernel_capacity = kernel_capacity
        self.max_places = max_places
        self.ratio = ratio
        self.relocalize = relocalize
        self.shortlist = shortlist
        self.index_features = index_features
        self.min_features = min_features
        self.t_localize = t_localize
        self.normalize = normalize
        self.scale = scale
        self.view = view
        self.scene_change = scene_change
        self.scene_lag = scene_lag
        self.scene_window = scene_window
        self._extractor = FeatureExtractor(features, max_features, normalize, scale, view)
        self._gate = None if scene_change is None else SceneChangeGate(
            scene_change, scene_lag, scene_window, self._extractor.binary, ratio)
        self.kernels: dict[int, UnionKernel] = {}
        self.graph = nx.Graph()
        self.current: int = UNKNOWN
        self.frame_shape: tuple[int, int] | None = None
        self._index = PlaceIndex(self._extractor.binary, self._index_sample)

    # -- river-style API ---------------------------------------------------------------------

    def learn_one(self, frame: np.ndarray) -> None:
        """Update the map with one frame (Sec. IV, steps 1-8).

        Args:
            frame: ``(H, W)`` or ``(H, W, 1|3|4)`` image (see :func:`~placeclust.frames.to_gray`),
                the size of the map's earlier frames.
        """
        self.learn_predict_one(frame)

    def predict_one(self, frame: np.ndarray) -> int:
        """The place of ``frame`` without changing the map or the current place.

        Args:
            frame: an image, as for :meth:`learn_one`.

        Returns:
            The nearest place within ``t_new_cluster``, or :data:`UNKNOWN` if there is none or
            the frame is featureless.
        """
        desc = self._describe(frame)
        if desc is None or not self.kernels:
            return UNKNOWN
        best, _ = self._nearest(desc)
        return best.place if best.distance <= self.t_new_cluster else UNKNOWN

    def learn_predict_one(self, frame: np.ndarray) -> int:
        """Learn from ``frame`` (steps 1-8) and return its place (step 9).

        Args:
            frame: an image, as for :meth:`learn_one`.

        Returns:
            The place id, or :data:`UNKNOWN` for a featureless frame or, on a full map
            (``max_places``), a frame beyond ``t_localize`` of every place searched.

        Raises:
            ValueError: ``frame`` is not a valid image or differs in size from the map's frames.
        """
        desc = self._describe(frame, learn=True)
        if desc is None:
            return UNKNOWN
        if not self.kernels:
            return self._new_place(desc)
        # a closed gate means the robot has not left its place's room: no search of the map
        in_room = self._gate is not None and not self._gate.is_open
        best, here = self._nearest(desc, whole_map=not in_room)
        if best.distance > self.t_new_cluster:
            if self.map_full:
                return self._localized(best.place, best.distance)
            if self._gate is None or self._gate.is_open or here is None:
                return self._new_place(desc)
            # no scene change: the robot is still in its place, which absorbs the frame (step 7)
            return self._absorb(here.place, desc, here.matches)
        if best.place != self.current and self.current != UNKNOWN:
            # a loop closure when they were not adjacent
            self.graph.add_edge(self.current, best.place)
        if best.distance > self.t_update_cluster:
            return self._absorb(best.place, desc, best.matches)
        self.current = best.place
        return best.place

    def localize_one(self, frame: np.ndarray) -> int:
        """Track the robot on a fixed map: the place of ``frame``, or :data:`UNKNOWN`.

        Like :meth:`learn_predict_one` (the search starts from the current place and its
        neighbours) but the map never changes: no kernel update, no new place, no new edge.
        A frame that matches no place within ``t_localize`` is :data:`UNKNOWN` and leaves the
        current place as it was, so tracking resumes from there.

        Args:
            frame: an image, as for :meth:`learn_one`.

        Returns:
            The place id, or :data:`UNKNOWN`.
        """
        desc = self._describe(frame)
        if desc is None or not self.kernels:
            return UNKNOWN
        best, _ = self._nearest(desc)
        return self._localized(best.place, best.distance)

    def reset_position(self) -> None:
        """Forget where the robot is (it was carried elsewhere); the map is kept.

        The next frame is searched in the whole map (through the index shortlist) instead of
        the current place's neighbourhood, and the scene-change gate forgets the frames before.
        """
        self.current = UNKNOWN
        if self._gate is not None:
            self._gate.reset()

    @property
    def n_places(self) -> int:
        """The number of places in the map."""
        return len(self.kernels)

    @property
    def map_full(self) -> bool:
        """Whether the map holds ``max_places`` places and opens no more."""
        return self.max_places is not None and len(self.kernels) >= self.max_places

    # -- map persistence ---------------------------------------------------------------------

    def get_params(self) -> dict[str, object]:
        """The constructor arguments (scikit-learn style), enough to rebuild an empty model.

        Returns:
            Parameter name -> value, for every argument of ``__init__``.
        """
        names = inspect.signature(type(self).__init__).parameters
        return {n: getattr(self, n) for n in names if n != "self"}

    def save(self, path: str | os.PathLike, world: str = "") -> None:
        """Write the map atomically (see :func:`placeclust.mapfile.save_map`).

        Args:
            path: the map file; its folder must exist.
            world: a fingerprint of the world the map was made in, checked by :meth:`load`.
        """
        save_map(self, path, world)

    @classmethod
    def load(cls, path: str | os.PathLike, world: str | None = None) -> OnlinePlaceClustering:
        """A recognizer from a map file (see :func:`placeclust.mapfile.load_map`).

        Args:
            path: a map file written by :meth:`save`.
            world: if given, the world the map must have been made in.

        Returns:
            A recognizer with the saved parameters, map and current place.

        Raises:
            FileNotFoundError: there is no file at ``path``.
            ValueError: the file is not a readable, consistent map (of ``world``, if given).
        """
        return load_map(path, world)

    def restore(self, kernels: dict[int, tuple], place_images: dict[int, int],
                edges: list, current: int, frame_shape: list | None) -> None:
        """Replace the map with saved state (used by :func:`placeclust.mapfile.load_map`).

        Args:
            kernels: place -> ``(descriptors, weights, last_seen, n_images)`` of its kernel.
            place_images: place -> frames assigned to it.
            edges: the topological graph's edges, pairs of places.
            current: the robot's place, or :data:`UNKNOWN`.
            frame_shape: ``(H, W)`` of the map's frames, or ``None``.

        Raises:
            ValueError: place ids are not ``0..n-1``, or ``current`` or an edge names a place
                that is not in the map.
        """
        places = sorted(int(p) for p in kernels)
        if places != list(range(len(places))):
            raise ValueError(f"place ids must be 0..n-1, got {places[:10]}")
        if current != UNKNOWN and current not in kernels:
            raise ValueError(f"current place {current} is not in the map")
        self.kernels = {p: UnionKernel.from_state(*kernels[p], binary=self._extractor.binary,
                                                  capacity=self.kernel_capacity, ratio=self.ratio)
                        for p in places}
        self.graph = nx.Graph()
        for p in places:
            self.graph.add_node(p, n_images=int(place_images[p]))
        for a, b in edges:
            if a not in self.kernels or b not in self.kernels:
                raise ValueError(f"edge ({a}, {b}) names a place that is not in the map")
            self.graph.add_edge(int(a), int(b))
        self.current = int(current)
        self.frame_shape = tuple(frame_shape) if frame_shape else None
        self._index = PlaceIndex(self._extractor.binary, self._index_sample)
        for p in places:
            self._index.add(p)

    # -- internals ------------------------------------------------------------------------------

    def _describe(self, frame: np.ndarray, learn: bool = False) -> np.ndarray | None:
        """The frame's (normalised) descriptors, or ``None`` if it is featureless; ``learn``
        feeds the scene-change gate, which only frames that may change the map should do."""
        gray = to_gray(frame)
        self.frame_shape = check_size(gray, self.frame_shape)
        feats, whole = self._extractor.extract_pair(gray)
        if len(feats) < self.min_features:
            return None
        desc = normalize(feats.descriptors, feats.binary)
        if learn and self._gate is not None:
            self._gate.update(desc, desc if whole is feats else
                              normalize(whole.descriptors, whole.binary))
        return desc

    def _compare(self, place: int, desc: np.ndarray) -> _Compared:
        kernel = self.kernels[place]
        matches = kernel.match(desc)
        return _Compared(place, 1.0 - dice_eq4(len(matches[0]), len(kernel), len(desc)), matches)

    def _nearest(self, desc: np.ndarray, whole_map: bool = True
                 ) -> tuple[_Compared, _Compared | None]:
        """``(best, here)``: the best place among the current one and its neighbours, then the
        whole map if needed (and ``whole_map``, or no place is current); ``here`` is the
        current place's comparison, ``None`` when no place is current.

        "The whole map" is the ``shortlist`` places with most votes in the index, so the cost
        does not grow with the number of places.
        """
        here = None if self.current == UNKNOWN else self._compare(self.current, desc)
        if here is not None and here.distance <= self.t_update_cluster:
            return here, here
        candidates = [] if here is None else [self.current, *self.graph.neighbors(self.current)]
        start = _NONE if here is None else here
        best = min([start, *(self._compare(p, desc) for p in candidates[1:])],
                   key=lambda c: c.distance)
        if best.distance > self.t_new_cluster and (
                (self.relocalize and whole_map) or here is None):
            for p in self._shortlist(desc, exclude=candidates):
                best = min(best, self._compare(p, desc), key=lambda c: c.distance)
                if best.distance <= self.t_update_cluster:
                    break
        return best, here

    def _shortlist(self, desc: np.ndarray, exclude: list[int]) -> list[int]:
        """The ``shortlist`` places the index votes for most, leaving out ``exclude``."""
        ranked = self._index.ranked(desc)
        return [p for p in ranked if p not in exclude][: self.shortlist]

    def _localized(self, place: int, distance: float) -> int:
        """Place the robot at ``place`` if within ``t_localize``, else report UNKNOWN."""
        if distance > self.t_localize:
            return UNKNOWN
        self.current = place
        return place

    def _absorb(self, place: int, desc: np.ndarray, matches: tuple) -> int:
        """Union_Of_Cluster (step 7): ``place``'s kernel takes the frame; the robot is there."""
        self.kernels[place].update(desc, matches)
        self.graph.nodes[place]["n_images"] += 1
        self.current = place
        return place

    def _new_place(self, desc: np.ndarray) -> int:
        place = len(self.kernels)
        self.kernels[place] = UnionKernel(desc, self._extractor.binary, self.kernel_capacity,
                                          self.ratio)
        self.graph.add_node(place, n_images=1)
        if self.current != UNKNOWN:
            self.graph.add_edge(self.current, place)
        self.current = place
        self._index.add(place)
        return place

    def _index_sample(self, place: int) -> np.ndarray:
        return self.kernels[place].top(self.index_features)
