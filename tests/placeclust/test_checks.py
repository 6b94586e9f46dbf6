"""Every built-in recognizer passes the protocol battery, and the battery catches breaches."""

import networkx as nx
import numpy as np
import pytest

from placeclust import PANORAMA, PANORAMA_ORB
from placeclust.baselines import KMeansPlaces, WPGMAPlaces
from placeclust.checks import check_recognizer
from placeclust.kunion import KAdjacentUnion
from placeclust.nested import NestedMapper
from placeclust.online import OnlinePlaceClustering
from placeclust.stream import StreamPlaces

FAST = {"max_features": 100, "n_words": 100}  # the bag-of-words baselines' examples use these


@pytest.mark.parametrize("cls, params", [
    (OnlinePlaceClustering, {}),
    (OnlinePlaceClustering, {"features": "orb"}),
    (OnlinePlaceClustering, dict(PANORAMA)),
    (OnlinePlaceClustering, {"features": "orb", **PANORAMA_ORB}),
    (NestedMapper, {}),
    (KAdjacentUnion, {"window": 2}),
    (KMeansPlaces, {"n_clusters": 2, **FAST}),
    (WPGMAPlaces, {"n_clusters": 2, **FAST}),
    (StreamPlaces, {}),
    (StreamPlaces, {"clusterer": "streamkmeans", "n_clusters": 2}),
], ids=["online", "online-orb", "online-panorama", "online-panorama-orb", "nested", "kunion",
        "kmeans", "wpgma", "dbstream", "streamkmeans"])
def test_every_built_in_recognizer_passes(cls, params):
    check_recognizer(cls, params)


class Forgetful:
    """Online, but keeps its threshold under another name and opens a place per frame."""

    def __init__(self, threshold: float = 0.5) -> None:
        self.level = threshold
        self.n_places = 0
        self.graph = nx.Graph()

    def learn_predict_one(self, frame: np.ndarray) -> int:
        self.n_places += 1
        return self.n_places - 1

    def predict_one(self, frame: np.ndarray) -> int:
        return 0


class Shared:
    """Keeps its places in a class attribute, so instances see each other's."""

    seen: list = []

    def __init__(self) -> None:
        self.graph = nx.Graph()

    @property
    def n_places(self) -> int:
        return len(self.seen)

    def learn_predict_one(self, frame: np.ndarray) -> int:
        if frame.dtype != np.uint8 or frame.ndim != 3:
            raise ValueError("bad frame")
        self.seen.append(0)
        return 0

    def predict_one(self, frame: np.ndarray) -> int:
        return 0


@pytest.mark.parametrize("cls, message", [
    (Forgetful, "check_parameters_are_attributes: constructor argument 'threshold'"),
    (Shared, "check_deterministic|check_instances_are_independent|check_online_protocol"),
])
def test_the_battery_names_what_a_recognizer_breaks(cls, message):
    with pytest.raises(AssertionError, match=message):
        check_recognizer(cls)


class Provisional(OnlinePlaceClustering):
    """Gives a new place's first frame a provisional id that it merges away at once, as
    consolidation merges a room seen anew into its place."""

    def learn_predict_one(self, frame: np.ndarray) -> int:
        before = self.n_places
        place = super().learn_predict_one(frame)
        return place + 100 if self.n_places > before else place

    def resolve(self, places: np.ndarray) -> np.ndarray:
        ids = np.asarray(places, np.int64)
        return np.where(ids >= 100, ids - 100, ids)


def test_a_recognizer_that_merges_places_is_judged_by_what_its_ids_resolve_to():
    check_recognizer(Provisional)  # ids 100, 0, 0, 101, 1, 1: two places
    check_recognizer(OnlinePlaceClustering, {**PANORAMA, "consolidate": 0.85})
