"""Online sequential place clustering: seed 000 (Tang, Hamami, Karasfi, Nakhaeinia), Sec. IV.

:class:`OnlinePlaceClustering` turns a stream of frames into a topological map of places, one
frame at a time; :data:`~placeclust.presets.PANORAMA` holds its settings for 360° panoramas.
"""

from __future__ import annotations

from typing import NamedTuple

import networkx as nx
import numpy as np

from placeclust.consolidation import Rehearsal
from placeclust.features import FeatureExtractor
from placeclust.frames import check_size, to_gray
from placeclust.index import PlaceIndex
from placeclust.kernel import UnionKernel
from placeclust.matching import dice_eq4, normalize
from placeclust.persistence import MapPersistence
from placeclust.presets import PANORAMA, PRESETS  # noqa: F401 (the package exports them)
from placeclust.scene_change import SceneChangeGate

UNKNOWN = -1


class _Compared(NamedTuple):
    """One place compared with a frame: Eq. 4 as a distance, and the correspondences."""

    place: int
    distance: float
    matches: tuple[np.ndarray, np.ndarray]


_NONE = _Compared(UNKNOWN, np.inf, (np.zeros(0, np.int64), np.zeros(0, np.int64)))

class OnlinePlaceClustering(MapPersistence):
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
    - **Consolidation** (``consolidate``, off by default). A young place whose frames keep
      matching an older place is merged into it (:mod:`placeclust.consolidation`), which
      repairs the places opened when a room is seen anew; :meth:`resolve` gives any id
      returned before a merge the place that holds it now.
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
            ``envs.commands.longrun``). Consolidation never reuses a merged id, so with it ids can
            reach beyond ``max_places - 1``.
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
        consolidate: distance (``1 - Eq. 4``) within which a young place's frames match an
            older place, or ``None`` for the paper's behaviour, no merging. See
            :mod:`placeclust.consolidation`; :data:`~placeclust.presets.PANORAMA` uses 0.85
            (``t_new_cluster``: the frames would have joined that place). The three settings
            below were chosen with it on the ``val`` split (``docs/design.md``).
        consolidate_probation: images a place's kernel takes in while it may still be merged.
        consolidate_streak: frames in a row that must match the same older place to merge.
        consolidate_ratio: a match counts only if its Eq. 4 similarity is at least this many
            times the runner-up place's (Lowe's ratio test, for places), or ``None`` for no
            test.

    Raises:
        ValueError: unless ``0 <= t_update_cluster < t_new_cluster < 1``, or if ``max_places``
            is below 1, ``consolidate_ratio`` below 1, or a ``consolidate`` setting is out of
            range (:class:`~placeclust.consolidation.Rehearsal`).

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
        consolidate: float | None = None,
        consolidate_probation: int = 60,
        consolidate_streak: int = 2,
        consolidate_ratio: float | None = 1.5,
    ) -> None:
        if not 0.0 <= t_update_cluster < t_new_cluster < 1.0:
            raise ValueError(
                "need 0 <= t_update_cluster < t_new_cluster < 1 (Sec. IV), got "
                f"t_update_cluster={t_update_cluster}, t_new_cluster={t_new_cluster}")
        if max_places is not None and max_places < 1:
            raise ValueError(f"max_places must be at least 1 or None, got {max_places}")
        if consolidate_ratio is not None and not consolidate_ratio >= 1.0:
            raise ValueError("consolidate_ratio must be at least 1 (the best place against the "
                             f"runner-up) or None, got {consolidate_ratio}")
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
        self.consolidate = consolidate
        self.consolidate_probation = consolidate_probation
        self.consolidate_streak = consolidate_streak
        self.consolidate_ratio = consolidate_ratio
        self._rehearsal = None if consolidate is None else Rehearsal(
            consolidate, consolidate_probation, consolidate_streak)
        #: ids merged away by consolidation -> the place that holds them now
        self.merged: dict[int, int] = {}
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
            return self._consolidated(desc, self._absorb(here.place, desc, here.matches))
        if best.place != self.current and self.current != UNKNOWN:
            # a loop closure when they were not adjacent
            self.graph.add_edge(self.current, best.place)
        if best.distance > self.t_update_cluster:
            return self._consolidated(desc, self._absorb(best.place, desc, best.matches))
        self.current = best.place
        return self._consolidated(desc, best.place)

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

    def rank_places(self, frame: np.ndarray, n: int = 10) -> list[int]:
        """The ``n`` places nearest ``frame`` by Eq. 4's distance, best first; the map and the
        current place are unchanged. Every place is compared (recall at N for a data set's
        queries, not tracking), so the cost grows with the map.

        Args:
            frame: an image, as for :meth:`learn_one`.
            n: how many places.

        Returns:
            Up to ``n`` place ids (none for a featureless frame).
        """
        desc = self._describe(frame)
        if desc is None:
            return []
        compared = sorted((self._compare(p, desc) for p in self.kernels),
                          key=lambda c: c.distance)
        return [c.place for c in compared[:n]]

    def reset_position(self) -> None:
        """Forget where the robot is (it was carried elsewhere); the map is kept.

        The next frame is searched in the whole map (through the index shortlist) instead of
        the current place's neighbourhood, and the scene-change gate forgets the frames before.
        """
        self.current = UNKNOWN
        if self._gate is not None:
            self._gate.reset()
        if self._rehearsal is not None:
            self._rehearsal.reset()

    def resolve(self, places: np.ndarray) -> np.ndarray:
        """The place that holds each id now: ids that consolidation merged away become the
        place they were merged into; other ids (and :data:`UNKNOWN`) stay as they are.

        Args:
            places: ids this recognizer returned, any shape.

        Returns:
            An int64 array of the same shape.
        """
        ids = np.asarray(places, np.int64)
        out = ids.copy()
        for drop, keep in self.merged.items():
            out[ids == drop] = keep
        return out

    @property
    def n_places(self) -> int:
        """The number of places in the map."""
        return len(self.kernels)

    @property
    def map_full(self) -> bool:
        """Whether the map holds ``max_places`` places and opens no more."""
        return self.max_places is not None and len(self.kernels) >= self.max_places

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

    def _consolidated(self, desc: np.ndarray, place: int) -> int:
        """``place``, or the older place it was just merged into (see
        :mod:`placeclust.consolidation`): on probation, the frame is also compared with the
        older place the index votes for most (and the runner-up, for ``consolidate_ratio``)."""
        if self._rehearsal is None or not self._rehearsal.on_probation(
                self.graph.nodes[place]["n_images"]):
            return place
        ratio = self.consolidate_ratio
        # only into an older place: a settled place is never merged into a young one
        others = [p for p in self._index.ranked(desc) if p < place][: 1 if ratio is None else 2]
        if not others:
            return place
        best, *runner_up = sorted((self._compare(p, desc) for p in others),
                                  key=lambda c: c.distance)
        distance = best.distance
        # runner_up is empty without a ratio test
        if runner_up and ratio is not None and (
                1.0 - distance < ratio * (1.0 - runner_up[0].distance)):
            distance = np.inf  # not distinctly the best: a doorway or a look-alike room
        if not self._rehearsal.observe(place, best.place, distance):
            return place
        self._merge(best.place, place)
        return best.place

    def _merge(self, keep: int, drop: int) -> None:
        """Make ``drop`` part of ``keep``: kernel, frames, edges, index votes and id."""
        self.kernels[keep].merge(self.kernels.pop(drop))
        self.graph.nodes[keep]["n_images"] += self.graph.nodes[drop]["n_images"]
        self.graph.add_edges_from((keep, p) for p in self.graph.neighbors(drop) if p != keep)
        self.graph.remove_node(drop)
        self._index.merge(drop, keep)
        self.merged = {d: keep if k == drop else k for d, k in self.merged.items()}
        self.merged[drop] = keep
        if self.current == drop:
            self.current = keep

    def _new_place(self, desc: np.ndarray) -> int:
        place = len(self.kernels) + len(self.merged)  # merged ids are never reused
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
