import json

import pytest

from train.choose import BEST, CHOICE, candidates, choose, main
from train.train import train

TOUR = """
place:
  env: {kind: errands, observe: place, scene_seeds: [0, 1], n_rooms: [3], recognizer: oracle,
        repeat: 2, n_errands: 2, tour_steps_per_room: 40, errand_steps: 30,
        errand_start: carried, layout: [grid, corridor]}
  n_envs: 1
  n_timesteps: 40
  policy: MlpPolicy
  n_steps: 20
  batch_size: 10
  n_epochs: 1
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("choose") / "run"
    config = folder.parent / "tour.yml"
    config.write_text(TOUR)
    train("place", seed=0, out=folder, progress=False, config_path=config)
    for checkpoint in sorted((folder / "checkpoints").glob("*.zip"))[2:]:
        checkpoint.unlink()  # two are enough to choose among, and each costs val errands
    return folder


def test_candidates_are_the_checkpoints_then_the_last_policy(run):
    found = candidates(run)
    assert [d for d, _ in found] == sorted(d for d, _ in found)
    assert found[-1][1] == run / "policy.zip" and found[-1][0] >= 40  # whole rollouts
    assert all(path.parent.name == "checkpoints" for _, path in found[:-1])
    assert len(found) == 3


def test_the_best_val_policy_is_copied_and_every_candidate_recorded(run):
    before = (run / "policy.zip").read_bytes()
    record = choose(run, n_scenes=1, rooms=3, n_errands=1, progress=False)
    assert record["split"] == "val" and record["layouts"] == ["grid", "corridor"]
    assert record["recognizer"] == "oracle" and record["errand_start"] == "carried"
    scores = [c["success_rate"] for c in record["candidates"]]
    assert len(scores) == 3 and record["chosen"]["success_rate"] == max(scores)
    assert (run / BEST).read_bytes() == (run / record["chosen"]["policy"]).read_bytes()
    assert (run / "policy.zip").read_bytes() == before  # the run's own files stay
    assert json.loads((run / CHOICE).read_text()) == record


def test_a_folder_that_is_not_a_run_is_refused(tmp_path, capsys):
    assert main([str(tmp_path), "--no-progress"]) == 2
    assert "not a training run" in capsys.readouterr().err
