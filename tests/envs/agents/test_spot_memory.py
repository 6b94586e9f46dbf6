import gymnasium as gym
import numpy as np
import pytest

from envs.agents.spot import SpotPlanner
from envs.agents.spot_memory import SpotMemoryPlanner


@pytest.fixture
def start(made):
    env = gym.make("PlaceNav-ImageGoal-v1", recognizer="oracle", n_rooms=3, n_errands=1,
                   tour_steps_per_room=40)
    made.append(env)
    obs, info = env.reset(seed=0)
    return env, obs, info


def _errand(obs, goal_place, place):
    return {**obs, "errand": np.int64(0), "goal_place": np.int64(goal_place),
            "place_id": np.int64(place)}


def test_a_place_opened_during_the_errands_gets_a_spot_and_no_first_step_stop(start):
    """v4's spot agent declares arrival at once for a goal place the tour never reported (a
    place the map opened by night); this one looks for it, then goes where it saw it."""
    env, obs, info = start
    here = int(obs["place_id"])
    v4 = SpotPlanner(unknown=env.unwrapped.max_places)
    v4.reset(info["tour"], obs)
    assert v4.act(_errand(obs, 7, here))[2] > 0  # the old rule: it stops where it stands
    agent = SpotMemoryPlanner(unknown=env.unwrapped.max_places)
    agent.reset(info["tour"], obs)
    assert agent.spot(7) is None
    assert agent.act(_errand(obs, 7, here))[2] < 0  # not seen yet: it looks for it
    seen = agent.act(_errand(obs, 7, 7))  # the recognizer reports place 7 here
    assert seen[2] < 0 or np.linalg.norm(agent.spot(7) - agent.pos) < 0.3
    assert agent.spot(7) is not None
    assert agent.act(_errand(obs, 7, 7))[2] > 0  # it stands at the spot: arrived


def test_a_tour_place_keeps_the_tours_spot(start):
    env, obs, info = start
    agent = SpotMemoryPlanner(unknown=env.unwrapped.max_places)
    agent.reset(info["tour"], obs)
    v4 = SpotPlanner(unknown=env.unwrapped.max_places)
    v4.reset(info["tour"], obs)
    for place in set(agent.places.tolist()) - {-1}:
        assert np.allclose(agent.spot(place), agent.path[v4.spot(place)])


def test_without_a_goal_place_it_gives_up_at_once(start):
    env, obs, info = start
    agent = SpotMemoryPlanner(unknown=env.unwrapped.max_places)
    agent.reset(info["tour"], obs)
    assert agent.act(_errand(obs, env.unwrapped.max_places, 0))[2] > 0
