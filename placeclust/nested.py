"""Nested two-level topological mapper: seed 001 (Elgayar, Salem, Roushdy), Sec. 4.

A global level of *locations* (tracked SIFT points, Sec. 4.4-4.5) and, inside each location, a
local level of *views* (Haar wavelet signatures, Sec. 3.2 and 4.6): :class:`NestedMapper`.
"""

from __future__ import annotations

from typing import ClassVar

import networkx as nx
import numpy as np

from placeclust.features import FeatureExtractor
from placeclust.frames import check_size, to_gray
from placeclust.index import PlaceIndex
from placeclust.matching import normalize, ratio_matches
from placeclust.wavelet import haar_signature, signature_similarity

UNKNOWN = -1


class Location:
    """A global node: tracked SIFT points with their missed counts ``C`` (Sec. 4.4)."""

    def __init__(self, descriptors: np.ndarray) -> None:
        self.descriptors = descriptors
        self.missed = np.zeros(len(descriptors), np.int64)
        self.views: list[np.ndarray] = []  # one Haar signature per view (the local level)
        self.n_keyframes = 0

    def track(self, descriptors: np.ndarray, img_idx: np.ndarray, loc_idx: np.ndarray,
              max_missed: int, capacity: int) -> None:
        """Feature tracking maintenance and termination (Sec. 4.4) for one assigned key frame.

        Matched points become active (``C = 0``), unmatched points of the location are missed
        once more (``C += 1``) and terminated at ``C >= max_missed``; the key frame's unmatched
        points join with ``C = 0``. ``capacity`` bounds the node, oldest-missed first out.
        """
        self.missed += 1
        self.missed[loc_idx] = 0
        new = np.setdiff1d(np.arange(len(descriptors)), img_idx)
        self.descriptors = np.concatenate([self.descriptors, descriptors[new]])
        self.missed = np.concatenate([self.missed, np.zeros(len(new), np.int64)])
        keep = self.missed < max_missed
        if keep.sum() > capacity:
            keep &= self.missed <= np.sort(self.missed[keep])[capacity - 1]
            keep[np.nonzero(keep)[0][capacity:]] = False
        self.descriptors, self.missed = self.descriptors[keep], self.missed[keep]


class NestedMapper:
    """Two-level topological SLAM: locations of tracked SIFT points, views by wavelet signature.

    Per frame (Sec. 4.2-4.5): a frame is a *key frame* when its mean absolute grey-level
    difference to the last key frame exceeds ``keyframe_threshold`` (0.08, on [0, 1] pixels);
    other frames keep the last localization. A key frame's SIFT points are matched with every
    location's points; the ``rank`` best locations are ranked by matches (found through a
    :class:`~placeclust.index.PlaceIndex` shortlist, so the cost does not grow with the map),
    and the frame joins the best one if it has at least ``min_matches`` (25) matches, else opens
    a new location linked to the last visited one. Inside the location, the frame's level-4
    Haar signature is compared with the location's views: similarity at least
    ``view_similarity`` (0.96) localises it in that view, else it opens a new view linked to the
    last visited view.

    The paper leaves the termination limit ``N`` open; ``max_missed`` = 8 key frames here.

    A location holds the points of its last ``max_missed`` key frames, so it follows the robot,
    and only a key frame sharing fewer than ``min_matches`` points with it opens another. In the
    simulator's buildings that never happens at a door, with the panorama or the forward camera:
    the next room is in view before the robot enters it, and the default keeps one location
    (``python -m envs.commands.seed001``, ``docs/design.md``). :meth:`localize_one` relocalizes
    on the map without changing it.

    Args:
        features: local features (the paper uses SIFT).
        max_features: features per frame.
        keyframe_threshold: "Next Increase" threshold on the mean absolute difference.
        min_matches: matches needed to recognise a location.
        rank: best locations ranked per key frame.
        view_similarity: wavelet signature similarity needed to recognise a view.
        wavelet_level: Haar decomposition level (4 in the paper).
        max_missed: ``N``, misses before a point's tracking is terminated.
        location_capacity: the most points a location keeps.
        ratio: Lowe's ratio for correspondences.
        normalize: contrast normalization (:class:`~placeclust.features.FeatureExtractor`).
        scale: resize factor before detection (:class:`~placeclust.features.FeatureExtractor`).

    Attributes:
        last_was_keyframe: whether the last frame was a key frame.
        last_matches: the last key frame's matches with the best location it was compared with.

    Examples:
        Four jittered views of one synthetic place, then four of another: only the first view
        of each differs enough from the last key frame to be a key frame, and the others keep
        its localization:

        >>> from placeclust.nested import NestedMapper
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(4)
        >>> mapper = NestedMapper()
        >>> places, keyframes = [], []
        >>> for f in frames:
        ...     places.append(mapper.localize(f))
        ...     keyframes.append(bool(mapper.last_was_keyframe))
        >>> places
        [(0, 0), (0, 0), (0, 0), (0, 0), (1, 0), (1, 0), (1, 0), (1, 0)]
        >>> keyframes
        [True, False, False, False, True, False, False, False]
        >>> mapper.n_places, list(mapper.graph.edges)
        (2, [(0, 1)])
        >>> mapper.predict_one(frames[0])
        0
    """

    #: the camera it was built for (Sec. 5: a forward camera); the closed loop
    #: (``envs.tasks.recognizers``) renders it, for a ``package.module:Class`` too
    camera: ClassVar[str] = "forward"

    def __init__(
        self,
        features: str = "sift",
        max_features: int = 500,
        keyframe_threshold: float = 0.08,
        min_matches: int = 25,
        rank: int = 3,
        view_similarity: float = 0.96,
        wavelet_level: int = 4,
        max_missed: int = 8,
        location_capacity: int = 1500,
        ratio: float = 0.8,
        normalize: str | None = "clahe",
        scale: float = 1.0,
    ) -> None:
        self.features = features
        self.max_features = max_features
        self.keyframe_threshold = keyframe_threshold
        self.min_matches = min_matches
        self.rank = rank
        self.view_similarity = view_similarity
        self.wavelet_level = wavelet_level
        self.max_missed = max_missed
        self.location_capacity = location_capacity
        self.ratio = ratio
        self.normalize = normalize
        self.scale = scale
        self._extractor = FeatureExtractor(features, max_features, normalize, scale)
        self.locations: dict[int, Location] = {}
        self.graph = nx.Graph()  # level 1: locations
        self.view_graphs: dict[int, nx.Graph] = {}  # level 2: views of each location
        self.current: tuple[int, int] = (UNKNOWN, UNKNOWN)
        self.last_was_keyframe = False
        self.last_matches = 0  # matches of the last key frame with its best location
        self.frame_shape: tuple[int, int] | None = None
        self._last_key: np.ndarray | None = None
        self._index = PlaceIndex(self._extractor.binary, self._index_sample)

    @property
    def n_places(self) -> int:
        """The number of locations (the global level)."""
        return len(self.locations)

    def learn_one(self, frame: np.ndarray) -> None:
        """Update the two-level map with one frame."""
        self.localize(frame)

    def learn_predict_one(self, frame: np.ndarray) -> int:
        """Learn from ``frame`` and return its location id (the global level).

        Args:
            frame: an image (see :func:`~placeclust.frames.to_gray`).

        Returns:
            The location, or -1 before the first key frame with features.
        """
        return self.localize(frame)[0]

    def predict_one(self, frame: np.ndarray) -> int:
        """The best location of ``frame`` without changing the map.

        Args:
            frame: an image (see :func:`~placeclust.frames.to_gray`).

        Returns:
            The location with most matches if they are at least ``min_matches``, else -1.
        """
        desc = self._describe(to_gray(frame))
        if len(desc) == 0 or not self.locations:
            return UNKNOWN
        loc, n = self._best_location(desc)
        return loc if n >= self.min_matches else UNKNOWN

    def localize_one(self, frame: np.ndarray) -> int:
        """Relocalize on a fixed map (Sec. 4.6): the location of ``frame``, or -1.

        The key-frame gate runs as when mapping, and a non-key frame keeps the last answer. A key
        frame goes to the location with most matches among the ranked ones if it has at least
        ``min_matches``, else -1; the map is never changed: no point is tracked, added or
        terminated, and no location, view or edge is opened. This is how a second drive is
        scored against the map of the first (``python -m envs.commands.seed001``).

        Args:
            frame: an image (see :func:`~placeclust.frames.to_gray`), the size of the map's
                frames.

        Returns:
            The location, or -1 (no location has ``min_matches`` matches, or no map yet).

        Examples:
            >>> from placeclust.nested import NestedMapper
            >>> from placeclust.synthetic import places
            >>> frames, truth = places(4)
            >>> mapper = NestedMapper()
            >>> [mapper.learn_predict_one(f) for f in frames][::4]
            [0, 1]
            >>> mapper.reset_position()
            >>> [mapper.localize_one(f) for f in frames[::-1]][::4], mapper.n_places
            ([1, 0], 2)
        """
        key = self._key_frame(frame)
        if key is None:
            return self.current[0]
        desc = key[1]
        if len(desc) < 2 or not self.locations:
            self.current, self.last_matches = (UNKNOWN, UNKNOWN), 0
            return UNKNOWN
        loc, n = self._best_location(desc)
        self.last_matches = n
        self.current = (loc, UNKNOWN) if n >= self.min_matches else (UNKNOWN, UNKNOWN)
        return self.current[0]

    def rank_places(self, frame: np.ndarray, n: int = 10) -> list[int]:
        """The ``n`` locations with most ratio-test matches to ``frame``, best first, among the
        ``rank`` the global index ranks first; the map and the current location are unchanged.
        Unlike :meth:`localize_one` no key-frame gate and no ``min_matches``: every frame with
        features gets an answer (placenav-v5's goal pictures).

        Args:
            frame: an image, the size of the map's frames.
            n: how many locations.

        Returns:
            Up to ``n`` location ids (none for a featureless frame or an empty map).

        Examples:
            >>> from placeclust.nested import NestedMapper
            >>> from placeclust.synthetic import places
            >>> frames, truth = places(4)
            >>> mapper = NestedMapper()
            >>> _ = [mapper.learn_predict_one(f) for f in frames]
            >>> mapper.rank_places(frames[0], n=1), mapper.rank_places(frames[-1], n=1)
            ([0], [1])
        """
        gray = to_gray(frame)
        check_size(gray, self.frame_shape)
        desc = self._describe(gray)
        if len(desc) < 2 or not self.locations:
            return []
        counts = [(len(self._matches(p, desc)[0]), p) for p in self._index.ranked(desc)[
            : self.rank]]
        return [p for _, p in sorted(counts, key=lambda c: (-c[0], c[1]))[:n]]

    def reset_position(self) -> None:
        """Forget where the robot is (a new drive starts); the map is kept.

        The next frame is a key frame, and is searched among the ranked locations only.
        """
        self.current = (UNKNOWN, UNKNOWN)
        self._last_key = None

    def localize(self, frame: np.ndarray) -> tuple[int, int]:
        """Two-level localization (Sec. 4.6) of ``frame``, learning as it goes.

        Args:
            frame: an image (see :func:`~placeclust.frames.to_gray`), the size of the map's
                earlier frames.

        Returns:
            ``(location, view)``; non-key frames return the last localization, a featureless
            key frame ``(UNKNOWN, UNKNOWN)`` and leaves the map as it was.

        Raises:
            ValueError: ``frame`` is not a valid image or differs in size from earlier frames.
        """
        key = self._key_frame(frame)
        if key is None:
            return self.current
        gray, desc = key
        if len(desc) < 2:  # featureless (a blank wall, a black frame): nothing to recognise
            return UNKNOWN, UNKNOWN
        loc = self._locate(desc)
        view = self._place_view(loc, haar_signature(gray, self.wavelet_level))
        self.current = (loc, view)
        return self.current

    # -- global level ---------------------------------------------------------------------------

    def _key_frame(self, frame: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """``(grey image, descriptors)`` when ``frame`` is a key frame (Sec. 4.2), else None."""
        gray = to_gray(frame)
        self.frame_shape = check_size(gray, self.frame_shape)
        self.last_was_keyframe = self._is_keyframe(gray)
        if not self.last_was_keyframe:
            return None
        self._last_key = gray
        return gray, self._describe(gray)

    def _is_keyframe(self, gray: np.ndarray) -> bool:
        if self._last_key is None:
            return True
        diff = np.abs(gray.astype(np.int16) - self._last_key.astype(np.int16)).mean() / 255.0
        return diff > self.keyframe_threshold

    def _describe(self, gray: np.ndarray) -> np.ndarray:
        feats = self._extractor.extract(gray)
        return normalize(feats.descriptors, feats.binary)

    def _matches(self, loc: int, desc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return ratio_matches(desc, self.locations[loc].descriptors, self._extractor.binary,
                             self.ratio)

    def _best_location(self, desc: np.ndarray) -> tuple[int, int]:
        last = self.current[0]
        ranked = self._index.ranked(desc)[: self.rank]
        if last != UNKNOWN and last not in ranked:
            ranked.append(last)
        counts = [(len(self._matches(p, desc)[0]), p) for p in ranked]
        n, loc = max(counts, default=(0, UNKNOWN))
        return loc, n

    def _locate(self, desc: np.ndarray) -> int:
        loc, n = self._best_location(desc) if self.locations else (UNKNOWN, 0)
        self.last_matches = n
        last = self.current[0]
        if n < self.min_matches:
            loc = len(self.locations)
            self.locations[loc] = Location(desc.copy())
            self.graph.add_node(loc)
            self.view_graphs[loc] = nx.Graph()
            self._index.add(loc)
        else:
            img_idx, loc_idx = self._matches(loc, desc)
            self.locations[loc].track(desc, img_idx, loc_idx, self.max_missed,
                                      self.location_capacity)
        if last != UNKNOWN and last != loc:
            self.graph.add_edge(last, loc)
        self.locations[loc].n_keyframes += 1
        return loc

    def _index_sample(self, loc: int) -> np.ndarray:
        location = self.locations[loc]
        return location.descriptors[np.argsort(location.missed, kind="stable")[:64]]

    # -- local level -----------------------------------------------------------------------------

    def _place_view(self, loc: int, signature: np.ndarray) -> int:
        views = self.locations[loc].views
        sims = [signature_similarity(signature, v) for v in views]
        last_loc, last_view = self.current
        if sims and max(sims) >= self.view_similarity:
            view = int(np.argmax(sims))
        else:
            view = len(views)
            views.append(signature)
            self.view_graphs[loc].add_node(view)
        if last_loc == loc and last_view not in (UNKNOWN, view):
            self.view_graphs[loc].add_edge(last_view, view)
        return view
