import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from train.config import load_config  # noqa: E402
from train.evaluate import POLICIES, evaluate, main  # noqa: E402
from train.make import make_env  # noqa: E402
from train.train import train  # noqa: E402

TINY = """
default: &default
  env: {scene_seed: 0, n_rooms: 4, control_dt: 0.2, max_episode_steps: 20}
  n_envs: 1
  n_timesteps: 256
  policy: MultiInputPolicy
  n_steps: 128
  batch_size: 64
  n_epochs: 1
place:
  <<: *default
oracle:
  <<: *default
"""


@pytest.fixture
def tiny_config(tmp_path):
    path = tmp_path / "ppo.yml"
    path.write_text(TINY)
    return path


@pytest.mark.parametrize("agent", ["oracle", "place"])
def test_a_short_training_run_completes(agent, tiny_config, tmp_path):
    out = tmp_path / agent
    policy = train(agent, seed=1, out=out, map_dir=POLICIES, progress=False,
                   config_path=tiny_config)
    assert policy.is_file() and (out / "progress.csv").read_text().strip()
    info = json.loads((out / "train_info.json").read_text())
    assert info["timesteps"] == 256 and info["agent"] == agent
    scores = evaluate("ppo" if agent == "place" else agent, 1, seed=1000, policy=policy,
                      map_dir=out, config_path=tiny_config)
    assert 0.0 <= scores["success_rate"] <= 1.0 and scores["mean_length"] >= 1


def test_unknown_agent_and_section(tiny_config):
    with pytest.raises(ValueError, match="no section 'noplace'"):
        load_config("noplace", tiny_config)
    with pytest.raises(ValueError, match="unknown agent"):
        make_env("telepathic")
    with pytest.raises(ValueError, match="needs map_path"):
        make_env("place")


def test_evaluate_cli_writes_json_and_reports_bad_input(tmp_path, capsys):
    out = tmp_path / "random.json"
    assert main(["--agent", "random", "--episodes", "2", "--seed", "1000",
                 "--json", str(out)]) == 0
    scores = json.loads(out.read_text())
    assert {"success_rate", "mean_length", "spl"} <= set(scores)
    assert 0.0 <= scores["spl"] <= scores["success_rate"] <= 1.0
    assert main(["--agent", "ppo", "--policy", str(tmp_path / "none.zip"),
                 "--episodes", "1"]) == 2
    assert "no policy file" in capsys.readouterr().err
    assert main(["--agent", "random", "--episodes", "0"]) == 2


def test_the_planner_reaches_rooms_on_the_recognizers_graph():
    """Fault caught: a planner that does not steer by the shipped map's graph (random
    actions, or standing still) reaches 0 of these 4 rooms in the 150 steps allowed; the
    planner reaches 3."""
    scores = evaluate("planner", 4, seed=1000)
    assert scores["episodes"] == 4
    assert scores["success_rate"] >= 0.5 and scores["spl"] > 0.3
    assert scores["mean_length"] < 150  # episodes end at the goal, not at the step cap


def test_shipped_map_matches_the_default_world():
    env = make_env("place", map_path=Path(POLICIES) / "map.npz")
    env.close()


def test_build_map_takes_the_configs_recognizer_arguments(tmp_path):
    from placeclust import OnlinePlaceClustering
    from train.mapping import build_map

    path = build_map(tmp_path, steps=30, progress=False, recognizer={"t_new_cluster": 0.92})
    model = OnlinePlaceClustering.load(path)
    assert model.t_new_cluster == 0.92 and model.n_places >= 1
    # the shipped config builds the place agent's map with the threshold it documents
    assert load_config("place")["map"] == {"t_new_cluster": 0.92}


def test_single_threaded_training_restores_the_threads(monkeypatch):
    import os

    import torch

    from train.train import _one_thread_each

    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    before = torch.get_num_threads()
    with _one_thread_each(True):
        assert torch.get_num_threads() == 1 and os.environ["OMP_NUM_THREADS"] == "1"
    assert torch.get_num_threads() == before and "OMP_NUM_THREADS" not in os.environ
    monkeypatch.setenv("OMP_NUM_THREADS", "2")  # a user's choice wins and survives
    with _one_thread_each(True):
        assert os.environ["OMP_NUM_THREADS"] == "2"
    assert os.environ["OMP_NUM_THREADS"] == "2"


def test_sensors_narrow_what_every_agent_observes():
    env = make_env("noplace", sensors=["goal", "heading", "odometry"])
    assert set(env.observation_space.spaces) == {"goal", "heading", "odometry"}
    obs, _ = env.reset(seed=0)
    assert set(obs) == {"goal", "heading", "odometry"}
    env.close()
    env = make_env("oracle", sensors=["odometry", "goal"])  # the config's order does not matter
    assert list(env.observation_space.spaces) == sorted(["place_id", "goal", "odometry"])
    env.close()


@pytest.mark.parametrize("sensors, message", [
    (["goal", "lidar"], "unknown sensors \\['lidar'\\]"),
    (["heading", "ranges"], "lack 'goal'"),
    ("goal", "list of names"),
])
def test_bad_sensors_are_named(sensors, message):
    with pytest.raises(ValueError, match=message):
        make_env("noplace", sensors=sensors)


def test_range_limit_makes_proximity_sensors():
    env = make_env("noplace", range_limit=0.8)
    assert env.observation_space["ranges"].high.max() == pytest.approx(0.8)
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs) and obs["ranges"].max() <= np.float32(0.8)
    env.close()
    with pytest.raises(ValueError, match="range_limit must be in"):
        make_env("noplace", range_limit=0.0)


def test_the_planner_needs_rangefinders(tiny_config, tmp_path, capsys):
    from train.evaluate import _table_agents

    with pytest.raises(ValueError, match="must include .heading. and .ranges."):
        make_env("planner", map_path=Path(POLICIES) / "map.npz", sensors=["goal", "heading"])
    blind = tmp_path / "blind.yml"
    blind.write_text(TINY.replace("max_episode_steps: 20}",
                                  "max_episode_steps: 20, sensors: [goal, heading]}"))
    assert "planner" not in _table_agents(blind)
    assert "left out" in capsys.readouterr().err
    assert "planner" in _table_agents(tiny_config)


def test_shipped_proximity_policies_fit_their_config():
    config = Path(__file__).resolve().parents[2] / "train" / "hyperparams" / "ppo_proximity.yml"
    for agent in ("noplace", "oracle"):  # the place agent's env renders; same check, slower
        scores = evaluate(agent, 1, seed=1000, config_path=config,
                          policies=Path(POLICIES) / "proximity")
        assert scores["episodes"] == 1


def test_a_corridor_map_is_built_in_the_corridor_and_refused_elsewhere(tmp_path):
    from train.train import prepare_map

    env_cfg = {"scene_seed": 0, "n_rooms": 5, "layout": "corridor", "max_episode_steps": 20}
    path = prepare_map("place", tmp_path, env_cfg, None, progress=False)
    make_env("place", map_path=path, **env_cfg).close()  # its world: accepted
    with pytest.raises(ValueError, match="layout=corridor"):
        make_env("place", map_path=path, n_rooms=5)  # the grid world of 5 rooms: refused


def test_shipped_corridor_policies_and_map_fit_their_config(tmp_path):
    """``--policies assets/policies/corridor`` finds its own map: without it the place agent
    would load the grid world's map and be refused."""
    config = Path(__file__).resolve().parents[2] / "train" / "hyperparams" / "ppo_corridor.yml"
    out = tmp_path / "ppo.json"
    assert main(["--agent", "ppo", "--episodes", "1", "--config", str(config),
                 "--policies", str(Path(POLICIES) / "corridor"), "--json", str(out)]) == 0
    assert json.loads(out.read_text())["episodes"] == 1


def test_agents_train_only_on_train_split_buildings(tmp_path):
    base = Path(__file__).resolve().parents[2] / "train" / "hyperparams" / "ppo.yml"
    test_world = tmp_path / "test_world.yml"
    test_world.write_text(f"base: {base}\nall:\n  env:\n    scene_seed: 2000\n")
    with pytest.raises(ValueError, match="not in the 'train' split"):
        train("noplace", 0, tmp_path / "run", timesteps=64, config_path=test_world)
    assert not (tmp_path / "run").exists()


TOUR = """
default: &default
  env: {kind: errands, observe: noplace, scene_seeds: [0, 1], n_rooms: [3], recognizer: oracle,
        repeat: 2,
        n_errands: 2, tour_steps_per_room: 40, errand_steps: 30, errand_start: carried}
  n_envs: 1
  n_timesteps: 128
  policy: MlpLstmPolicy
  algo: recurrent_ppo
  n_steps: 64
  batch_size: 32
  n_epochs: 1
noplace_lstm:
  <<: *default
"""


def test_a_memory_agent_trains_on_tours_and_runs_in_the_closed_loop(tmp_path):
    pytest.importorskip("sb3_contrib")
    from envs.runs.tour_errands import run_scene

    config = tmp_path / "tour.yml"
    config.write_text(TOUR)
    policy = train("noplace_lstm", seed=0, out=tmp_path / "run", progress=False,
                   config_path=config)
    info = json.loads((tmp_path / "run" / "train_info.json").read_text())
    assert info["algo"] == "recurrent_ppo" and info["timesteps"] == 128
    from envs.agents.learned import LearnedAgent

    agent = LearnedAgent.load(policy)
    assert (agent.observe, agent.recurrent, agent.repeat) == ("noplace", True, 2)
    row = run_scene(2000, n_rooms=3, recognizer="oracle", agent="ppo", n_errands=2,
                    policy=policy, tour_steps_per_room=40, errand_steps=30,
                    errand_start="carried")
    assert len(row["errands"]) == 2 and 0.0 <= row["success_rate"] <= 1.0


def test_a_config_with_an_unknown_learner_is_refused(tmp_path):
    config = tmp_path / "tour.yml"
    config.write_text(TOUR.replace("recurrent_ppo", "dqn"))
    with pytest.raises(ValueError, match="unknown algo 'dqn'"):
        train("noplace_lstm", out=tmp_path / "run", progress=False, config_path=config)
