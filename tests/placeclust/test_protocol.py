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


def test_a_ranker_names_a_place_where_localizing_leaves_it_unknown():
    """Seed 001's mapper localizes only with min_matches; its ranking answers every frame with
    features, best first, and agrees with localize_one where that answers."""
    from placeclust.nested import NestedMapper
    from placeclust.online import OnlinePlaceClustering
    from placeclust.protocol import can_rank
    from placeclust.synthetic import places

    frames, _ = places(4)
    strict = NestedMapper(min_matches=10_000)
    loose = NestedMapper()
    for frame in frames:
        strict.learn_predict_one(frame)
        loose.learn_predict_one(frame)
    assert can_rank(NestedMapper) and can_rank(OnlinePlaceClustering)
    strict.reset_position()
    loose.reset_position()
    assert strict.localize_one(frames[0]) == -1
    ranked = strict.rank_places(frames[0], n=5)
    assert ranked and ranked[0] == loose.localize_one(frames[0])
    assert len(set(ranked)) == len(ranked) <= 5
    assert strict.rank_places(np.zeros_like(frames[0])) == []
