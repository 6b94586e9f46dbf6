"""``python -m train.report``: errand agents on the same buildings, paired against brackets."""

import json

import pytest

from envs.runs.results import write_results
from train.report import main

PROVENANCE = {"suite": None, "size": "full", "definition": {},
              "versions": {"placeclust": "0.13.0"}, "render_fingerprint": "abc"}


def _agent_file(folder, name, recognizer, successes, **settings):
    """``successes[s]``: building s's errands, 1 for a success."""
    rows = []
    for scene, done in enumerate(successes):
        errands = [{"goal": "a", "success": bool(x), "steps": 100 if x else 500, "path": 5.0,
                    "shortest": 4.0, "spl": 0.8 * x, "redrawn": False} for x in done]
        rows.append({"scene_seed": 2000 + scene, "recognizer": recognizer, "agent": "ppo",
                     "success_rate": sum(done) / len(done), "errands": errands,
                     "precision": 1.0, "nmi": 1.0, "n_places": 6, "places_per_room": 1.0,
                     "seconds": 1.0})
    base = {"split": "test", "scene_seeds": [2000 + s for s in range(len(successes))],
            "rooms": 6, "n_errands": 4, "seed": 0, "agent": "ppo",
            "policy": f"runs/train/carried_{name}/best_model.zip",
            "task": {"errand_start": "carried"}}
    path = folder / f"{name}.json"
    write_results(path, rows, [recognizer], {**base, **settings}, PROVENANCE)
    return f"{name}={path}"


@pytest.fixture
def agents(tmp_path):
    return [_agent_file(tmp_path, "noplace", "none", [[0, 0, 0, 1]] * 8),
            _agent_file(tmp_path, "place", "panorama-orb", [[1, 1, 0, 0]] * 4 + [[1, 0, 0, 1]] * 4),
            _agent_file(tmp_path, "oracle", "oracle", [[1, 1, 1, 0]] * 8)]


def test_each_agent_is_paired_against_the_brackets(agents, tmp_path, capsys):
    docs = tmp_path / "bench.md"
    assert main([*agents, "--against", "oracle", "noplace", "--docs", str(docs),
                 "--section", "agents-test"]) == 0
    out = capsys.readouterr().out
    assert "| `place` | carried_place | panorama-orb | 0.50 [0.50, 0.50] |" in out
    # place − oracle, place − noplace
    assert "**-0.25 [-0.25, -0.25]** | **+0.25 [+0.25, +0.25]** |" in out
    assert "`oracle` is at or above every other agent" in out
    assert "errand_start carried" in out and "2000–2007" in out
    text = docs.read_text()
    assert "BEGIN GENERATED agents-test" in text and "python -m train.report" in text


def test_an_upper_bracket_below_another_agent_is_said(agents, capsys):
    assert main([*agents, "--against", "noplace", "oracle"]) == 0
    assert "`noplace` is below `place`, `oracle` beyond the interval" in capsys.readouterr().out


def test_incomparable_files_and_bad_names_are_refused(agents, tmp_path, capsys):
    other = _agent_file(tmp_path, "elsewhere", "oracle", [[1, 1, 1, 1]] * 8, rooms=4)
    assert main([*agents, other, "--against", "oracle"]) == 2
    assert "settings rooms: 6 against 4" in capsys.readouterr().err
    assert main([*agents, "--against", "random"]) == 2
    assert "--against names ['random']" in capsys.readouterr().err
    assert main([agents[0], agents[0], "--against", "noplace"]) == 2
    assert "named twice" in capsys.readouterr().err
    assert main(["noplace", "--against", "noplace"]) == 2
    assert "is not NAME=FILE" in capsys.readouterr().err
    json.loads((tmp_path / "noplace.json").read_text())  # nothing written over


def test_one_recognizer_of_a_leaderboard_file_is_named_with_an_at(agents, tmp_path, capsys):
    rows = []
    for recognizer, done in (("oracle", [1, 1, 1, 1]), ("none", [0, 0, 0, 0])):
        for scene in range(8):
            rows.append({"scene_seed": 2000 + scene, "recognizer": recognizer,
                         "agent": "planner", "success_rate": sum(done) / 4,
                         "errands": [{"goal": "a", "success": bool(x), "steps": 100,
                                      "path": 5.0, "shortest": 4.0, "spl": 0.8 * x,
                                      "redrawn": False} for x in done],
                         "precision": 1.0, "nmi": 1.0, "n_places": 6, "places_per_room": 1.0,
                         "seconds": 1.0})
    board = tmp_path / "board.json"
    write_results(board, rows, ["oracle", "none"],
                  {"split": "test", "scene_seeds": list(range(2000, 2008)), "rooms": 6,
                   "n_errands": 4, "seed": 0, "agent": "planner", "policy": None,
                   "task": {"errand_start": "carried"}}, PROVENANCE)
    assert main([*agents, f"planner={board}@oracle", "--against", "planner"]) == 0
    out = capsys.readouterr().out
    assert "| `planner` | planner | oracle | 1.00 [1.00, 1.00] |" in out
    assert "| `oracle` | carried_oracle | oracle | 0.75 [0.75, 0.75] | 0.60 [0.60, 0.60] | " \
           "**-0.25 [-0.25, -0.25]** |" in out
    assert main([*agents, f"planner={board}", "--against", "planner"]) == 2
    assert "holds the recognizers ['oracle', 'none']; name one" in capsys.readouterr().err
    assert main([*agents, f"planner={board}@panorama", "--against", "planner"]) == 2
    assert "holds no recognizer 'panorama'" in capsys.readouterr().err


def test_training_seeds_are_a_level_of_the_bootstrap(agents, tmp_path, capsys):
    (tmp_path / "s1").mkdir()
    seed1 = _agent_file(tmp_path / "s1", "oracle", "oracle", [[0, 0, 0, 0]] * 8)
    seeded = f"{agents[2]},{seed1.partition('=')[2]}"
    assert main([*agents[:2], seeded, "--against", "oracle", "noplace"]) == 0
    out = capsys.readouterr().out
    # oracle's errands 3 of 4 in seed 0, none in seed 1: 3 of 8 in all, but the buildings are
    # all alike and the seeds are not, so the interval is the seeds' spread, not [0.38, 0.38]
    assert "| `oracle` | carried_oracle + carried_oracle | oracle | 0.38 [0.00, 0.75] |" in out
    assert "| 0.75 / 0.00 |" in out  # each seed's own success
    # pooled as more errands of one agent, oracle (0.38) would be below place (0.50) "beyond
    # the interval"; with its seeds' spread the sample cannot say so
    assert "`oracle` is at or above every other agent within its interval" in out
    other = _agent_file(tmp_path / "s1", "four", "oracle", [[1, 1, 1, 1]] * 8, rooms=4)
    assert main([*agents[:2], f"{agents[2]},{other.partition('=')[2]}",
                 "--against", "oracle"]) == 2
    assert "a seed's file is not comparable" in capsys.readouterr().err
