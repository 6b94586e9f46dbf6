"""Online sequential place clustering: seed 000 (Tang, Hamami, Karasfi, Nakhaeinia), Sec. IV."""

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
#: Why ``scale=0.75`` (placeclust 0.9.0): OpenCV's SIFT is most of a frame, and it doubles its
#: input for its first octave, so a 384x96 copy of a 512x128 panorama still gives ~470-480 of
#: the 500 features, in ~10 instead of ~15 ms. On the 16 tours of ``README``, "Scene changes",
#: the quality held (precision 0.987 against 0.982, NMI 0.864 against 0.863, 1.51 against 1.43
#: places per room; 15 tours of 16 meet all three bars, against 13). Its price is reuse under
#: another condition, which the gate already makes poor: mapped by day, localized by night,
#: cloudy light, moved furniture or camera noise, precision 0.77-0.82 against 0.80-0.85.
#: ``dict(PANORAMA, scale=1.0)`` gives the full-size detection back.
PANORAMA: Mapping[str, object] = MappingProxyType(
    {"view": "sides", "kernel_capacity": 600, "scene_change": 0.25, "scale": 0.75})


class OnlinePlaceClustering:
    """Unsupervised, online place recognition with union-of-features kernels.

    Each frame's local features are compared with the kernels of the current place and its
    neighbours in the topological graph (Sec. IV, step 4). Eq. 4 is a similarity (the Dice
    coefficient of matched features) although the text calls it a distance and compares its
    *minimum* with the thresholds, so this class uses ``distance = 1 - Eq. 4``, which keeps the
    paper's ordering ``T_Update_Cluster < T_New_Cluster < 1`` (steps 5-8):

    - ``distance > t_new_cluster``: a new place, connected to the current one (step 6);
    - ``t_new_cluster >= distance > t_update_cluster``: the place's kernel absorbs the frame
      (``Union_Of_Cluster``, step 7);
    - ``distance <= t_update_cluster``: the frame is recognised, the kernel is left as it is
      (step 8).

    The current place is compared first, and a frame it recognises (step 8) stays there without
    a comparison with the neighbours, so tracking costs one match however many neighbours the
    place has gained (the paper takes the nearest of them all: the two differ only where a
    neighbour is nearer still than a place that recognises the frame). On 16 simulated tours
    this changed no figure, with :data:`PANORAMA` or the defaults; on a 12-room tour of 8,000
    frames it saved 14% of the matches.

    The paper does not say what happens when the robot returns to a known place that is not a
    neighbour of the current one (a loop); restricted to neighbours, it would open a duplicate
    place. Here, when no neighbour is within ``t_new_cluster``, the frame is relocalized
    against the whole map through a :class:`~placeclust.index.PlaceIndex` (the ``shortlist``
    places with most votes are checked with Eq. 4); if one is within ``t_new_cluster`` the
    robot is placed there and an edge closes the loop; the shortlist is checked in order of
    votes and stops at a place that recognises the frame. ``relocalize=False`` gives the paper's
    neighbour-only search.

    With ``scene_change`` set, a place opens only near a scene change
    (:class:`~placeclust.scene_change.SceneChangeGate`, the online form of the scene-change
    detection of Sec. III.C step 1): a frame beyond ``t_new_cluster`` of every place within
    ``scene_window`` frames after a scene change opens a new place as in step 6; any other
    frame beyond it stays in the current place, whose kernel absorbs it as in step 7. A kernel
    is a bounded union of the oldest heaviest features, so driving through a room leaves it
    behind every metre or so; without the gate each time opens a place, with it only a doorway
    does. While the gate is closed the robot has not left its room, so a frame that no
    neighbour matches is not searched for in the whole map either (a full map localizes it
    among the neighbours, see ``max_places``): on a 12-room tour of 8,000 frames 37% of the
    frames had been searched for, 47 are now; precision rose from 0.943 to 0.953 and the
    median frame took 14.5 instead of 16.1 ms (SIFT). A first frame, or the
    first after :meth:`reset_position`, opens a place anyway. Map files do not keep the gate's
    recent frames: after :meth:`load` it stays closed for ``scene_lag`` frames, so learning
    resumes in the saved place. The places are whole rooms, but their kernels still hold what
    was seen first: mapping by day and localizing the same route under another condition
    (:meth:`localize_one`), precision fell from 0.93-0.94 (side views without the gate) to
    0.81-0.85 with it (placeclust 0.7.0, ``README``, "Scene changes"): for a map that must
    serve under other conditions, leave the gate off.

    Frames with fewer than ``min_features`` features (a black image, a blank wall) are
    featureless: they are reported as :data:`UNKNOWN` (-1) and change nothing.

    Args:
        features: local feature type, see :mod:`placeclust.features` (the paper uses SURF-64).
        max_features: features kept per frame.
        t_new_cluster: ``T_New_Cluster`` on ``1 - Eq. 4``. The paper gives no values for
            either threshold. ``scale=0.75, t_new_cluster=0.9, t_update_cluster=0.5`` gave
            higher precision and NMI on tours under one light, but lower precision when the
            map is reused under another light or after changes (``README``, "Choosing the
            thresholds"), so the defaults stay.
        t_update_cluster: ``T_Update_Cluster`` on ``1 - Eq. 4``.
        kernel_capacity: the most features a kernel keeps (Sec. III.B pruning).
        max_places: the most places the map holds, or ``None`` for no limit (the paper). A
            full map stops growing: a frame that would open a place is localized instead, as
            by :meth:`localize_one`, and changes nothing. Kernels are capped too, so memory and
            latency are bounded for any run length and any feature type (ORB keeps opening
            places on new paths through known rooms, see ``envs.longrun``).
        ratio: Lowe's ratio for correspondences (Eq. 3).
        relocalize: search the whole map when no neighbour matches (see above).
        shortlist: places checked exactly after an index query.
        index_features: features per place in the relocalization index.
        min_features: fewer features than this make a frame featureless.
        t_localize: distance above which :meth:`localize_one` reports :data:`UNKNOWN`. On a
            fixed map the question is "which place is this most like", not "is this a new
            place", so it is looser than ``t_new_cluster``: on random drives in a 4-room world
            mapped by one tour (ORB), 0.85 left 89% of frames unknown, 0.98 none, with 99% of
            frames in their place's majority room.
        normalize: contrast normalization before feature detection (see
            :class:`~placeclust.features.FeatureExtractor`). The paper works on raw images;
            CLAHE is this project's addition for COLD-like light changes: on three 4-room
            worlds (SIFT), it raised precision from 0.87 to 0.95 under one light and, mapping
            by day and localizing at night, from 0.76 to 0.94 (``placeclust bench``).
        scale: resize factor in (0, 1] before feature detection (see
            :class:`~placeclust.features.FeatureExtractor`); saved maps record it.
        view: ``"full"`` (any camera) or, for 360° panoramas with the heading at the centre
            column, ``"sides"``: only the features within 45° of the robot's left and right
            (:data:`~placeclust.features.VIEWS`). A whole panorama sees the next room through
            a doorway before the robot reaches it and the last room after, so places open
            early or late; a sideways view changes room as the robot passes the door. On 16
            simulated tours (4 and 8 rooms) precision rose from 0.93 to 0.96 with
            ``kernel_capacity=600`` (half the features, half the kernel) and to 0.97 with
            ``t_new_cluster=0.9, t_update_cluster=0.5`` as well, at 3.3 and 2.5 places per
            room against 2.4
            (``README``, "Side views"). Saved maps record it.
        scene_change: similarity threshold of the scene-change gate (see above), or ``None``
            for the paper's behaviour, a new place whenever no place is within
            ``t_new_cluster``. With ``view="sides", kernel_capacity=600`` and 0.25
            (:data:`PANORAMA` before its ``scale=0.75``), 16 simulated tours gave precision
            0.98, NMI 0.863 and 1.4 places per room, against 0.96, 0.70 and 3.3 without the
            gate (``README``, "Scene changes").
        scene_lag: frames between the two frames the gate compares (10 frames are 40 cm of the
            simulator's scripted tours).
        scene_window: frames after a scene change during which a place may open.

    Example:
        >>> import numpy as np
        >>> from placeclust import OnlinePlaceClustering
        >>> rng = np.random.default_rng(0)
        >>> frame = (rng.random((64, 256)) * 255).astype(np.uint8)
        >>> model = OnlinePlaceClustering(features="orb")
        >>> model.learn_predict_one(frame), model.learn_predict_one(frame)
        (0, 0)
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
        """Update the map with one frame (Sec. IV, steps 1-8)."""
        self.learn_predict_one(frame)

    def predict_one(self, frame: np.ndarray) -> int:
        """The place of ``frame`` without changing the map, or :data:`UNKNOWN`."""
        desc = self._describe(frame)
        if desc is None or not self.kernels:
            return UNKNOWN
        best, _ = self._nearest(desc)
        return best.place if best.distance <= self.t_new_cluster else UNKNOWN

    def learn_predict_one(self, frame: np.ndarray) -> int:
        """Learn from ``frame`` and return its place id (step 9), or :data:`UNKNOWN`."""
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
        """
        desc = self._describe(frame)
        if desc is None or not self.kernels:
            return UNKNOWN
        best, _ = self._nearest(desc)
        return self._localized(best.place, best.distance)

    def reset_position(self) -> None:
        """Forget where the robot is (it was carried elsewhere): the next frame is searched in
        the whole map (through the index shortlist) instead of the current place's
        neighbourhood, and the scene-change gate forgets the frames before. The map is kept."""
        self.current = UNKNOWN
        if self._gate is not None:
            self._gate.reset()

    @property
    def n_places(self) -> int:
        return len(self.kernels)

    @property
    def map_full(self) -> bool:
        """Whether the map holds ``max_places`` places and opens no more."""
        return self.max_places is not None and len(self.kernels) >= self.max_places

    # -- map persistence ---------------------------------------------------------------------

    def get_params(self) -> dict[str, object]:
        """The constructor arguments (scikit-learn style), enough to rebuild an empty model."""
        names = inspect.signature(type(self).__init__).parameters
        return {n: getattr(self, n) for n in names if n != "self"}

    def save(self, path: str | os.PathLike, world: str = "") -> None:
        """Write the map atomically (see :func:`placeclust.mapfile.save_map`)."""
        save_map(self, path, world)

    @classmethod
    def load(cls, path: str | os.PathLike, world: str | None = None) -> OnlinePlaceClustering:
        """A recognizer from a map file; ``world`` must match if given (see :mod:`mapfile`)."""
        return load_map(path, world)

    def restore(self, kernels: dict[int, tuple], place_images: dict[int, int],
                edges: list, current: int, frame_shape: list | None) -> None:
        """Replace the map with saved state (used by :func:`placeclust.mapfile.load_map`)."""
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
