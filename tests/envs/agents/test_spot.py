import gymnasium as gym
import numpy as np
import pytest

from envs.agents.spot import SpotPlanner
from envs.runs.task_spec import ErrandTask
from envs.runs.tour_errands import check_goals, run_scene

TASK = {"goal_kind": "image", "tour_steps_per_room": 60}


def _run(recognizer, seed=0, **kw):
    return run_scene(1000, n_rooms=4, recognizer=recognizer, agent="spot", n_errands=4,
                     seed=seed, **{**TASK, **kw})


def test_the_ceiling_stops_at_the_goal():
    """Fails if the agent stops short of its target or drives to the wrong spot."""
    row = _run("oracle-pose")
    assert row["success_rate"] == 1.0 and row["final_distance"] < 0.6


def test_without_a_goal_place_the_agent_gives_up_at_once():
    row = _run("none")
    assert row["success_rate"] == 0.0 and row["mean_length"] == 1.0


def test_finer_places_bring_the_agent_nearer_the_goal():
    """Fails if the agent ignores the place it is given (true rooms and cells of a quarter
    of a room would then end alike)."""
    rooms = [_run("oracle", seed=s)["final_distance"] for s in range(3)]
    cells = [_run("oracle-cells:4", seed=s)["final_distance"] for s in range(3)]
    assert np.mean(cells) < np.mean(rooms)


def test_the_medoid_is_the_step_nearest_all_of_its_place(made):
    env = gym.make("PlaceNav-ImageGoal-v0", recognizer="oracle", n_rooms=3, n_errands=1,
                   tour_steps_per_room=40)
    made.append(env)
    obs, info = env.reset(seed=0)
    agent = SpotPlanner(unknown=env.unwrapped.max_places)
    agent.reset(info["tour"], obs)
    steps = np.flatnonzero(agent.places == 0)
    points = agent.path[steps]
    total = np.linalg.norm(points[:, None] - points[None], axis=2).sum(axis=1)
    assert total[list(steps).index(agent.spot(0))] <= total.min() + 1e-6
    assert agent.spot(99) is None


def test_agents_run_only_the_goals_they_can():
    check_goals("spot", [ErrandTask(goal_kind="image")])
    with pytest.raises(ValueError, match="relocalizer agent cannot run errands to image"):
        check_goals("relocalizer", [ErrandTask(), ErrandTask(goal_kind="image")])
    with pytest.raises(ValueError, match="spot agent cannot run errands to room"):
        check_goals("spot", [ErrandTask()])
    with pytest.raises(ValueError, match="relocalizer agent cannot run errands to image"):
        run_scene(1000, agent="relocalizer", tracks={"carried": {"goal_kind": "image"}})


def test_more_errands_begin_with_the_errands_of_fewer():
    """A suite with more errands a building (placenav-v4's 15) holds the shorter suite's
    (v3's 5) goal for goal, so their figures can be read together. Fails if a goal, a carry or
    the agent's seed is drawn from a stream whose draws depend on how many errands follow."""
    def errands(n, **kw):
        row = run_scene(1000, n_rooms=4, recognizer="oracle-cells:2", agent="spot", n_errands=n,
                        seed=0, tracks={"continued": {}, "carried": {"errand_start": "carried"}},
                        **{**TASK, **kw})
        return {t: [(e["goal"], e["steps"], e["success"], round(e["final_distance"], 6))
                    for e in r["errands"]] for t, r in row["tracks"].items()}

    short, longer = errands(2), errands(5)
    for track in short:
        assert longer[track][:2] == short[track] and len(longer[track]) == 5
