
import numpy as np
import pytest

from placeclust.metrics import confusion_table, precision, recall, score
from placeclust.nested import NestedMapper
from placeclust.runner import run
from placeclust.wavelet import haar_signature, signature_similarity


def test_nested_mapper_two_locations_and_keyframes(two_places):
    frames, truth = two_places
    mapper = NestedMapper()
    out = [mapper.localize(f) for f in frames]
    locs = np.array([o[0] for o in out])
    assert mapper.n_places == 2 and precision(locs, truth) == 1.0
    assert mapper.graph.has_edge(0, 1)
    assert all(len(mapper.locations[i].views) >= 1 for i in (0, 1))
    mapper.localize(frames[-1])
    assert not mapper.last_was_keyframe  # same picture: no key frame, same answer


def test_nested_relocalization_leaves_the_map_as_it_was(two_places):
    frames, truth = two_places
    mapper = NestedMapper()
    for f in frames:
        mapper.learn_one(f)
    points = {i: loc.descriptors.copy() for i, loc in mapper.locations.items()}
    views = {i: len(loc.views) for i, loc in mapper.locations.items()}
    edges = set(mapper.graph.edges)
    mapper.reset_position()
    found = [mapper.localize_one(f) for f in frames[::-1]]
    assert found[0] == 1 and found[-1] == 0 and mapper.n_places == 2
    assert set(mapper.graph.edges) == edges
    for i, loc in mapper.locations.items():
        assert np.array_equal(loc.descriptors, points[i]) and len(loc.views) == views[i]
    assert mapper.last_matches >= mapper.min_matches


def test_nested_relocalization_of_an_unseen_place_is_unknown(two_places):
    frames, _ = two_places
    mapper = NestedMapper()
    for f in frames[:20]:
        mapper.learn_one(f)
    mapper.reset_position()
    assert mapper.localize_one(frames[-1]) == -1 and mapper.n_places == 1
    assert NestedMapper().localize_one(frames[0]) == -1  # no map yet


def test_haar_signature_level4_and_similarity():
    rng = np.random.default_rng(0)
    img = rng.integers(0, 255, (64, 256)).astype(np.uint8)
    sig = haar_signature(img)
    assert sig.shape == (3 * 4 * 16,)  # H, V, D of a 4x16 level-4 grid of a 64x256 image
    assert signature_similarity(sig, sig) == 1.0
    assert signature_similarity(sig, -sig) == 0.0


@pytest.mark.parametrize("algo", ["kmeans", "wpgma", "kunion"])
def test_offline_baselines_separate_two_places(two_places, algo):
    frames, truth = two_places
    result = run(algo, frames, "orb")
    assert len(result.assignments) == len(frames)
    assert precision(result.assignments, truth) >= 0.9


def test_metrics_on_a_known_clustering():
    truth = np.array([0, 0, 0, 0, 1, 1, 1, 1])
    pred = np.array([5, 5, 5, 7, 7, 7, 7, -1])
    assert precision(pred, truth) == pytest.approx(6 / 8)
    assert recall(pred, truth) == pytest.approx(6 / 8)
    s = score(pred, truth)
    assert s["n_places"] == 2 and s["n_rooms"] == 2 and s["unknown_rate"] == 1 / 8
    conf = confusion_table(pred, truth)
    assert conf[0] == {"a": 4, "b": 0, "c": 1, "d": 3, "AC": 7 / 8, "TP": 0.75, "P": 1.0}
    with pytest.raises(ValueError, match="frames"):
        score(pred[:3], truth)



def test_kunion_joins_down_to_the_number_of_places_it_is_given():
    from placeclust.kunion import KAdjacentUnion
    from placeclust.synthetic import places

    frames, truth = places(6, n_places=3)
    free = KAdjacentUnion(window=3).fit_predict(frames)
    assert len(np.unique(free)) == 3 and precision(free, truth) == 1.0
    assert len(np.unique(KAdjacentUnion(window=3, n_clusters=1).fit_predict(frames))) == 1
    # more places asked than scene changes found: the scene changes' k stands
    assert len(np.unique(KAdjacentUnion(window=3, n_clusters=9).fit_predict(frames))) == 3
    with pytest.raises(ValueError, match="n_clusters"):
        KAdjacentUnion(n_clusters=0)


@pytest.mark.parametrize("algo", ["kmeans", "wpgma"])
def test_offline_baselines_take_a_blank_stretch_as_one_place(two_places, algo):
    """Blank frames (no features at all) used to crash the vocabulary and the linkage."""
    from placeclust.baselines import KMeansPlaces, WPGMAPlaces

    model_cls = KMeansPlaces if algo == "kmeans" else WPGMAPlaces
    frames, _ = two_places
    blank = np.full((4,) + frames.shape[1:], 128, np.uint8)
    assert model_cls(n_clusters=2).fit_predict(blank).tolist() == [0, 0, 0, 0]
    labels = model_cls(n_clusters=3, max_features=100, n_words=100).fit_predict(
        np.concatenate([frames, blank]))
    tail = labels[len(frames):]
    assert len(set(tail)) == 1 and tail[0] not in set(labels[:len(frames)])
