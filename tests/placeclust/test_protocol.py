"""The protocol's dispatch: what the commands ask of a recognizer before they run it."""

import numpy as np

from placeclust import OnlinePlaceClustering
from placeclust.kunion import KAdjacentUnion
from placeclust.nested import NestedMapper
from placeclust.null import NoPlaces, RandomPlaces
from placeclust.protocol import (
    OnlineRecognizer,
    can_localize,
    is_offline,
    is_online,
    map_full,
    reads_images,
    reset_position,
    resolve,
    view,
)
from placeclust.stream import StreamPlaces


def test_every_built_in_recognizer_is_online_or_offline_and_says_what_it_can():
    assert is_online(OnlinePlaceClustering) and is_online(NestedMapper)
    assert is_offline(KAdjacentUnion) and not is_online(KAdjacentUnion)
    assert can_localize(OnlinePlaceClustering) and can_localize(NestedMapper)
    assert not can_localize(StreamPlaces) and not can_localize(KAdjacentUnion)
    assert isinstance(OnlinePlaceClustering(), OnlineRecognizer)
    assert not reads_images(RandomPlaces()) and not reads_images(NoPlaces())
    assert reads_images(OnlinePlaceClustering())


def test_the_optional_parts_have_safe_defaults():
    class Bare:  # an online recognizer with nothing optional
        graph = None

    bare = Bare()
    reset_position(bare)  # nothing to forget: no error
    assert np.array_equal(resolve(bare, [3, -1, 2]), [3, -1, 2])
    assert not map_full(bare) and view(bare) == "full"
    model = OnlinePlaceClustering(max_places=1)
    assert not map_full(model) and view(OnlinePlaceClustering(view="sides")) == "sides"
    assert RandomPlaces().learn_predict_one(None) == 0  # no image needed
