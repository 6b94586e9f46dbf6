"""A trained policy's ``config.yml`` says how the closed loop runs it."""

import pytest

from envs.agents.learned import LearnedAgent, config_path


def test_a_checkpoint_is_described_by_its_runs_config(tmp_path):
    run = tmp_path / "carried_place"
    (run / "checkpoints").mkdir(parents=True)
    (run / "config.yml").write_text("env: {observe: place, repeat: 4}\n")
    assert config_path(run / "policy.zip") == run / "config.yml"
    assert config_path(run / "best_model.zip") == run / "config.yml"
    assert config_path(run / "checkpoints" / "ppo_6000_steps.zip") == run / "config.yml"
    shipped = tmp_path / "elsewhere" / "policy.zip"  # no config: a hints agent (the default)
    assert config_path(shipped) == shipped.parent / "config.yml"


def test_a_missing_policy_or_an_unknown_observation_is_named(tmp_path):
    with pytest.raises(FileNotFoundError, match="no policy file"):
        LearnedAgent.load(tmp_path / "policy.zip")
    (tmp_path / "policy.zip").write_bytes(b"not read before the config is checked")
    (tmp_path / "config.yml").write_text("env: {observe: eyes}\n")
    with pytest.raises(ValueError, match="observes 'eyes'"):
        LearnedAgent.load(tmp_path / "policy.zip")
