"""The reference a practitioner would try first: river's streaming clusterers on one global
descriptor per frame.

No local features and no graph search: each frame becomes one vector, seed 001's Haar wavelet
signature (Sec. 4.4) scaled to unit length, and a streaming clusterer of river assigns it to a
cluster, which is its place. It runs through the same runner, metrics and benchmark as the
seeds' recognizers (``placeclust cluster --algo stream``), so their extra machinery can be
judged against it.

Examples:
    >>> from placeclust.stream import StreamPlaces
    >>> from placeclust.synthetic import places
    >>> frames, truth = places(3)
    >>> model = StreamPlaces()
    >>> [model.learn_predict_one(f) for f in frames]
    [0, 0, 0, 1, 1, 1]
    >>> model.n_places, sorted(model.graph.edges)
    (2, [(0, 1)])
"""

from __future__ import annotations

from collections.abc import Hashable
from typing import TYPE_CHECKING

import networkx as nx
import numpy as np

from placeclust.frames import check_size, to_gray
from placeclust.online import UNKNOWN
from placeclust.wavelet import haar_signature

if TYPE_CHECKING:
    from river.base import Clusterer

CLUSTERERS = ("dbstream", "streamkmeans")


class StreamPlaces:
    """Places as the clusters of a river streaming clusterer over Haar signatures.

    Args:
        clusterer: ``"dbstream"`` (DBSTREAM, Hahsler & Bolaños 2016: density-based, opens
            clusters as it goes) or ``"streamkmeans"`` (STREAMKMeans: ``n_clusters`` fixed in
            advance, as an offline method would need).
        clustering_threshold: DBSTREAM's radius around a micro-cluster, on unit-length
            signatures (0 identical, 2 opposite); 0.7 gave the highest NMI among 0.3-1.35 on
            the demo's tour (scene 0, ``train`` split).
        fading_factor: DBSTREAM's forgetting rate; 0 never forgets, as a map should not.
        n_clusters: STREAMKMeans's number of clusters.
        wavelet_level: Haar decomposition level of the signature (seed 001 uses 4).
        seed: STREAMKMeans's random seed.

    The local feature type of the runner (``--features``) is not used. A place id is given to
    each of river's cluster ids in the order they first appear;
    consecutive frames in different places join the two places in :attr:`graph`. A blank
    frame is :data:`~placeclust.online.UNKNOWN` and changes nothing.
    """

    def __init__(self, clusterer: str = "dbstream", clustering_threshold: float = 0.7,
                 fading_factor: float = 0.0, n_clusters: int = 8, wavelet_level: int = 4,
                 seed: int = 0) -> None:
        if clusterer not in CLUSTERERS:
            raise ValueError(f"unknown clusterer {clusterer!r}; choose one of {CLUSTERERS}")
        self.clusterer = clusterer
        self.clustering_threshold = clustering_threshold
        self.fading_factor = fading_factor
        self.n_clusters = n_clusters
        self.wavelet_level = wavelet_level
        self.seed = seed
        self.graph = nx.Graph()
        self.frame_shape: tuple[int, int] | None = None
        self._ids: dict[int, int] = {}
        self._last = UNKNOWN
        self._model = self._make_model()

    def _make_model(self) -> Clusterer:
        from river import cluster

        if self.clusterer == "dbstream":
            return cluster.DBSTREAM(clustering_threshold=self.clustering_threshold,
                                    fading_factor=self.fading_factor)
        return cluster.STREAMKMeans(n_clusters=self.n_clusters, seed=self.seed)

    @property
    def n_places(self) -> int:
        """Places opened so far."""
        return len(self._ids)

    def _features(self, frame: np.ndarray) -> dict[Hashable, float] | None:
        """River's input: the unit Haar signature as feature index -> value, or ``None``."""
        gray = to_gray(frame)
        self.frame_shape = check_size(gray, self.frame_shape)
        signature = haar_signature(gray, self.wavelet_level).astype(float)
        norm = float(np.linalg.norm(signature))
        if norm == 0.0:
            return None  # a blank frame: nothing to describe
        return dict(enumerate(signature / norm))

    def _place(self, cluster_id: int, learn: bool) -> int:
        if cluster_id not in self._ids:
            if not learn:
                return UNKNOWN
            self._ids[cluster_id] = len(self._ids)
            self.graph.add_node(self._ids[cluster_id])
        return self._ids[cluster_id]

    def learn_predict_one(self, frame: np.ndarray) -> int:
        """Learn ``frame`` and return its place (river's ``learn_one`` then ``predict_one``)."""
        x = self._features(frame)
        if x is None:
            return UNKNOWN
        self._model.learn_one(x)
        place = self._place(int(self._model.predict_one(x)), learn=True)
        if self._last != UNKNOWN and place != self._last:
            self.graph.add_edge(self._last, place)
        self._last = place
        return place

    def learn_one(self, frame: np.ndarray) -> None:
        """Learn ``frame``."""
        self.learn_predict_one(frame)

    def predict_one(self, frame: np.ndarray) -> int:
        """The place of ``frame`` without learning it (``UNKNOWN`` for a cluster not seen)."""
        x = self._features(frame)
        if x is None or not self._ids:
            return UNKNOWN
        return self._place(int(self._model.predict_one(x)), learn=False)
