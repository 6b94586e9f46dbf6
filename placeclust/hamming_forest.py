"""Approximate nearest binary descriptor: hierarchical k-medoids trees under Hamming distance.

This is FLANN's hierarchical clustering index (Muja & Lowe, "Fast Matching of Binary
Features", CRV 2012), compiled with numba, for :class:`~placeclust.index.PlaceIndex` with ORB
and AKAZE. Each tree splits its descriptors around ``branching`` randomly chosen descriptors
(the medoids, no iteration), recursively, until a node holds at most ``leaf_size``; a query
descends each tree to the nearest medoid at every level and compares the descriptors of the
leaf it reaches. Every tree is searched: FLANN's own, with 4 trees and ``checks=16``, spent its
checks in the first tree's leaf and searched no other, one query at a time through a priority
queue, so it was slower and found the true nearest less often.

The trees are drawn from a seed, so the same descriptors and seed give the same index in any
process, whatever else drew random numbers before.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from placeclust.hamming import _NONE, _popcount, as_words

_TREE_SEEDS = 1 << 16  # trees of one seed: tree t is drawn from seed * _TREE_SEEDS + t


@njit(inline="always")
def _distance(a: np.ndarray, b: np.ndarray) -> int:
    d = 0
    for k in range(a.shape[0]):
        d += _popcount(a[k] ^ b[k])
    return d


@njit(inline="always")
def _splitmix64(state: np.uint64) -> tuple[np.uint64, np.uint64]:
    # a tiny seeded generator of its own, so that building never touches a global random state
    state = state + np.uint64(0x9E3779B97F4A7C15)
    z = state
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return state, z ^ (z >> np.uint64(31))


@njit(cache=True)
def _build_tree(words: np.ndarray, branching: int, leaf_size: int, seed: int):
    """One tree over the rows of ``words``: ``(perm, first_child, n_children, center, start,
    stop)``. Node 0 is the root; a node's children are ``first_child .. first_child +
    n_children - 1`` (``first_child`` -1 for a leaf); ``center`` is the data row of a node's
    medoid; a node holds the data rows ``perm[start:stop]``."""
    n = words.shape[0]
    cap = 2 * n + 1  # every split makes at least two non-empty children: fewer nodes than 2n
    first_child = np.full(cap, -1, np.int64)
    n_children = np.zeros(cap, np.int64)
    center = np.full(cap, -1, np.int64)
    start = np.zeros(cap, np.int64)
    stop = np.zeros(cap, np.int64)
    perm = np.arange(n)
    assign = np.empty(n, np.int64)
    buffer = np.empty(n, np.int64)
    counts = np.zeros(branching, np.int64)
    medoids = np.empty(branching, np.int64)
    stack = np.empty(cap, np.int64)
    stop[0], n_nodes, depth = n, 1, 1
    stack[0] = 0
    state = np.uint64(seed)
    while depth:
        depth -= 1
        node = stack[depth]
        s, e = start[node], stop[node]
        m = e - s
        if m <= leaf_size:
            continue
        k = min(branching, m)
        for c in range(k):  # k distinct medoids: a partial Fisher-Yates shuffle of the node
            state, r = _splitmix64(state)
            j = s + c + np.int64(r % np.uint64(m - c))
            perm[s + c], perm[j] = perm[j], perm[s + c]
            medoids[c] = perm[s + c]
        counts[:k] = 0
        for i in range(s, e):
            row = words[perm[i]]
            best, nearest = _NONE, 0
            for c in range(k):
                d = _distance(row, words[medoids[c]])
                if d < best:
                    best, nearest = d, c
            assign[i] = nearest
            counts[nearest] += 1
        if counts[:k].max() == m:  # identical descriptors cannot be split: keep them a leaf
            continue
        offset = s
        first_child[node] = n_nodes
        for c in range(k):
            if counts[c] == 0:  # a medoid equal to an earlier one loses all its rows to it
                continue
            start[n_nodes], stop[n_nodes], center[n_nodes] = offset, offset + counts[c], medoids[c]
            stack[depth] = n_nodes
            depth += 1
            n_nodes += 1
            n_children[node] += 1
            counts[c] = offset  # now where child c's rows go next
            offset = stop[n_nodes - 1]
        for i in range(s, e):  # stable counting sort of the node's rows by child
            buffer[counts[assign[i]]] = perm[i]
            counts[assign[i]] += 1
        perm[s:e] = buffer[s:e]
    return (perm, first_child[:n_nodes], n_children[:n_nodes], center[:n_nodes],
            start[:n_nodes], stop[:n_nodes])


@njit(nogil=True, cache=True)
def _nearest(query, leaf_words, center_words, roots, perm, first_child, n_children, start, stop):
    n = query.shape[0]
    dist = np.empty(n, np.int64)
    idx = np.empty(n, np.int64)
    for i in range(n):
        q = query[i]
        best, found = _NONE, np.int64(-1)
        for root in roots:
            node = root
            while first_child[node] >= 0:  # down to the nearest medoid at every level
                nearest, near = first_child[node], _NONE
                for c in range(first_child[node], first_child[node] + n_children[node]):
                    d = _distance(q, center_words[c])
                    if d < near:
                        near, nearest = d, c
                node = nearest
            for j in range(start[node], stop[node]):
                d = _distance(q, leaf_words[j])
                if d < best or (d == best and perm[j] < found):  # ties: the lowest row, any tree
                    best, found = d, perm[j]
        dist[i], idx[i] = best, found
    return dist, idx


class HammingForest:
    """Approximate nearest neighbours of binary descriptors among fixed ``descriptors``.

    Args:
        descriptors: (n, bytes) uint8, n >= 1, the indexed descriptors (ORB: 32 bytes).
        trees: independent trees, each searched; more find the true nearest more often.
        branching: medoids per node (FLANN's ``branching``).
        leaf_size: most descriptors in a leaf (FLANN's ``leaf_max_size``).
        seed: draws the medoids, a non-negative integer; the same descriptors and seed give the
            same trees, and a forest of more trees holds those of fewer (tree ``t`` is drawn
            from ``seed`` and ``t`` alone), so it finds each nearest neighbour at least as well.

    Raises:
        ValueError: ``descriptors`` is empty, or a parameter is out of range.

    Examples:
        >>> import numpy as np
        >>> from placeclust.hamming_forest import HammingForest
        >>> data = np.random.default_rng(0).integers(0, 256, (100, 32), dtype=np.uint8)
        >>> forest = HammingForest(data, trees=2, leaf_size=10, seed=0)
        >>> idx, dist = forest.nearest(data[[5, 9]])
        >>> len(forest), idx.tolist(), dist.tolist()
        (100, [5, 9], [0, 0])
    """

    def __init__(self, descriptors: np.ndarray, trees: int = 4, branching: int = 32,
                 leaf_size: int = 100, seed: int = 0) -> None:
        if len(descriptors) == 0:
            raise ValueError("cannot index an empty set of descriptors")
        if trees < 1 or branching < 2 or leaf_size < 1 or seed < 0:
            raise ValueError(f"need trees >= 1, branching >= 2, leaf_size >= 1 and seed >= 0, "
                             f"got {trees}, {branching}, {leaf_size} and {seed}")
        words = np.ascontiguousarray(as_words(descriptors))
        self._nbytes = descriptors.shape[1]
        parts = [_build_tree(words, branching, leaf_size, (_TREE_SEEDS * seed + t) % 2**63)
                 for t in range(trees)]
        # the trees side by side in one set of arrays: node and row numbers offset per tree
        nodes = np.cumsum([0] + [len(p[1]) for p in parts])
        rows = len(words) * np.arange(trees)
        self._roots = nodes[:-1].astype(np.int64)
        self._perm = np.concatenate([p[0] for p in parts])
        self._first_child = np.concatenate(
            [np.where(p[1] >= 0, p[1] + o, -1) for p, o in zip(parts, nodes)])
        self._n_children = np.concatenate([p[2] for p in parts])
        self._start = np.concatenate([p[4] + r for p, r in zip(parts, rows)])
        self._stop = np.concatenate([p[5] + r for p, r in zip(parts, rows)])
        # the words in search order (copies), so that a query reads leaves and medoids in
        # sequence; a root has no medoid and its row is never read
        self._leaf_words = words[self._perm]
        self._center_words = words[np.maximum(np.concatenate([p[3] for p in parts]), 0)]

    def __len__(self) -> int:
        return len(self._perm) // len(self._roots)

    def nearest(self, descriptors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The approximately nearest indexed descriptor of each of ``descriptors``.

        Args:
            descriptors: (m, bytes) uint8, as wide as the indexed ones.

        Returns:
            ``(idx, dist)``, both (m,) int64: the row among the indexed descriptors and its
            Hamming distance in bits. Equal distances give the lowest row.

        Raises:
            ValueError: the query rows are not as wide as the indexed ones.
        """
        if descriptors.ndim != 2 or descriptors.shape[1] != self._nbytes:
            raise ValueError(f"query descriptors must be (m, {self._nbytes}) uint8, got "
                             f"{descriptors.dtype} of shape {descriptors.shape}")
        query = np.ascontiguousarray(as_words(descriptors))
        dist, idx = _nearest(query, self._leaf_words, self._center_words, self._roots,
                             self._perm, self._first_child, self._n_children, self._start,
                             self._stop)
        return idx, dist
