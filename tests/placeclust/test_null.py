import numpy as np
import pytest

from placeclust import UNKNOWN
from placeclust.checks import check_recognizer
from placeclust.null import NoPlaces, RandomPlaces
from placeclust.synthetic import places


@pytest.mark.parametrize("cls", [RandomPlaces, NoPlaces])
def test_null_recognizers_follow_the_protocol(cls):
    check_recognizer(cls)


def test_random_ids_ignore_the_frames_and_follow_the_seed():
    frames, _ = places(3)
    same = np.stack([frames[0]] * len(frames))
    a, b = RandomPlaces(n_ids=4, hold=1, seed=3), RandomPlaces(n_ids=4, hold=1, seed=3)
    seen = [a.learn_predict_one(f) for f in frames]
    assert [b.learn_predict_one(f) for f in same] == seen  # what is seen changes nothing
    model = RandomPlaces(n_ids=4, hold=5, seed=0)
    ids = [model.learn_predict_one(frames[0]) for _ in range(20)]
    assert all(len(set(ids[k:k + 5])) == 1 for k in range(0, 20, 5))  # held for 5 frames
    assert set(ids) <= set(range(4)) and model.n_places == len(set(ids))


def test_no_places_never_names_a_place():
    frames, _ = places(3)
    model = NoPlaces()
    assert [model.learn_predict_one(f) for f in frames] == [UNKNOWN] * len(frames)
    assert model.n_places == 0


def test_bad_settings_are_named():
    with pytest.raises(ValueError, match="n_ids and hold"):
        RandomPlaces(n_ids=0)
