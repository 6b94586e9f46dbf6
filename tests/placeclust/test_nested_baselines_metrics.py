
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

