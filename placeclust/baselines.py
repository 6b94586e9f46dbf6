"""Offline baselines of seed 000's Fig. 2: k-means, WPGMA, and shared helpers.

Both cluster one vector per frame: a tf-idf bag-of-words histogram of the frame's local
features over a vocabulary learnt (k-means) from the sequence itself, so they see the same
features as the online recognizers. The number of places ``k`` comes from the scene-change
detector of the k-adjacent-union method (:func:`estimate_k`) unless given: all offline methods
get the same, unsupervised, estimate.
"""

from __future__ import annotations

import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.ndimage import uniform_filter1d
from scipy.signal import argrelmin
from scipy.spatial.distance import pdist, squareform
from sklearn.cluster import KMeans, MiniBatchKMeans

from placeclust.features import FeatureExtractor
from placeclust.frames import check_sequence, to_gray
from placeclust.matching import dice_eq4, normalize, ratio_matches


def describe_all(frames: np.ndarray, extractor: FeatureExtractor) -> list[np.ndarray]:
    """Normalised descriptors of every frame of a sequence.

    Args:
        frames: (T, H, W[, C]) images.
        extractor: the local features to compute.

    Returns:
        One (N_t, D) array per frame (see :func:`~placeclust.matching.normalize`).

    Raises:
        ValueError: ``frames`` is not a non-empty sequence of valid images.
    """
    frames = check_sequence(frames)
    out = []
    for f in frames:
        feats = extractor.extract(to_gray(f))
        out.append(normalize(feats.descriptors, feats.binary))
    return out


def bag_of_words(descs: list[np.ndarray], binary: bool, n_words: int = 200,
                 seed: int = 0) -> np.ndarray:
    """(T, n_words) L2-normalised tf-idf histograms over a vocabulary learnt from ``descs``.

    Args:
        descs: one (N_t, D) descriptor array per frame (:func:`describe_all`).
        binary: binary descriptors are unpacked to bits before clustering.
        n_words: vocabulary size (fewer if there are fewer sampled features).
        seed: seeds the feature sample and the vocabulary's mini-batch k-means.

    Returns:
        One unit-L2 row per frame (all zeros for a frame without features or whose words
        occur in every frame); a single all-zero column when no frame has a feature (a
        blank wall seen throughout), so the caller still gets one row a frame.
    """
    if not any(len(d) for d in descs):
        return np.zeros((len(descs), 1), np.float32)

    def as_float(d: np.ndarray) -> np.ndarray:
        return np.unpackbits(d, axis=1).astype(np.float32) if binary else d

    rng = np.random.default_rng(seed)
    pool = np.concatenate([as_float(d) for d in descs if len(d)])
    sample = pool[rng.permutation(len(pool))[:20000]]
    n_words = min(n_words, len(sample))
    vocab = MiniBatchKMeans(n_clusters=n_words, random_state=seed, n_init=3).fit(sample)
    hist = np.zeros((len(descs), n_words), np.float32)
    for t, d in enumerate(descs):
        if len(d):
            np.add.at(hist[t], vocab.predict(as_float(d)), 1.0)
    df = (hist > 0).sum(axis=0)
    hist *= np.log((1 + len(descs)) / (1 + df))[None, :]
    norms = np.linalg.norm(hist, axis=1, keepdims=True)
    return hist / np.maximum(norms, 1e-12)


def consecutive_similarity(descs: list[np.ndarray], binary: bool) -> np.ndarray:
    """Eq. 4 similarity (Dice of ratio-tested matches) of each frame with the next, (T-1,).

    Eq. 4 rather than Eq. 1: every feature has *some* nearest neighbour, so Eq. 1 barely dips
    at a scene change, while the share of unambiguous matches drops sharply.

    Args:
        descs: one descriptor array per frame (:func:`describe_all`).
        binary: Hamming (True) or Euclidean (False) descriptors.
    """
    return np.array([dice_eq4(len(ratio_matches(a, b, binary)[0]), len(b), len(a))
                     for a, b in zip(descs[:-1], descs[1:])])


def scene_changes(descs: list[np.ndarray], binary: bool, window: int = 15) -> np.ndarray:
    """Frame indices where a new scene starts (Sec. III.C, step 1).

    Local minima of the neighbouring-image similarity (:func:`consecutive_similarity`), at
    least ``window`` frames apart, that fall a standard deviation below its smoothed level
    (smoothing only the level: smoothing the curve itself would shift the minima).

    Args:
        descs: one descriptor array per frame (:func:`describe_all`).
        binary: Hamming (True) or Euclidean (False) descriptors.
        window: the fewest frames between two scene changes.

    Returns:
        The indices of the first frames of new scenes, int64, in increasing order.

    Examples:
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(4)
        >>> from placeclust.baselines import describe_all, estimate_k, scene_changes
        >>> from placeclust.features import FeatureExtractor
        >>> descs = describe_all(frames, FeatureExtractor())
        >>> scene_changes(descs, binary=False, window=2).tolist()
        [4]
        >>> estimate_k(descs, binary=False, window=2)
        2
    """
    if len(descs) < 3:
        return np.zeros(0, np.int64)
    sim = consecutive_similarity(descs, binary)
    level = uniform_filter1d(sim, size=4 * window + 1, mode="nearest")
    minima = argrelmin(sim, order=window, mode="wrap" if len(sim) <= 2 * window else "clip")[0]
    return minima[sim[minima] < level[minima] - sim.std()] + 1


def estimate_k(descs: list[np.ndarray], binary: bool, window: int = 15) -> int:
    """Number of places from scene-change detection: segments between changes.

    Args:
        descs: one descriptor array per frame (:func:`describe_all`).
        binary: Hamming (True) or Euclidean (False) descriptors.
        window: the fewest frames between two scene changes (:func:`scene_changes`).

    Returns:
        One more than the number of scene changes.
    """
    return int(len(scene_changes(descs, binary, window)) + 1)


def cosine_distances(x: np.ndarray) -> np.ndarray:
    """Condensed cosine distances between rows, defined for all-zero rows too.

    A frame without words (no features, or only words that occur everywhere) has no angle:
    it is taken as 0 from another such frame and 1 from every other, so a blank stretch
    forms one cluster instead of making the linkage fail on NaN.

    Args:
        x: (T, D) vectors.

    Returns:
        The (T·(T-1)/2,) condensed distance vector SciPy's ``linkage`` takes.
    """
    blank = ~x.any(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        d = squareform(pdist(x, metric="cosine"), checks=False)
    d[np.ix_(blank, ~blank)] = d[np.ix_(~blank, blank)] = 1.0
    d[np.ix_(blank, blank)] = 0.0
    np.fill_diagonal(d, 0.0)
    return squareform(np.clip(d, 0.0, 2.0), checks=False)


class KMeansPlaces:
    """k-means on bag-of-words vectors (scikit-learn), the weakest baseline of Fig. 2.

    Args:
        features: local feature type.
        n_clusters: places; ``None`` estimates them by scene-change detection.
        n_words: vocabulary size.
        max_features: features per frame.
        seed: seeds the vocabulary and k-means.
        normalize: contrast normalization (:class:`~placeclust.features.FeatureExtractor`).
        scale: resize factor before detection (:class:`~placeclust.features.FeatureExtractor`).
        view: ``"full"`` or ``"sides"`` of a panorama (:data:`~placeclust.features.VIEWS`).

    Examples:
        Four views of one synthetic place, then four of another; the cluster ids are
        arbitrary, the partition is not:

        >>> from placeclust.synthetic import places
        >>> frames, truth = places(4)
        >>> from placeclust.baselines import KMeansPlaces
        >>> model = KMeansPlaces(n_clusters=2, max_features=100, n_words=100)
        >>> labels = model.fit_predict(frames)
        >>> (labels == labels[0]).tolist()
        [True, True, True, True, False, False, False, False]
    """

    def __init__(self, features: str = "sift", n_clusters: int | None = None,
                 n_words: int = 200, max_features: int = 500, seed: int = 0,
                 normalize: str | None = "clahe", scale: float = 1.0, view: str = "full"
                 ) -> None:
        self.features = features
        self.n_clusters = n_clusters
        self.n_words = n_words
        self.max_features = max_features
        self.seed = seed
        self.normalize = normalize
        self.scale = scale
        self.view = view

    def _prepare(self, frames: np.ndarray) -> tuple[np.ndarray, int]:
        ext = FeatureExtractor(self.features, self.max_features, self.normalize, self.scale,
                               self.view)
        descs = describe_all(frames, ext)
        k = self.n_clusters or estimate_k(descs, ext.binary)
        return bag_of_words(descs, ext.binary, self.n_words, self.seed), min(k, len(frames))

    def fit_predict(self, frames: np.ndarray) -> np.ndarray:
        """Cluster a whole sequence.

        Args:
            frames: (T, H, W[, C]) images.

        Returns:
            Place id per frame, (T,) int.
        """
        x, k = self._prepare(frames)
        k = min(k, len(np.unique(x, axis=0)))  # identical rows (blank frames) are one place
        return KMeans(n_clusters=k, n_init=10, random_state=self.seed).fit_predict(x)


class WPGMAPlaces(KMeansPlaces):
    """WPGMA agglomerative clustering of bag-of-words vectors, the other baseline of Fig. 2.

    SciPy's ``weighted`` linkage with cosine distances, cut into ``n_clusters`` clusters; the
    arguments are those of :class:`KMeansPlaces`.

    Examples:
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(4)
        >>> from placeclust.baselines import WPGMAPlaces
        >>> model = WPGMAPlaces(n_clusters=2, max_features=100, n_words=100)
        >>> labels = model.fit_predict(frames)
        >>> (labels == labels[0]).tolist()
        [True, True, True, True, False, False, False, False]
    """

    def fit_predict(self, frames: np.ndarray) -> np.ndarray:
        x, k = self._prepare(frames)
        if len(x) < 2:
            return np.zeros(len(x), np.int64)
        z = linkage(cosine_distances(x), method="weighted")
        return fcluster(z, t=k, criterion="maxclust").astype(np.int64) - 1
