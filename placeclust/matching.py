"""Descriptor matching and the image similarities of seed 000 (Tang et al., Eq. 1-4).

Float descriptors are compared by Euclidean distance (Eq. 2) after L2 normalisation, binary ones
by the Hamming distance divided by the number of bits, so every distance lies in [0, 2] and
Eq. 1 means the same for every feature type. The nearest neighbour of Eq. 3 is a correspondence
only when it passes Lowe's ratio test: Eq. 3 alone pairs every feature with something.
"""

from __future__ import annotations

import numpy as np
from threadpoolctl import ThreadpoolController

from placeclust.hamming import as_words, top2_hamming
from placeclust.threads import split_rows

# The matching GEMMs run on one BLAS thread each (``knn2`` splits a match over OpenCV's
# threads instead): OpenBLAS's own threads keep spinning after each call and slow OpenCV's
# SIFT in the same process. The limit is taken in the calling thread, around the split (the
# worker threads follow it: OpenBLAS ignores a limit set in a worker once the main thread has
# set one), and holds only during the call; the process's own BLAS settings are left alone.
_BLAS = ThreadpoolController()

# Query rows per thread below which splitting a float match costs more than it saves.
_MIN_SPLIT = 128


def normalize(desc: np.ndarray, binary: bool) -> np.ndarray:
    """Unit-L2 rows for float descriptors, so that Eq. 2 distances lie in [0, 2].

    Args:
        desc: (N, D) descriptors.
        binary: binary descriptors are returned unchanged.

    Returns:
        (N, D) float32 unit rows, or ``desc`` itself.

    Examples:
        >>> import numpy as np
        >>> from placeclust.matching import normalize
        >>> normalize(np.array([[3.0, 4.0]], np.float32), binary=False)
        array([[0.6, 0.8]], dtype=float32)
    """
    if binary or len(desc) == 0:
        return desc
    norms = np.linalg.norm(desc, axis=1, keepdims=True)
    return (desc / np.maximum(norms, 1e-12)).astype(np.float32)


def knn2(query: np.ndarray, train: np.ndarray, binary: bool) -> tuple[np.ndarray, np.ndarray]:
    """Two nearest ``train`` rows for each ``query`` row (the search behind Eq. 1 and 3).

    Args:
        query: (N, D) descriptors, unit rows if float (see :func:`normalize`).
        train: (M, D) descriptors of the same type.
        binary: Hamming distance as a fraction of the bits (True) or Euclidean (False).

    Returns:
        ``(dist, idx)``, both (N, 2), sorted by distance; with a single train row the second
        column repeats distance inf and index -1.

    Raises:
        ValueError: ``query`` and ``train`` have different widths.

    Examples:
        >>> import numpy as np
        >>> from placeclust.matching import knn2
        >>> train = np.eye(3, dtype=np.float32)
        >>> dist, idx = knn2(train[[2]], train, binary=False)
        >>> idx.tolist(), [round(float(d), 3) for d in dist[0]]
        ([[2, 0]], [0.0, 1.414])
    """
    n = len(query)
    if n == 0 or len(train) == 0:
        return np.full((n, 2), np.inf, np.float32), np.full((n, 2), -1, np.int64)
    if query.shape[1] != train.shape[1]:
        raise ValueError(f"query descriptors have {query.shape[1]} columns, train descriptors "
                         f"{train.shape[1]}: not the same feature type")
    single = len(train) == 1
    if binary:
        # one thread: split over cores, the Hamming match took no less time
        bits, idx = top2_hamming(as_words(query), np.ascontiguousarray(as_words(train).T))
        dist = bits.astype(np.float32) / (8 * query.shape[1])
    else:
        with _BLAS.limit(limits=1, user_api="blas"):
            found = split_rows(lambda rows: _top2_dot(rows, train, single), query, _MIN_SPLIT)
        idx = np.concatenate([i for i, _ in found])
        dot = np.concatenate([d for _, d in found])
        dist = np.sqrt(np.maximum(2.0 - 2.0 * dot, 0.0)).astype(np.float32)
    if single:
        dist[:, 1], idx[:, 1] = np.inf, -1
    return dist, idx


def _top2_dot(query: np.ndarray, train: np.ndarray, single: bool
              ) -> tuple[np.ndarray, np.ndarray]:
    """Indices and dot products of the two largest ``query @ train.T`` entries of each row."""
    # |q - t|^2 = |q|^2 + |t|^2 - 2 q.t with unit rows: one GEMM, the fastest route here.
    # The two nearest are the two largest dot products: two argmax passes (the first one
    # masked out) cost less than an argpartition over the whole matrix.
    sim = query @ train.T
    rows = np.arange(len(query))
    first = sim.argmax(axis=1)
    best = sim[rows, first]
    if not single:  # a single row's second column is set to (inf, -1) by the caller
        sim[rows, first] = -np.inf
    second = sim.argmax(axis=1)
    return (np.stack([first, second], axis=1).astype(np.int64),
            np.stack([best, sim[rows, second]], axis=1))


#: (max_distance, sure_distance) per descriptor kind. Unit float vectors of unrelated features
#: lie ~1.0-1.3 apart; 256-bit binary ones differ in ~half their bits (0.5), their nearest of a
#: few hundred in ~0.3, so binary thresholds must be far tighter.
DISTANCES = {False: (0.7, 0.35), True: (0.25, 0.1)}


def ratio_matches(query: np.ndarray, train: np.ndarray, binary: bool, ratio: float = 0.8
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Correspondences ``(query_idx, train_idx)`` by Eq. 3 with Lowe's ratio test.

    A nearest neighbour is kept when it is closer than ``ratio`` times the second nearest, or
    when it is closer than the *sure* distance of :data:`DISTANCES` (an unmistakable match,
    which near-duplicate features in a union kernel would otherwise fail the ratio test on),
    and never when it is farther than the *max* distance.

    Args:
        query: (N, D) descriptors, unit rows if float (see :func:`normalize`).
        train: (M, D) descriptors of the same type.
        binary: Hamming (True) or Euclidean (False) descriptors.
        ratio: Lowe's ratio.

    Returns:
        Two int arrays of the same length: the matched query rows and their train rows.

    Examples:
        >>> import numpy as np
        >>> from placeclust.matching import normalize, ratio_matches
        >>> rng = np.random.default_rng(0)
        >>> train = normalize(rng.normal(size=(20, 16)).astype(np.float32), binary=False)
        >>> query = normalize(train[[3, 7]] + 0.01, binary=False)
        >>> q, t = ratio_matches(query, train, binary=False)
        >>> q.tolist(), t.tolist()
        ([0, 1], [3, 7])
    """
    max_distance, sure = DISTANCES[binary]
    dist, idx = knn2(query, train, binary)
    d1, d2 = dist[:, 0], dist[:, 1]
    ok = (d1 <= max_distance) & ((d1 < ratio * d2) | (d1 < sure))
    q = np.nonzero(ok)[0]
    return q, idx[q, 0]


def similarity_eq1(a: np.ndarray, b: np.ndarray, binary: bool) -> float:
    """Eq. 1: one minus the mean distance from each feature of ``a`` to its nearest in ``b``.

    Args:
        a: (N, D) descriptors of one image, unit rows if float.
        b: (M, D) descriptors of the other image or kernel.
        binary: Hamming (True) or Euclidean (False) descriptors.

    Returns:
        The similarity, 1 for identical feature sets; 0 if either set is empty.

    Examples:
        >>> import numpy as np
        >>> from placeclust.matching import similarity_eq1
        >>> b = np.eye(4, dtype=np.float32)
        >>> round(similarity_eq1(b[:2], b, binary=False), 3)
        1.0
        >>> similarity_eq1(b[:0], b, binary=False)
        0.0
    """
    if len(a) == 0 or len(b) == 0:
        return 0.0
    dist, _ = knn2(a, b, binary)
    return float(1.0 - dist[:, 0].mean())


def dice_eq4(n_matches: int, n_kernel: int, n_image: int) -> float:
    """Eq. 4: ``2 |matches| / (N_C + N_I)``, a similarity in [0, 1] (Dice coefficient).

    Args:
        n_matches: correspondences (Eq. 3) between the kernel and the image.
        n_kernel: ``N_C``, features of the kernel.
        n_image: ``N_I``, features of the image.

    Returns:
        The similarity; 0 when both are empty.

    Examples:
        >>> from placeclust.matching import dice_eq4
        >>> dice_eq4(30, 100, 50)
        0.4
    """
    total = n_kernel + n_image
    return 0.0 if total == 0 else 2.0 * n_matches / total
