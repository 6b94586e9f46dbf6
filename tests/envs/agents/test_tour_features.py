import gymnasium as gym
import numpy as np
import pytest

from envs.agents.roadmap import Roadmap
from envs.agents.tour_features import (
    AHEAD,
    JOIN,
    N_BASE,
    N_PLACE,
    NODE_SPACING,
    SENSES,
    Anchored,
    TourFeatures,
    n_features,
    way_block,
)

SMALL = {"recognizer": "oracle", "n_rooms": 3, "n_errands": 3, "tour_steps_per_room": 40,
         "errand_steps": 30}


@pytest.fixture
def features(made):
    def _make(senses, **kwargs):
        made.append(TourFeatures(gym.make("PlaceNav-GuidedTour-v1", **{**SMALL, **kwargs}),
                                 senses))
        return made[-1]

    return _make


def _drive(env, seed, steps=60):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    out = [obs]
    for _ in range(steps):
        obs, _, done, _, _ = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        out.append(obs)
        if done:
            break
    return np.array(out)


def test_the_way_follows_the_tours_roadmap_around_a_corner():
    # an L-shaped tour: 5 m east, then 5 m north; the goal at its end
    east = np.stack([np.linspace(0, 5, 101), np.zeros(101)], axis=1)
    north = np.stack([np.full(100, 5.0), np.linspace(0.05, 5, 100)], axis=1)
    route = Roadmap(np.concatenate([east, north]), spacing=NODE_SPACING, join=JOIN)
    goal = route.node_of_step(200)
    carrot, left = route.way(goal, np.array([1.0, 0.0]), AHEAD)
    assert carrot == pytest.approx([2.0, 0.0], abs=0.35)  # along the tour, not across
    assert left == pytest.approx(9.0, abs=0.3)
    yaw = np.pi / 2  # facing +y: the carrot 1 m along +x is 1 m to the right
    ahead, side, distance, known = way_block(route, goal, np.array([1.0, 0.0]), yaw)
    assert (ahead, side, known) == pytest.approx((0.0, -1.0, 1.0), abs=0.35)
    assert distance == pytest.approx(0.9, abs=0.03)
    assert way_block(route, goal, None, 0.0) == [0.0] * 4


def test_a_position_is_anchored_where_the_tour_was_in_that_place():
    anchored = Anchored({3: np.array([1.0, 2.0])})
    anchored.update(-1, np.array([1.0, 0.0]))
    assert anchored.position is None and not anchored.changed
    anchored.update(3, np.array([1.0, 0.0]))
    assert anchored.changed and anchored.position.tolist() == [1.0, 2.0]
    anchored.update(3, np.array([0.5, 0.0]))
    assert not anchored.changed and anchored.position.tolist() == [1.5, 2.0]
    anchored.update(7, np.zeros(2))  # a place the tour never saw
    assert anchored.changed and anchored.position is None
    anchored.lose()
    assert anchored.label is None and not anchored.precise
    # moving between two places the tour crossed between: anchored at the crossing
    anchored = Anchored({3: np.array([1.0, 2.0]), 4: np.array([5.0, 2.0])},
                        {(3, 4): np.array([3.0, 2.0])})
    anchored.update(4, np.zeros(2))
    assert anchored.position.tolist() == [5.0, 2.0] and not anchored.precise
    anchored.update(3, np.zeros(2))
    assert anchored.position.tolist() == [3.0, 2.0] and anchored.precise


def test_each_agent_sees_what_the_one_before_sees_and_more(features):
    runs = {s: _drive(features(s), seed=2) for s in SENSES}
    for senses, obs in runs.items():
        assert obs.shape[1] == n_features(senses) and np.all(np.abs(obs) <= 2.0)
    assert np.array_equal(runs["noplace"], runs["place"][:, :N_BASE])
    # the same, but for the oracle's dead reckoning, corrected once it moves between rooms
    place, oracle = runs["place"], runs["oracle"]
    assert np.array_equal(place[:, :N_BASE - 4], oracle[:, :N_BASE - 4])
    assert np.array_equal(place[:, N_BASE:], oracle[:, N_BASE:N_BASE + N_PLACE])
    assert np.array_equal(place[0], oracle[0, :N_BASE + N_PLACE])
    # with a recognizer right about every room, the place is the room
    assert np.allclose(oracle[:, N_BASE:N_BASE + N_PLACE], oracle[:, N_BASE + N_PLACE:])


def test_dead_reckoning_is_lost_when_the_robot_is_carried(features):
    kept = _drive(features("place"), seed=3)
    assert np.all(kept[:, N_BASE - 1] == 1.0)  # known from the tour on
    carried = _drive(features("place", errand_start="carried"), seed=3)
    assert np.all(carried[:, N_BASE - 1] == 0.0)  # never known after a carry
    assert carried[:, N_BASE + 3].max() >= 0.5  # the place tells it where it is
    # nothing to re-anchor: the carried agents see what they were trained on
    noplace = _drive(features("noplace", errand_start="carried"), seed=3)
    assert np.array_equal(noplace, carried[:, :N_BASE])


def _pursue(obs):
    """Drive toward the carrot of the way from dead reckoning (pure pursuit)."""
    ahead, side = obs[N_BASE - 4], obs[N_BASE - 3]
    return np.clip([ahead, 2.0 * side], -1.0, 1.0).astype(np.float32)


def test_only_the_oracles_dead_reckoning_is_re_anchored_where_it_crosses_a_door(features):
    crossings = {}
    for senses in ("place", "oracle"):
        env = features(senses, n_errands=2, errand_steps=200)
        obs, _ = env.reset(seed=4)
        crossings[senses], done = [], False
        while not done:
            label = obs[-N_PLACE:]  # the place's block, or the true room's
            if label[5] == 1.0 and label[3] == 1.0:  # just entered where the tour crossed
                crossings[senses].append(np.abs(obs[N_BASE - 4:N_BASE] - label[:4]).max())
            obs, _, done, _, _ = env.step(_pursue(obs))
    assert crossings["oracle"] and max(crossings["oracle"]) < 1e-6
    assert crossings["place"] and max(crossings["place"]) > 1e-3  # its own, drifting


def test_unknown_senses_are_refused(made):
    made.append(gym.make("PlaceNav-GuidedTour-v1", **SMALL))
    with pytest.raises(ValueError, match="unknown senses 'eyes'"):
        TourFeatures(made[-1], "eyes")


def test_a_held_action_sums_the_rewards_of_its_steps(made):
    totals = {}
    for repeat in (1, 3):
        made.append(TourFeatures(gym.make("PlaceNav-GuidedTour-v1", **SMALL), "noplace",
                                 repeat=repeat))
        env = made[-1]
        env.reset(seed=6)
        done, total, decisions = False, 0.0, 0
        while not done:
            _, reward, done, _, info = env.step(np.array([0.5, 0.2], np.float32))
            total, decisions = total + reward, decisions + 1
        totals[repeat] = (total, decisions, [e["steps"] for e in info["errands"]])
    (one, n_one, steps_one), (three, n_three, steps_three) = totals[1], totals[3]
    assert steps_one == steps_three and one == pytest.approx(three)
    assert n_three < n_one
