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
core too). The binary forest searches on one core: it is fast enough without the split.
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
            ``exact_below`` places. A small tail keeps its brute-force search a small part of a
            query, for a rebuild every ``max_tail`` new places (in the frame that opens the
            place).
        exact_below: maps of fewer places are all tail, searched exactly (24 places are 1,536
            features at most). The 23-place map of the shipped policies stays exact: searched
            through FLANN, the 0.8 m proximity agent's success fell.
        checks: indexed features the SIFT kd-tree compares per query feature, at least one
            leaf (speed/recall trade-off).
        trees: k-medoids trees of the binary index, one leaf searched in each (each tree adds
            a leaf search to a query).

    Examples:
        Three places of eight random features each; a query made of place 2's features votes
        for place 2:

        >>> import numpy as np
        >>> from placeclust.index import PlaceIndex
        >>> from placeclust.matching import normalize
        >>> rng = np.random.default_rng(0)
        >>> places = {p: normalize(rng.normal(size=(8, 16)).astype(np.float32), binary=False)
        ...           for p in range(3)}
        >>> index = PlaceIndex(binary=False, sample=places.__getitem__)
        >>> for p in places:
        ...     index.add(p)
        >>> len(index), index.ranked(places[2][:5]), index.votes(places[1])
        (3, [2], {1: 8})
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

    def merge(self, drop: int, keep: int) -> None:
        """Two places became one: ``drop``'s indexed features vote for ``keep`` from now on,
        and ``keep``'s merged sample joins the tail (see :mod:`placeclust.consolidation`)."""
        self._places.discard(drop)
        self._tail.pop(drop, None)
        self._labels[self._labels == drop] = keep
        self._tail[keep] = self._sample(keep)

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
        from OpenCV's global RNG, so otherwise the index, and with it which places a query
        votes for, would depend on whatever the process had drawn before. The build seeds that
        RNG and afterwards reseeds it from a number drawn from the caller's stream, so a user's
        own ``cv2.setRNGSeed`` still gives them a reproducible sequence.
        """
        data = self._data
        assert data is not None  # rebuild() and _tally() build only over data
        if self.binary:
            # ORB: 4 k-medoids trees, one leaf searched in each. FLANN's hierarchical index with
            # the same parameters searched only the first tree's leaf (its checks were spent
            # there), finding the nearest feature's place less often, more slowly. LSH scans
            # buckets that fill as the map grows (ORB descriptors are far from uniform).
            self._tree = HammingForest(data, trees=self.trees, branching=32, leaf_size=100,
                                       seed=len(data))
            return
        carry_on = np.zeros((1, 1), np.int32)
        # cv2's stubs take only arrays for low and high; OpenCV takes scalars too
        cv2.randu(carry_on, 0, np.iinfo(np.int32).max)  # type: ignore[call-overload]
        cv2.setRNGSeed(len(data))
        try:
            # SIFT: one randomized kd-tree with 16 checks shortlists the best place about as
            # often as more trees and checks, and loop closures stay nearly as fast at any size.
            self._tree = cv2.flann.Index(data, dict(algorithm=_KDTREE, trees=1))
        finally:
            cv2.setRNGSeed(int(carry_on[0, 0]))

    def _search(self, descriptors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest indexed feature of each descriptor and its distance (Euclidean, or
        Hamming as a fraction of the bits); FLANN's work is split over threads."""
        tree = self._tree
        if self.binary:
            assert isinstance(tree, HammingForest)  # _build makes one for binary descriptors
            idx, bits = tree.nearest(descriptors)
            return idx, bits / (8.0 * descriptors.shape[1])
        assert isinstance(tree, cv2.flann.Index)  # ... and a FLANN kd-tree for float ones
        found = split_rows(
            lambda rows: tree.knnSearch(rows, 1, params=dict(checks=self.checks)),
            descriptors, _MIN_SPLIT)
        idx = np.concatenate([i for i, _ in found])[:, 0].astype(np.int64)
        squared = np.concatenate([d for _, d in found])[:, 0].astype(np.float64)
        return idx, np.sqrt(np.maximum(squared, 0))

    def votes(self, descriptors: np.ndarray) -> dict[int, int]:
        """Place -> number of ``descriptors`` whose nearest indexed feature belongs to it.

        Args:
            descriptors: (N, D) features of one image, unit rows if float.

        Returns:
            Votes of the places that got any.
        """
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
