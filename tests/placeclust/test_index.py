import copy

import cv2
import numpy as np
import pytest

from placeclust.index import PlaceIndex

N_PLACES, PER_PLACE = 30, 64  # FLANN takes the first 24 places (exact_below); 6 stay in the tail


def place_samples(binary: bool) -> list[np.ndarray]:
    rng = np.random.default_rng(0)
    if binary:
        return [rng.integers(0, 256, (PER_PLACE, 32), dtype=np.uint8) for _ in range(N_PLACES)]
    x = rng.normal(size=(N_PLACES, PER_PLACE, 32)).astype(np.float32)
    return list(x / np.linalg.norm(x, axis=2, keepdims=True))


def filled_index(samples: list[np.ndarray], binary: bool) -> PlaceIndex:
    """A default index holding every place of ``samples``."""
    index = PlaceIndex(binary, lambda p: samples[p])
    for p in range(len(samples)):
        index.add(p)
    return index


def seen_again(sample: np.ndarray, binary: bool, rng: np.random.Generator) -> np.ndarray:
    """``sample`` observed again: a few bits flipped, or a little Gaussian noise."""
    if binary:
        flips = np.packbits(rng.random((len(sample), 256)) < 0.05, axis=1)
        return sample ^ flips
    noisy = sample + rng.normal(scale=0.05, size=sample.shape).astype(np.float32)
    return noisy / np.linalg.norm(noisy, axis=1, keepdims=True)


def assert_clear_winner(votes: dict[int, int], place: int) -> None:
    # the index is approximate: on these structureless random bits the k-medoids trees give
    # the true place 57-64 of its 64 votes over 30 build seeds (median 62) and the runner-up at
    # most 2 (FLANN's, searched through one tree: 30-50 and 9), but the place must win by far
    runner_up = max((v for p, v in votes.items() if p != place), default=0)
    assert votes.get(place, 0) >= max(3 * runner_up, PER_PLACE // 3), votes


@pytest.mark.parametrize("binary", [True, False], ids=["hamming", "euclidean"])
def test_votes_name_the_place_seen_again_in_the_tree_and_in_the_tail(binary):
    samples = place_samples(binary)
    index = filled_index(samples, binary)
    assert index.n_rebuilds == 1 and len(index._tail) == N_PLACES - index.exact_below == 6
    rng = np.random.default_rng(1)
    for place in (0, 11, 23, 24, 29):  # indexed by FLANN (0-23) and by brute force (24-29)
        assert_clear_winner(index.votes(seen_again(samples[place], binary, rng)), place)


def test_ranked_places_come_by_most_votes_then_lowest_id():
    """The order the recognizers check a shortlist in: ties go to the lower place id, whatever
    the order of the features that voted."""
    samples = place_samples(binary=False)
    index = filled_index(samples, False)
    # exact copies of tail features (places 24-29), searched by brute force: exact votes
    query = np.concatenate([samples[27][:3], samples[25][:5], samples[24][:3], samples[29][:1]])
    assert index.votes(query) == {24: 3, 25: 5, 27: 3, 29: 1}
    assert index.ranked(query) == [25, 24, 27, 29]
    assert index.ranked(query[:0]) == []


def test_small_maps_are_searched_exactly_and_large_ones_keep_a_short_tail():
    samples = place_samples(binary=False)
    index = PlaceIndex(False, lambda p: samples[p], max_tail=2, exact_below=5)
    tails = []
    for p in range(10):
        index.add(p)
        tails.append(len(index._tail))
    # all tail until 5 places, then FLANN takes the tail whenever it holds 2
    assert tails == [1, 2, 3, 4, 0, 1, 0, 1, 0, 1] and index.n_rebuilds == 3


def test_a_copied_index_rebuilds_its_tree_and_votes_alike():
    samples = place_samples(binary=True)
    index = filled_index(samples, True)
    query = seen_again(samples[5], True, np.random.default_rng(2))
    clone = copy.deepcopy(index)  # trees are not copied: rebuilt on the first query
    assert clone._tree is None
    assert_clear_winner(clone.votes(query), 5)


def test_an_empty_index_or_query_gives_no_votes():
    index = PlaceIndex(True, lambda p: np.zeros((0, 32), np.uint8))
    assert index.votes(np.zeros((3, 32), np.uint8)) == {}
    index.add(0)  # a place without features is indexed but can get no votes
    index.rebuild()
    assert index.votes(np.zeros((3, 32), np.uint8)) == {}
    assert index.votes(np.zeros((0, 32), np.uint8)) == {}


@pytest.mark.parametrize("binary", [False, True])
def test_the_index_does_not_depend_on_what_the_process_drew_before(binary):
    """FLANN draws from OpenCV's global RNG: the same places must give the same votes whatever
    was drawn before, and the caller's own seeded stream must stay reproducible."""
    rng = np.random.default_rng(5)
    if binary:
        places = {p: rng.integers(0, 256, (300, 32), dtype=np.uint8) for p in range(6)}
        queries = rng.integers(0, 256, (200, 32), dtype=np.uint8)
    else:
        places = {p: rng.random((300, 64), dtype=np.float32) for p in range(6)}
        queries = rng.random((200, 64), dtype=np.float32)

    def votes_after(draws: int) -> dict[int, int]:
        cv2.randu(np.zeros((draws, 1), np.float32), 0, 1)  # what the process did before
        index = PlaceIndex(binary, places.__getitem__, max_tail=100)
        for p in places:
            index.add(p)
        index.rebuild()
        return index.votes(queries)

    assert votes_after(1) == votes_after(7919)

    def stream() -> np.ndarray:
        cv2.setRNGSeed(42)
        votes_after(3)
        return cv2.randu(np.zeros((4, 1), np.float32), 0, 1)

    np.testing.assert_array_equal(stream(), stream())


@pytest.mark.parametrize("binary", [False, True], ids=["euclidean", "hamming"])
def test_a_query_split_over_threads_votes_as_one_search(binary):
    samples = place_samples(binary)
    index = filled_index(samples, binary)
    rng = np.random.default_rng(3)
    query = np.concatenate([seen_again(samples[p], binary, rng) for p in (2, 7, 9, 13)])
    threads = cv2.getNumThreads()
    try:
        cv2.setNumThreads(1)
        alone = index.votes(query)
        cv2.setNumThreads(4)  # 256 features: four parts of 64
        split = index.votes(query)
    finally:
        cv2.setNumThreads(threads)
    assert split == alone and sum(alone.values()) == len(query)
