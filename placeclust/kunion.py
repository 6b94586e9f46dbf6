"""The offline k-adjacent-union place clustering of seed 000, Sec. III.C (Karasfi et al.)."""

from __future__ import annotations

import networkx as nx
import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.spatial.distance import squareform

from placeclust.baselines import describe_all, scene_changes
from placeclust.features import FeatureExtractor
from placeclust.kernel import UnionKernel
from placeclust.matching import dice_eq4, similarity_eq1


class KAdjacentUnion:
    """k-means-like offline clustering with union kernels and neighbour-restricted assignment.

    Steps of Sec. III.C: (1) scene-change detection gives ``k`` contiguous segments; (2) each
    segment's union kernel (:class:`~placeclust.kernel.UnionKernel`); (3-4) kernels whose similarity
    exceeds ``join_similarity`` are joined (Eq. 4 between kernels rather than the paper's Eq. 1:
    every feature has some nearest neighbour, so Eq. 1 barely separates unrelated kernels, while it
    ranks candidates for one image well enough for step 6), and the place graph links clusters that
    follow each other in the sequence; (5-6) frames are reassigned in order, each to the most
    similar (Eq. 1) of the current cluster and its graph neighbours, the current cluster switching
    when two consecutive frames agree on another one; (7) kernels are recomputed; (8) repeat until
    no assignment changes (or ``max_iter``).

    Step 4 does not say how similar is similar. With ``join_similarity`` it is a threshold, and
    joining is transitive (the connected components of the pairs above it), the literal
    reading; on panoramas a few cross-room pairs above it chain every room into one cluster
    (``docs/design.md``). With ``n_clusters`` the most similar clusters are joined instead
    (average linkage on Eq. 4 similarities) until ``n_clusters`` remain, for comparisons at
    matched numbers of places; a sequence with fewer scene changes keeps its ``k``, and steps 5-7
    may still empty a cluster.

    Args:
        features: local feature type.
        join_similarity: Eq. 4 similarity above which two kernels are joined (step 4).
        window: scene-change detector window, frames.
        max_iter: iterations of steps 5-7.
        kernel_stride: every ``kernel_stride``-th frame of a cluster enters its kernel.
        kernel_capacity: features kept per kernel.
        max_features: features per frame.
        normalize: contrast normalization (:class:`~placeclust.features.FeatureExtractor`).
        scale: resize factor before detection (:class:`~placeclust.features.FeatureExtractor`).
        view: ``"full"`` or ``"sides"`` of a panorama (:data:`~placeclust.features.VIEWS`).
        n_clusters: join down to this many clusters instead of by ``join_similarity``.

    Attributes:
        graph: the place graph of the last iteration (step 4).
        n_iter_: iterations of steps 5-7 run by the last :meth:`fit_predict`.

    Examples:
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(4)
        >>> from placeclust.kunion import KAdjacentUnion
        >>> model = KAdjacentUnion(window=2)
        >>> model.fit_predict(frames).tolist()
        [0, 0, 0, 0, 1, 1, 1, 1]
        >>> list(model.graph.edges)
        [(0, 1)]
    """

    def __init__(self, features: str = "sift", join_similarity: float = 0.15, window: int = 15,
                 max_iter: int = 8, kernel_stride: int = 3, kernel_capacity: int = 1200,
                 max_features: int = 500, normalize: str | None = "clahe",
                 scale: float = 1.0, view: str = "full", n_clusters: int | None = None) -> None:
        if n_clusters is not None and n_clusters < 1:
            raise ValueError(f"n_clusters must be a positive number of places, got {n_clusters}")
        self.features = features
        self.join_similarity = join_similarity
        self.window = window
        self.max_iter = max_iter
        self.kernel_stride = kernel_stride
        self.kernel_capacity = kernel_capacity
        self.max_features = max_features
        self.normalize = normalize
        self.scale = scale
        self.view = view
        self.n_clusters = n_clusters
        self.graph = nx.Graph()
        self.n_iter_ = 0

    def fit_predict(self, frames: np.ndarray) -> np.ndarray:
        """Cluster a whole sequence (steps 1-8).

        Args:
            frames: (T, H, W[, C]) images.

        Returns:
            Place id per frame, (T,) int, numbered 0..n_places-1.
        """
        ext = FeatureExtractor(self.features, self.max_features, self.normalize, self.scale,
                               self.view)
        descs = describe_all(frames, ext)
        bounds = [0, *scene_changes(descs, ext.binary, self.window).tolist(), len(descs)]
        labels = np.zeros(len(descs), np.int64)
        for i, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
            labels[a:b] = i
        kernels = self._kernels(descs, labels, ext.binary)
        labels = self._join(kernels, labels, ext.binary)
        for iteration in range(1, self.max_iter + 1):
            self.n_iter_ = iteration
            self.graph = self._place_graph(labels)
            kernels = self._kernels(descs, labels, ext.binary)
            new = self._assign(descs, labels, kernels, ext.binary)
            if np.array_equal(new, labels):
                break
            labels = new
        _, labels = np.unique(labels, return_inverse=True)
        return labels.astype(np.int64)

    def _kernels(self, descs: list[np.ndarray], labels: np.ndarray, binary: bool
                 ) -> dict[int, UnionKernel]:
        kernels: dict[int, UnionKernel] = {}
        for c in np.unique(labels).tolist():
            strided = np.nonzero(labels == c)[0][:: self.kernel_stride]
            members = [m for m in strided if len(descs[m])]
            if not members:
                continue
            k = UnionKernel(descs[members[0]], binary, self.kernel_capacity)
            for m in members[1:]:
                k.update(descs[m])
            kernels[c] = k
        return kernels

    def _join(self, kernels: dict[int, UnionKernel], labels: np.ndarray, binary: bool
              ) -> np.ndarray:
        """Steps 3-4: merge clusters whose kernels are similar (Eq. 4)."""
        ids = sorted(kernels)
        sim = np.eye(len(ids))
        for i, a in enumerate(ids):
            for j in range(i + 1, len(ids)):
                ka, kb = kernels[a], kernels[ids[j]]
                sim[i, j] = sim[j, i] = dice_eq4(len(kb.match(ka.descriptors)[0]), len(kb),
                                                 len(ka))
        out = labels.copy()
        for group in self._groups(sim):
            members = [ids[i] for i in group]
            out[np.isin(labels, members)] = min(members)
        return out

    def _groups(self, sim: np.ndarray) -> list[list[int]]:
        """Indices of the kernels to join into one cluster, group by group."""
        if self.n_clusters is None:
            g = nx.Graph()
            g.add_nodes_from(range(len(sim)))
            g.add_edges_from(zip(*np.nonzero(np.triu(sim > self.join_similarity, 1))))
            return [sorted(c) for c in nx.connected_components(g)]
        if len(sim) <= self.n_clusters:
            return [[i] for i in range(len(sim))]
        tree = linkage(squareform(1.0 - sim, checks=False), "average")
        cut = fcluster(tree, self.n_clusters, "maxclust")
        return [np.flatnonzero(cut == c).tolist() for c in np.unique(cut)]

    @staticmethod
    def _place_graph(labels: np.ndarray) -> nx.Graph:
        g = nx.Graph()
        g.add_nodes_from(np.unique(labels).tolist())
        change = np.nonzero(labels[1:] != labels[:-1])[0]
        g.add_edges_from((int(labels[i]), int(labels[i + 1])) for i in change)
        return g

    def _assign(self, descs: list[np.ndarray], labels: np.ndarray,
                kernels: dict[int, UnionKernel], binary: bool) -> np.ndarray:
        """Steps 5-6: sequential, neighbour-restricted nearest-kernel assignment."""
        current = int(labels[0])
        new = labels.copy()
        for j, d in enumerate(descs):
            cands = [c for c in [current, *self.graph.neighbors(current)] if c in kernels]
            if not cands or not len(d):
                new[j] = current
                continue
            new[j] = max(cands, key=lambda c: similarity_eq1(d, kernels[c].descriptors, binary))
            if j and new[j] == new[j - 1] != current:
                current = int(new[j])
        return new
