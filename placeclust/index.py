"""Relocalization index: which places does an image look like, without a loop over all kernels.

Each place puts a sample of its heaviest kernel features (``per_place``) into a tree index (a
randomized FLANN kd-tree for float descriptors, the model being RTAB-Map's FLANN vocabulary;
hierarchical k-medoids trees under Hamming distance for binary ones,
:class:`~placeclust.hamming_forest.HammingForest`). New places go to a small brute-force
*tail* first; when the tail holds ``max_tail`` places the whole index is rebuilt ("sealed")
from every place's current top features, so the build cost is amortised and a query costs one
tree search plus a bounded brute-force one, whatever the map size. A query returns votes: for
each image feature, the place owning its nearest indexed feature.

FLANN searches one query feature after another, so the features are split over OpenCV's
threads (:func:`placeclust.threads.split_rows`; ``cv2.setNumThreads(1)`` keeps the index on one
core too). On the 2-core machine of the README a SIFT query of a 500-place map took 4.7 against
2.4 ms. The binary forest answers the same ORB query in ~0.4 ms on one core.
"""

from __future__ import annotations

from collections.abc import Callable

import cv2
import numpy as np

from placeclust.hamming_forest import HammingForest
from placeclust.matching import knn2
from placeclust.threads import split_rows

_KDTREE = 1  # cvflann::flann_algorithm_t
_MIN_SPLIT = 64  # query features per thread below which a split costs more than it saves


class PlaceIndex:
    """Approximate nearest-neighbour votes over every place's top features.

    Args:
        binary: Hamming (k-medoids trees) or Euclidean (kd-tree) descriptors.
        sample: ``sample(place_id) -> descriptors`` gives a place's current top features; it is
            called when a place is added and for every place when the index is rebuilt.
        max_tail: places kept in the brute-force tail before a rebuild, once the map has
            ``exact_below`` places. With 24 the tail of a 500-place map cost half as much as
            the FLANN search (1.9 against 3.8 ms, SIFT); with 8 it stays under ~0.5 ms, for a
            rebuild every 8 new places (at 500 places ~40 ms with SIFT, ~60 ms with ORB, in
            the frame that opens the place).
        exact_below: maps of fewer places are all tail, searched exactly (24 places are 1,536
            features at most). The 23-place map of the shipped policies stays exact: searched
            through FLANN, the 0.8 m proximity agent's success fell from 0.56 to 0.52.
        checks: indexed features the SIFT kd-tree compares per query feature, at least one
            leaf (speed/recall trade-off).
        trees: k-medoids trees of the binary index, one leaf searched in each (~0.2 ms a tree
            for an ORB image at 500 places, in the loop).
    """

    def __init__(self, binary: bool, sample: Callable[[int], np.ndarray], max_tail: int = 8,
                 exact_below: int = 24, checks: int = 16, trees: int = 4) -> None:
        self.binary = binary
        self._sample = sample
        self.max_tail = max_tail
        self.exact_below = exact_below
        self.checks = checks
        self.trees = trees
        self._tree: cv2.flann.Index | HammingForest | None = None
        self._data: np.ndarray | None = None  # what _tree indexes, kept so it can be rebuilt
        self._labels = np.zeros(0, np.int64)
        self._tail: dict[int, np.ndarray] = {}
        self._places: set[int] = set()
        self.n_rebuilds = 0

    def __len__(self) -> int:
        return len(self._places)

    def __getstate__(self) -> dict:
        # a FLANN index cannot be pickled or copied; the tree is rebuilt from _data (the same
        # tree: see _build) on the next query
        return {**self.__dict__, "_tree": None}

    def add(self, place: int) -> None:
        """Index a new place (its sample goes to the tail)."""
        self._places.add(place)
        self._tail[place] = self._sample(place)
        if len(self._tail) >= self.max_tail and len(self._places) >= self.exact_below:
            self.rebuild()

    def rebuild(self) -> None:
        """Rebuild the tree from every place's current top features; empty the tail."""
        self._tail.clear()
        samples = [(p, self._sample(p)) for p in sorted(self._places)]
        samples = [(p, s) for p, s in samples if len(s)]
        self._tree, self._data = None, None
        self._labels = np.zeros(0, np.int64)
        if not samples:
            return
        self._data = np.ascontiguousarray(np.concatenate([s for _, s in samples]))
        self._labels = np.concatenate([np.full(len(s), p, np.int64) for p, s in samples])
        self._build()
        self.n_rebuilds += 1

    def _build(self) -> None:
        """Build the tree over ``_data``, the same tree for the same data in any process.

        Both trees are seeded by the number of indexed features. FLANN draws its kd-tree splits
        from OpenCV's global RNG, so the index, and with it which places a query votes for,
        depended on whatever the process had drawn before (``--agent all`` and ``--agent ppo``
        scored one policy 0.86 and 0.84). The build seeds that RNG and afterwards reseeds it
        from a number drawn from the caller's stream, so a user's own ``cv2.setRNGSeed`` still
        gives them a reproducible sequence.
        """
        # Measured on the 8,000-frame 12-room tour: its map, sealed whole, then 1,000 of its
        # frames relocalized through the index with no current place, against an exhaustive
        # search; and the loop-closure latency of `python -m placeclust.benchmark latency`.
        if self.binary:
            # ORB: 4 k-medoids trees, one leaf searched in each. FLANN's hierarchical index with
            # the same parameters and checks=16 searched only the first tree's leaf (its checks
            # were spent there): on a 500-place map of the benchmark its nearest feature was in
            # the exact nearest's place for 25% of the query features against 51% here, at
            # 1.7-2.2 against 0.4-0.6 ms. On the tour: the best place shortlisted for 978 of the
            # 1,000 frames (FLANN: 978; 2 trees: 974; 3: 985), and 1 revisit missed while mapping (a
            # new place opened where an old one was within the threshold; FLANN: 2; 1 tree: 10;
            # 2 trees: 1). LSH, used before FLANN's trees, scans buckets that fill as the map
            # grows (ORB descriptors are far from uniform): 4.8 ms.
            self._tree = HammingForest(self._data, trees=self.trees, branching=32,
                                       leaf_size=100, seed=len(self._data))
            return
        carry_on = np.zeros((1, 1), np.int32)
        cv2.randu(carry_on, 0, np.iinfo(np.int32).max)
        cv2.setRNGSeed(len(self._data))
        try:
            # SIFT: one randomized kd-tree, 16 checks, found the best place for 997 of the
            # 1,000 frames (4 trees, 32 checks: 999); 500-place loop closures cost 1.1-1.6x
            # the 10-place ones over five runs (4 trees, 32 checks: 1.85x, ~11 ms in the tree).
            self._tree = cv2.flann_Index(self._data, dict(algorithm=_KDTREE, trees=1))
        finally:
            cv2.setRNGSeed(int(carry_on[0, 0]))

    def _search(self, descriptors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest indexed feature of each descriptor and its distance (Euclidean, or
        Hamming as a fraction of the bits); FLANN's work is split over threads."""
        if self.binary:
            idx, bits = self._tree.nearest(descriptors)
            return idx, bits / (8.0 * descriptors.shape[1])
        found = split_rows(
            lambda rows: self._tree.knnSearch(rows, 1, params=dict(checks=self.checks)),
            descriptors, _MIN_SPLIT)
        idx = np.concatenate([i for i, _ in found])[:, 0].astype(np.int64)
        squared = np.concatenate([d for _, d in found])[:, 0].astype(np.float64)
        return idx, np.sqrt(np.maximum(squared, 0))

    def votes(self, descriptors: np.ndarray) -> dict[int, int]:
        """Place -> number of ``descriptors`` whose nearest indexed feature belongs to it."""
        places, counts = self._tally(descriptors)
        return dict(zip(places.tolist(), counts.tolist()))

    def ranked(self, descriptors: np.ndarray) -> list[int]:
        """The places with votes (see :meth:`votes`), most votes first, then the lowest id."""
        places, counts = self._tally(descriptors)
        return places[np.argsort(-counts, kind="stable")].tolist()  # places come in id order

    def _tally(self, descriptors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(places, counts)``: the places with votes in increasing id order, and their votes."""
        n = len(descriptors)
        if n == 0 or not self._places:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        best_d = np.full(n, np.inf)
        best_p = np.full(n, -1, np.int64)
        if self._tree is None and self._data is not None:
            self._build()  # after unpickling or copying
        if self._tree is not None and len(self._labels) >= 2:
            idx, d = self._search(descriptors)
            ok = idx >= 0
            best_d[ok], best_p[ok] = d[ok], self._labels[idx[ok]]
        if self._tail:
            places = list(self._tail)
            data = np.concatenate([self._tail[p] for p in places])
            labels = np.concatenate([np.full(len(self._tail[p]), p) for p in places])
            dist, idx = knn2(descriptors, data, self.binary)
            closer = (idx[:, 0] >= 0) & (dist[:, 0] < best_d)
            best_p[closer] = labels[idx[closer, 0]]
        return np.unique(best_p[best_p >= 0], return_counts=True)
