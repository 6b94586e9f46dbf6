import numpy as np
import pytest

from placeclust.hamming_forest import HammingForest


def random_bits(n: int, nbytes: int = 32, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (n, nbytes), dtype=np.uint8)


def brute_force(query: np.ndarray, data: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nearest row of ``data`` for each query row, ties to the lowest row."""
    bits = np.unpackbits(query[:, None, :] ^ data[None, :, :], axis=2).sum(axis=2)
    return bits.argmin(axis=1), bits.min(axis=1)  # argmin keeps the first of equal minima


@pytest.mark.parametrize("nbytes", [32, 61, 3])
def test_one_leaf_is_an_exact_search_with_the_lowest_row_on_ties(nbytes):
    data = random_bits(300, nbytes)
    data[150:] = data[:150]  # every descriptor twice: the lower row must win the tie
    query = random_bits(200, nbytes, seed=1)
    query[:50] = data[200:250]  # exact copies of the second halves' rows
    idx, dist = HammingForest(data, trees=1, leaf_size=len(data)).nearest(query)
    want_idx, want_dist = brute_force(query, data)
    np.testing.assert_array_equal(dist, want_dist)
    np.testing.assert_array_equal(idx, want_idx)
    assert (idx[:50] == np.arange(50, 100)).all()


@pytest.mark.parametrize("trees", [1, 3])
def test_every_indexed_descriptor_finds_itself_or_its_lower_twin(trees):
    # a query descends by the rule that placed each descriptor, so it reaches its own leaf;
    # twins share every leaf, where the shuffled medoid draws can put the higher row first
    data = random_bits(5000)
    data[2500:] = data[:2500]
    forest = HammingForest(data, trees=trees, branching=8, leaf_size=10, seed=3)
    idx, dist = forest.nearest(data)
    assert (dist == 0).all() and (idx == np.arange(len(data)) % 2500).all()


def test_more_trees_find_a_neighbour_at_least_as_near_and_usually_the_nearest():
    rng = np.random.default_rng(2)
    centres = random_bits(40, seed=4)  # clustered like real descriptors, not uniform noise
    data = centres[rng.integers(0, 40, 4000)] ^ np.packbits(rng.random((4000, 256)) < 0.1, 1)
    query = data[rng.integers(0, 4000, 500)] ^ np.packbits(rng.random((500, 256)) < 0.05, 1)
    _, exact = brute_force(query, data)
    found = {trees: HammingForest(data, trees=trees, leaf_size=50, seed=9).nearest(query)[1]
             for trees in (1, 4)}
    assert (found[4] <= found[1]).all() and (found[1] >= exact).all()
    assert (found[4] == exact).mean() > (found[1] == exact).mean()
    assert (found[4] == exact).mean() > 0.5


def test_the_same_seed_gives_the_same_trees():
    data, query = random_bits(3000), random_bits(300, seed=1)

    def answers(seed: int) -> np.ndarray:
        return HammingForest(data, leaf_size=20, seed=seed).nearest(query)[0]

    np.testing.assert_array_equal(answers(5), answers(5))
    assert (answers(5) != answers(6)).any()


def test_identical_descriptors_stay_one_leaf():
    data = np.zeros((500, 32), np.uint8)  # nothing to split them on: no endless recursion
    idx, dist = HammingForest(data, leaf_size=10).nearest(np.ones((2, 32), np.uint8))
    assert idx.tolist() == [0, 0] and dist.tolist() == [32, 32]


def test_bad_input_is_refused_with_a_clear_error():
    with pytest.raises(ValueError, match="empty"):
        HammingForest(np.zeros((0, 32), np.uint8))
    with pytest.raises(ValueError, match="branching >= 2"):
        HammingForest(random_bits(10), branching=1)
    with pytest.raises(ValueError, match="uint8"):
        HammingForest(np.zeros((10, 32), np.float32))
    forest = HammingForest(random_bits(10))
    with pytest.raises(ValueError, match=r"\(m, 32\)"):
        forest.nearest(random_bits(5, 16))
    with pytest.raises(ValueError, match="uint8"):
        forest.nearest(np.zeros((5, 32), np.float32))
