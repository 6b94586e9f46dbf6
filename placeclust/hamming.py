"""The two nearest binary descriptors by Hamming distance, compiled with numba.

OpenCV's ``batchDistance`` (what ``BFMatcher`` uses) calls a Hamming routine per pair of
descriptors, the cost of nearly every binary match. Here the kernel's descriptors are laid out
word-major, so that one query word is XORed and popcounted against many kernel rows at once
(SIMD over the rows), and the two nearest are then picked in one pass, several times faster on
one core, with the same distances and indices (ties keep OpenCV's order, the lower index first;
tested against brute force).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_NONE = np.int64(1 << 30)  # "no neighbour yet": above any Hamming distance of a descriptor


@njit(inline="always")
def _popcount(x):  # numba lowers this bit trick to the CPU's popcount instruction
    x = x - ((x >> 1) & 0x5555555555555555)
    x = (x & 0x3333333333333333) + ((x >> 2) & 0x3333333333333333)
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0F
    return (x * 0x0101010101010101) >> 56


@njit(nogil=True, cache=True)
def _top2_words(query: np.ndarray, train_t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two nearest of each ``query`` row (n, w) uint64 among the columns of ``train_t``
    (w, m) uint64; a missing second neighbour is distance ``_NONE``, index -1."""
    n, w = query.shape
    m = train_t.shape[1]
    dist = np.empty((n, 2), np.int64)
    idx = np.empty((n, 2), np.int64)
    row = np.empty(m, np.int64)
    for i in range(n):
        row[:] = 0
        for k in range(w):
            word = query[i, k]
            column = train_t[k]
            for j in range(m):
                row[j] += _popcount(word ^ column[j])
        d1, d2, i1, i2 = _NONE, _NONE, -1, -1
        for j in range(m):  # strict comparisons: an equal distance keeps the lower index first
            d = row[j]
            if d < d2:
                if d < d1:
                    d2, i2, d1, i1 = d1, i1, d, j
                else:
                    d2, i2 = d, j
        dist[i, 0], dist[i, 1], idx[i, 0], idx[i, 1] = d1, d2, i1, i2
    return dist, idx


def as_words(descriptors: np.ndarray) -> np.ndarray:
    """(n, bytes) uint8 descriptors as (n, words) uint64, zero-padded to whole words.

    Zeros add nothing to a Hamming distance: AKAZE's 61 bytes become 8 words.

    Raises:
        ValueError: ``descriptors`` is not a 2-D uint8 array.

    Examples:
        >>> import numpy as np
        >>> from placeclust.hamming import as_words
        >>> as_words(np.zeros((5, 32), np.uint8)).shape, as_words(np.zeros((5, 61), np.uint8)).shape
        ((5, 4), (5, 8))
    """
    if descriptors.dtype != np.uint8 or descriptors.ndim != 2:
        raise ValueError(f"binary descriptors must be a 2-D uint8 array, got "
                         f"{descriptors.ndim}-D {descriptors.dtype}")
    n, nbytes = descriptors.shape
    words = -(-nbytes // 8)
    if nbytes == 8 * words and descriptors.flags.c_contiguous:
        return descriptors.view(np.uint64)
    padded = np.zeros((n, 8 * words), np.uint8)
    padded[:, :nbytes] = descriptors
    return padded.view(np.uint64)


def top2_hamming(query: np.ndarray, train_t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hamming distances (in bits) and indices of the two nearest train rows of each query row.

    Args:
        query: (n, w) uint64, rows from :func:`as_words`.
        train_t: (w, m) uint64, :func:`as_words` of the train rows, transposed and contiguous.

    Returns:
        ``(dist, idx)``, both (n, 2) int64 and sorted by distance; with one train row the second
        column is distance ``2**30`` and index -1.

    Raises:
        ValueError: the arrays are not uint64 or their word counts differ.

    Examples:
        >>> import numpy as np
        >>> from placeclust.hamming import as_words, top2_hamming
        >>> train = np.random.default_rng(0).integers(0, 256, (100, 32), dtype=np.uint8)
        >>> train_t = np.ascontiguousarray(as_words(train).T)
        >>> dist, idx = top2_hamming(as_words(train[[5, 9]]), train_t)
        >>> idx[:, 0].tolist(), dist[:, 0].tolist()
        ([5, 9], [0, 0])
    """
    if query.dtype != np.uint64 or train_t.dtype != np.uint64:
        raise ValueError(f"need uint64 words, got {query.dtype} and {train_t.dtype}")
    if query.shape[1] != train_t.shape[0]:
        raise ValueError(f"query rows have {query.shape[1]} words, train rows "
                         f"{train_t.shape[0]}")
    return _top2_words(np.ascontiguousarray(query), np.ascontiguousarray(train_t))
