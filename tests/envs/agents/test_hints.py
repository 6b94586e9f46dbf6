import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401
from envs.agents.hints import N_FEATURES, PlannerHints, residual
from envs.agents.teach_repeat import TourPlanner

TASK = {"recognizer": "oracle", "n_rooms": 3, "n_errands": 1, "tour_steps_per_room": 40,
        "errand_steps": 300}  # v1: the first errand walks 3 m


def _drive(env, act_of):
    """The robot's positions over one episode, acting by ``act_of(env, obs, info)``'s
    per-step function, and the episode's errands."""
    obs, info = env.reset(seed=0)
    act = act_of(env, obs, info)
    nav = env.unwrapped.nav
    path, done = [], False
    while not done:
        obs, _, done, _, info = env.step(act(obs))
        path.append(nav.robot.pose(nav.data)[:2].copy())
    env.close()
    return np.array(path), info["errands"]


def test_a_zero_correction_drives_the_robot_as_the_planner_does():
    """Fault caught: the wrapper acting on stale features (a step late, or the first step's
    forever), or adding the correction to anything but the planner's action: the path then
    leaves the planner's own."""

    def planner(env, obs, info):
        p = TourPlanner(unknown=env.unwrapped.max_places, seed=0)
        p.reset(info["tour"], obs)
        return p.act

    def hints_with_zeros(env, obs, info):
        assert obs.shape == (N_FEATURES,) and obs in env.observation_space
        assert residual(obs, np.zeros(2)) == pytest.approx(obs[:2])
        return lambda _obs: np.zeros(2, np.float32)

    alone, errands = _drive(gym.make("PlaceNav-GuidedTour-v1", scene_seed=0, **TASK), planner)
    wrapped, errands_wrapped = _drive(
        PlannerHints(gym.make("PlaceNav-GuidedTour-v1", scene_seed=0, **TASK)),
        hints_with_zeros)
    assert errands[0]["success"]  # the planner's errand, which the wrapper must repeat
    assert wrapped.shape == alone.shape and np.allclose(wrapped, alone, atol=1e-6)
    assert errands_wrapped[0]["success"] and errands_wrapped[0]["steps"] == errands[0]["steps"]
    assert residual(np.array([0.9, -0.9]), np.array([0.5, -0.5])) == pytest.approx([1.0, -1.0])


def test_the_shipped_policy_runs_errands_and_a_missing_one_is_named(tmp_path):
    pytest.importorskip("stable_baselines3")  # the train extra
    from envs.runs.tour_errands import run_scene

    row = run_scene(3, n_rooms=3, recognizer="oracle", agent="ppo", n_errands=2, seed=0,
                    tour_steps_per_room=40)
    assert len(row["errands"]) == 2 and 0.0 <= row["success_rate"] <= 1.0
    with pytest.raises(FileNotFoundError, match="no policy file .*python -m train.train"):
        run_scene(3, recognizer="oracle", agent="ppo", policy=tmp_path / "none.zip")
