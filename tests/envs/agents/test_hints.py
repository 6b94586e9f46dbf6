import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401
from envs.agents.hints import N_FEATURES, PlannerHints, residual

TASK = {"recognizer": "oracle", "n_rooms": 3, "n_errands": 1, "tour_steps_per_room": 40,
        "errand_steps": 300}  # v1: the first errand walks 3 m


def test_a_zero_correction_is_the_planner():
    env = PlannerHints(gym.make("PlaceNav-GuidedTour-v1", scene_seed=0, **TASK))
    try:
        obs, _ = env.reset(seed=0)
        assert obs.shape == (N_FEATURES,) and obs in env.observation_space
        assert residual(obs, np.zeros(2)) == pytest.approx(obs[:2])
        done = False
        while not done:  # zero corrections drive the planner's errand to its end
            obs, _, done, _, info = env.step(np.zeros(2, np.float32))
        assert info["errands"][0]["success"]
    finally:
        env.close()
    assert residual(np.array([0.9, -0.9]), np.array([0.5, -0.5])) == pytest.approx([1.0, -1.0])


def test_the_shipped_policy_runs_errands_and_a_missing_one_is_named(tmp_path):
    pytest.importorskip("stable_baselines3")  # the train extra
    from envs.commands.closed_loop import run_scene

    row = run_scene(3, n_rooms=3, recognizer="oracle", agent="ppo", goals=2, seed=0,
                    tour_steps_per_room=40)
    assert len(row["errands"]) == 2 and 0.0 <= row["success_rate"] <= 1.0
    with pytest.raises(FileNotFoundError, match="no policy file .*python -m train.train"):
        run_scene(3, recognizer="oracle", agent="ppo", policy=tmp_path / "none.zip")
