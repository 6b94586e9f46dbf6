import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.utils.env_checker import check_env

from envs.tasks.place_id import PlaceIdWrapper, TrueRoomWrapper
from placeclust import UNKNOWN, OnlinePlaceClustering
from placeclust.nested import NestedMapper
from placeclust.null import RandomPlaces


class Counter:
    """A stand-in recognizer that opens a new place on every frame (or reports unknown)."""

    def __init__(self, unknown: bool = False):
        import networkx as nx

        self.graph = nx.Graph()
        self.n = 0
        self.unknown = unknown

    def learn_predict_one(self, frame):
        if self.unknown:
            return UNKNOWN
        self.n += 1
        return self.n - 1

    @property
    def n_places(self):
        return self.n


@pytest.fixture
def task():
    env = gym.make("PlaceNav-ReachRoom-v0")  # ORB needs the full 512 x 128 panorama
    yield env
    env.close()


def test_spaces(task):
    w = PlaceIdWrapper(task, max_places=8)
    assert w.observation_space["place_id"] == spaces.Discrete(9)
    obs, info = w.reset(seed=0)
    assert w.observation_space.contains(obs)
    assert {"place_id", "n_places", "map_full"} <= set(info)
    assert "place_ms" not in info and w.place_ms > 0  # timings vary: kept out of info
    hot = PlaceIdWrapper(task, max_places=8, one_hot=True)
    assert hot.observation_space["place_id"].shape == (9,)
    obs, _ = hot.reset(seed=0)
    assert obs["place_id"].sum() == 1 and hot.observation_space.contains(obs)


def test_check_env(task):
    check_env(PlaceIdWrapper(task), skip_render_check=True)
    sb3 = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3.check_env(PlaceIdWrapper(task), warn=True)


def test_map_persists_across_resets_unless_asked(task):
    w = PlaceIdWrapper(task)
    w.reset(seed=0)
    for _ in range(30):
        w.step(np.array([1.0, 0.5], np.float32))
    learned = w.recognizer.n_places
    assert learned >= 1 and w.graph is w.recognizer.graph
    w.reset(seed=1)
    assert w.recognizer.n_places >= learned

    fresh = PlaceIdWrapper(task, OnlinePlaceClustering("orb"), reset_map=True)
    fresh.reset(seed=0)
    for _ in range(30):
        fresh.step(np.array([1.0, 0.5], np.float32))
    _, info = fresh.reset(seed=1)
    assert info["n_places"] == 1  # the empty map it was given, plus this first frame


def test_map_full_and_no_place_read_as_the_reserved_value(task):
    w = PlaceIdWrapper(task, Counter(), max_places=2)
    obs, info = w.reset(seed=0)
    assert obs["place_id"] == 0 and not info["map_full"]
    w.step(np.zeros(2, np.float32))
    obs, _, _, _, info = w.step(np.zeros(2, np.float32))
    assert obs["place_id"] == 2 and info["map_full"] and info["place_id"] == 2
    lost = PlaceIdWrapper(task, Counter(unknown=True), max_places=2)
    obs, info = lost.reset(seed=0)
    assert obs["place_id"] == 2 and info["place_id"] == UNKNOWN and not info["map_full"]


def test_the_default_recognizer_never_outgrows_the_observation(task):
    w = PlaceIdWrapper(task, max_places=1)
    w.reset(seed=0)
    for _ in range(30):  # drives far enough to open several places uncapped
        obs, _, _, _, info = w.step(np.array([1.0, 0.6], np.float32))
    assert info["n_places"] == 1 and info["map_full"]
    assert obs["place_id"] in (0, 1)  # localized on the one place, or unknown


def test_fixed_map_localizes_without_learning(task, tmp_path):
    mapper = PlaceIdWrapper(task)
    mapper.reset(seed=0)
    for _ in range(40):
        mapper.step(np.array([1.0, 0.4], np.float32))
    path = tmp_path / "map.npz"
    mapper.recognizer.save(path, world=task.unwrapped.world_id)
    fixed = OnlinePlaceClustering.load(path, world=task.unwrapped.world_id)
    n = fixed.n_places
    w = PlaceIdWrapper(task, fixed, learn=False)
    w.reset(seed=0)
    for _ in range(20):
        _, _, _, _, info = w.step(np.array([1.0, 0.4], np.float32))
    assert fixed.n_places == n and info["n_places"] == n


def test_a_nested_map_localizes_without_learning(task):
    mapper = PlaceIdWrapper(task, NestedMapper(min_matches=150))
    mapper.reset(seed=0)
    for _ in range(40):
        mapper.step(np.array([1.0, 0.4], np.float32))
    nested = mapper.recognizer
    n, points = nested.n_places, sum(len(loc.descriptors) for loc in nested.locations.values())
    w = PlaceIdWrapper(task, nested, learn=False)
    obs, _ = w.reset(seed=0)
    seen = [obs["place_id"]]
    for _ in range(20):
        obs, _, _, _, info = w.step(np.array([1.0, 0.4], np.float32))
        seen.append(obs["place_id"])
    assert nested.n_places == n == info["n_places"]
    assert sum(len(loc.descriptors) for loc in nested.locations.values()) == points
    assert any(p < n for p in seen)  # the start is on the map it drove


def test_bad_configurations():
    no_pano = gym.make("PlaceNav-ReachRoom-v0", panorama=False)
    with pytest.raises(ValueError, match="panorama"):
        PlaceIdWrapper(no_pano)
    env = gym.make("PlaceNav-ReachRoom-v0")
    with pytest.raises(ValueError, match="localize_one"):
        PlaceIdWrapper(env, RandomPlaces(), learn=False)
    with pytest.raises(ValueError, match="max_places"):
        PlaceIdWrapper(env, max_places=0)


def test_map_of_another_world_is_refused(task, tmp_path):
    model = OnlinePlaceClustering("orb")
    obs, _ = task.reset(seed=0)
    model.learn_one(obs["panorama"])
    model.save(tmp_path / "m.npz", world=task.unwrapped.world_id)
    other = gym.make("PlaceNav-ReachRoom-v0", scene_seed=1, panorama=False).unwrapped.world_id
    with pytest.raises(ValueError, match="is a map of world"):
        OnlinePlaceClustering.load(tmp_path / "m.npz", world=other)


def test_true_room_wrapper():
    env = TrueRoomWrapper(gym.make("PlaceNav-ReachRoom-v0", panorama=False))
    obs, info = env.reset(seed=2)
    assert obs["place_id"] == info["room_id"]
    assert env.observation_space["place_id"].n == len(env.unwrapped.plan.rooms) + 1
