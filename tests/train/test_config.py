from pathlib import Path

import pytest

from train.config import HYPERPARAMS, env_section, load_config, read_config

BASE = """
default: &default
  env: {scene_seed: 0, n_rooms: 4, max_episode_steps: 150}
  n_timesteps: 1000
  policy_kwargs: {net_arch: [64, 64]}
place:
  <<: *default
oracle:
  <<: *default
"""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text)
    return path


def test_a_child_file_changes_only_the_keys_it_names(tmp_path):
    write(tmp_path, "ppo.yml", BASE)
    child = write(tmp_path, "short.yml", """
base: ppo.yml
all:
  env: {range_limit: 0.8}
place:
  n_timesteps: 500
""")
    place, oracle = load_config("place", child), load_config("oracle", child)
    assert place["env"] == {"scene_seed": 0, "n_rooms": 4, "max_episode_steps": 150,
                            "range_limit": 0.8}
    assert place["n_timesteps"] == 500 and oracle["n_timesteps"] == 1000
    assert place["policy_kwargs"] == {"net_arch": [64, 64]}
    assert env_section(child, "planner")["range_limit"] == 0.8  # default's, for the planner
    assert "range_limit" not in load_config("place", tmp_path / "ppo.yml")["env"]


def test_a_base_can_have_a_base(tmp_path):
    write(tmp_path, "ppo.yml", BASE)
    write(tmp_path, "mid.yml", "base: ppo.yml\nall: {env: {n_rooms: 8}}\n")
    top = write(tmp_path, "top.yml", "base: mid.yml\nall: {env: {range_limit: 1.0}}\n")
    assert load_config("oracle", top)["env"] == {"scene_seed": 0, "n_rooms": 8,
                                                 "max_episode_steps": 150, "range_limit": 1.0}


def test_bad_files_are_named(tmp_path):
    write(tmp_path, "ppo.yml", BASE)
    loop = write(tmp_path, "a.yml", "base: b.yml\n")
    write(tmp_path, "b.yml", "base: a.yml\n")
    with pytest.raises(ValueError, match="include each other"):
        read_config(loop)
    extra = write(tmp_path, "extra.yml", "base: ppo.yml\nnoplace: {n_timesteps: 5}\n")
    with pytest.raises(ValueError, match=r"sections \['noplace'\] that its base does not have"):
        read_config(extra)
    orphan = write(tmp_path, "orphan.yml", "all: {env: {n_rooms: 8}}\n")
    with pytest.raises(ValueError, match="no 'base'"):
        read_config(orphan)
    with pytest.raises(FileNotFoundError):
        read_config(write(tmp_path, "gone.yml", "base: missing.yml\n"))
    with pytest.raises(ValueError, match="no section 'noplace'"):
        load_config("noplace", tmp_path / "ppo.yml")


def test_the_shipped_proximity_robot_differs_from_the_main_one_only_in_range():
    proximity = read_config(HYPERPARAMS.parent / "ppo_proximity.yml")
    for name, section in read_config(HYPERPARAMS).items():
        assert proximity[name] == {**section, "env": {**section["env"], "range_limit": 0.8}}


def test_the_corridor_config_changes_the_world_and_budget_not_the_ppo_settings():
    corridor = read_config(HYPERPARAMS.parent / "ppo_corridor.yml")
    world = {"layout": "corridor", "n_rooms": 5, "control_dt": 0.4, "max_episode_steps": 125}
    for name, section in read_config(HYPERPARAMS).items():
        assert corridor[name] == {**section, "env": {**section["env"], **world},
                                  "n_timesteps": 200000}
