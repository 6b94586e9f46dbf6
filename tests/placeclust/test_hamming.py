import cv2
import numpy as np
import pytest

from placeclust.hamming import as_words, top2_hamming
from placeclust.matching import knn2


def sparse_bits(rng, n, nbytes):
    """Descriptors with few bits set, so that many distances tie."""
    return np.packbits(rng.random((n, 8 * nbytes)) < 0.03, axis=1)[:, :nbytes]


def brute_force(query, train):
    bits = np.unpackbits(query[:, None, :] ^ train[None, :, :], axis=2).sum(axis=2)
    order = np.argsort(bits, axis=1, kind="stable")[:, :2]  # ties: the lower index first
    return np.take_along_axis(bits, order, 1), order


@pytest.mark.parametrize("nbytes", [32, 61, 3], ids=["orb", "akaze", "three-bytes"])
def test_two_nearest_agree_with_brute_force_ties_included(nbytes):
    rng = np.random.default_rng(nbytes)
    query, train = sparse_bits(rng, 200, nbytes), sparse_bits(rng, 150, nbytes)
    expected_dist, expected_idx = brute_force(query, train)
    assert (expected_dist[:, 0] == expected_dist[:, 1]).sum() > 20  # the fixture does tie
    dist, idx = top2_hamming(as_words(query), np.ascontiguousarray(as_words(train).T))
    np.testing.assert_array_equal(idx, expected_idx)
    np.testing.assert_array_equal(dist, expected_dist)


def test_knn2_gives_opencvs_answer():
    """The matcher it replaces: OpenCV's batchDistance (BFMatcher's), distances and order."""
    rng = np.random.default_rng(7)
    query, train = sparse_bits(rng, 300, 32), sparse_bits(rng, 400, 32)
    cv_dist, cv_idx = cv2.batchDistance(query, train, -1, normType=cv2.NORM_HAMMING, K=2,
                                        update=0, crosscheck=False)
    dist, idx = knn2(query, train, True)
    np.testing.assert_array_equal(idx, cv_idx)
    np.testing.assert_allclose(dist, cv_dist / 256.0)


def test_one_train_row_has_no_second_neighbour():
    rng = np.random.default_rng(8)
    query, train = sparse_bits(rng, 5, 32), sparse_bits(rng, 1, 32)
    dist, idx = top2_hamming(as_words(query), np.ascontiguousarray(as_words(train).T))
    assert np.all(idx[:, 0] == 0) and np.all(idx[:, 1] == -1)
    assert np.all(dist[:, 1] > 256)


def test_words_of_a_strided_view_and_bad_input():
    rng = np.random.default_rng(9)
    wide = sparse_bits(rng, 4, 64)
    np.testing.assert_array_equal(as_words(wide[:, :32]), as_words(wide[:, :32].copy()))
    with pytest.raises(ValueError, match="uint64"):
        top2_hamming(wide[:, :32], as_words(wide[:, :32]).T)
    with pytest.raises(ValueError, match="words"):
        top2_hamming(as_words(wide), np.ascontiguousarray(as_words(wide[:, :32]).T))
    with pytest.raises(ValueError, match="uint8"):  # bytes, not bits or integers
        as_words(wide.astype(np.int32))
    with pytest.raises(ValueError, match="columns"):  # 30 and 32 bytes are both 4 words
        knn2(wide[:, :30], wide[:, :32], True)
