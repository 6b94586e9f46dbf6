"""Frozen suites and the provenance every results file carries."""

import dataclasses
import json
import re

import mujoco
import pytest

from envs.commands import leaderboard
from envs.runs.suite import (
    SUITES,
    get_suite,
    physics_fingerprint,
    provenance,
    render_fingerprint,
)
from envs.world.splits import SPLITS


def test_a_suite_reports_on_test_buildings_and_is_frozen():
    for suite in SUITES.values():
        assert suite.split == "test"
        assert set(suite.scene_seeds()) <= set(SPLITS["test"])
        assert len(suite.scene_seeds("quick")) < len(suite.scene_seeds())
        long = suite.task(track="long") if suite.tracks else suite.task("long")
        assert long.tour_steps_per_room >= 500
        with pytest.raises(dataclasses.FrozenInstanceError):
            suite.goals = 1  # type: ignore[misc]
    with pytest.raises(ValueError, match="unknown suite 'placenav-v0'"):
        get_suite("placenav-v0")
    with pytest.raises(ValueError, match="unknown size"):
        SUITES["placenav-v1"].scene_seeds("huge")


def test_placenav_v2_runs_every_track_with_the_relocalizer():
    from envs.runs.suite import TRACKS

    suite = get_suite("placenav-v2")
    # every track there was (v5 added the changed tracks on a fixed map), and v5 runs them all
    before_v5 = [t for t in TRACKS if not t.endswith("-fixed")]
    assert suite.track_names == before_v5 and suite.agent == "relocalizer"
    assert set(get_suite("placenav-v5").track_names) == set(TRACKS)
    assert SUITES["placenav-v1"].agent == "planner" and not SUITES["placenav-v1"].tracks
    for track in suite.track_names:  # the quick size is the full size's first building
        assert suite.scene_seeds("quick", track) == suite.scene_seeds("full", track)[:1]


def test_the_render_and_physics_fingerprints_are_stable_and_recorded():
    prov = provenance(SUITES["placenav-v1"], "quick")
    assert prov["render_fingerprint"] == render_fingerprint() and len(prov["versions"]) > 3
    assert prov["physics_fingerprint"] == physics_fingerprint()
    assert prov["suite"] == "placenav-v1" and prov["definition"]["n_errands"] == 5
    render_fingerprint.cache_clear()
    physics_fingerprint.cache_clear()
    assert render_fingerprint() == prov["render_fingerprint"]  # rendered again: the same
    assert physics_fingerprint() == prov["physics_fingerprint"]  # driven again: the same


def test_a_suite_fixes_its_buildings_and_errands(capsys):
    with pytest.raises(SystemExit):
        leaderboard.main(["--suite", "placenav-v1", "--errands", "3"])
    assert "fixes --errands" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # the old name is the same option, fixed too
        leaderboard.main(["--suite", "placenav-v1", "--goals-per-scene", "3"])
    assert "fixes --goals-per-scene" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # an abbreviation would slip past the check
        leaderboard.main(["--suite", "placenav-v1", "--err", "3"])
    assert "unrecognized arguments: --err" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # a size picks the suite's buildings, not others
        leaderboard.main(["--suite", "placenav-v1", "--size", "quick", "--split", "val"])
    assert "--size picks among the suite's buildings" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        leaderboard.main(["--size", "quick"])
    assert "--size goes with --suite" in capsys.readouterr().err


def _tracked(**sizes: int):
    """A suite of tracks, each sized on its own, like placenav-v2."""
    from envs.runs.suite import Suite

    return Suite(name="tracked-v0", env_id="PlaceNav-GuidedTour-v1", split="test",
                 n_buildings=0, n_quick=1, n_long=0, n_rooms=3, n_errands=1, seed=0,
                 tour_steps_per_room=30, long_tour_steps_per_room=500, agent="relocalizer",
                 tracks=tuple(sizes.items()))


def test_a_suite_of_tracks_sizes_each_track_on_its_own():
    suite = _tracked(continued=3, carried=2, long=1)
    test = list(SPLITS["test"])
    assert suite.scene_seeds("full", "carried") == test[:2]
    assert suite.scene_seeds() == test[:3]  # every track's buildings
    assert suite.scene_seeds("quick", "continued") == test[:1]
    assert suite.task(track="carried").kwargs() == {
        "n_errands": 1, "tour_steps_per_room": 30, "local_light": True,
        "errand_start": "carried"}
    assert suite.task(track="long").tour_steps_per_room == 500
    with pytest.raises(ValueError, match="its long tours|choose one of"):
        suite.scene_seeds("long")
    with pytest.raises(ValueError, match="no track 'corridor'"):
        suite.scene_seeds("full", "corridor")
    with pytest.raises(ValueError, match="runs its tracks one by one"):
        suite.task()


def test_a_suites_smaller_track_costs_no_tour_of_its_own(monkeypatch):
    from envs.runs.suite import track_task

    suite = _tracked(continued=3, carried=2, corridor=1)
    plan = {t: (suite.scene_seeds("full", t), suite.task(track=t)) for t in suite.track_names}
    jobs = leaderboard.suite_jobs(plan, ["oracle"], n_rooms=3, agent="relocalizer", seed=0)
    test = list(SPLITS["test"])
    served = sorted((j["scene_seed"], tuple(sorted(j["tracks"]))) for j in jobs)
    assert served == sorted([(test[0], ("carried", "continued")), (test[0], ("corridor",)),
                             (test[1], ("carried", "continued")), (test[2], ("continued",))])
    assert track_task("corridor")["layout"] == "corridor"


def test_a_suite_of_tracks_runs_them_all_with_its_agent(monkeypatch, tmp_path, capsys):
    suite = _tracked(continued=1, carried=1)
    monkeypatch.setattr(leaderboard, "get_suite", lambda name: suite)
    monkeypatch.setattr(leaderboard, "SUITES", {"tracked-v0": suite})
    with pytest.raises(SystemExit):
        leaderboard.main(["--suite", "tracked-v0", "--size", "long"])
    assert "runs at the sizes full, quick; its long tours are the track" in \
        capsys.readouterr().err
    with pytest.raises(SystemExit):
        leaderboard.main(["--suite", "tracked-v0", "--local-light"])
    assert "fixes --local-light" in capsys.readouterr().err
    assert leaderboard.main(["--suite", "tracked-v0", "--size", "quick", "--recognizers",
                             "oracle", "none", "--workers", "1", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "| recognizer | continued | carried | suite score (mean) |" in out or \
        "no suite score: track" in err  # one building may leave oracle and none level
    # one building: said so, and no half-width rather than nan
    assert "1 building of 3 rooms" in out and not re.search(r"\bnan\b", out)
    # what the figures hold for: the engine and both fingerprints, named in the paragraph
    assert (f"MuJoCo {mujoco.__version__}, render fingerprint `{render_fingerprint()}`, "
            f"physics fingerprint `{physics_fingerprint()}`") in out
    for track in ("continued", "carried"):
        doc = json.loads((tmp_path / track / "results.json").read_text())
        assert doc["settings"]["agent"] == "relocalizer"  # the suite's, not the planner
        assert doc["settings"]["track"] == track and doc["provenance"]["suite"] == "tracked-v0"
        assert doc["settings"]["scene_seeds"] == suite.scene_seeds("quick", track)
    assert len(list((tmp_path / "runs").glob("*.json"))) == 2  # one tour a recognizer


def test_a_suites_settings_run_on_the_buildings_named_and_say_they_are_not_its(
        monkeypatch, tmp_path, capsys):
    suite = _tracked(continued=2, carried=1)
    monkeypatch.setattr(leaderboard, "get_suite", lambda name: suite)
    monkeypatch.setattr(leaderboard, "SUITES", {"tracked-v0": suite})
    assert leaderboard.main(["--suite", "tracked-v0", "--scene-seeds", "1000",
                             "--recognizers", "oracle", "--workers", "1",
                             "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert ("Suite `tracked-v0`'s settings on other buildings than its own (named by the "
            "command, or with doors; not the suite's figures), placeclust") in out
    for track in ("continued", "carried"):
        doc = json.loads((tmp_path / track / "results.json").read_text())
        assert doc["settings"]["scene_seeds"] == [1000]  # every track: the buildings named
        assert doc["settings"]["agent"] == "relocalizer" and doc["settings"]["n_errands"] == 1
        assert doc["provenance"]["suite"] == "tracked-v0"
        assert doc["provenance"]["buildings"] == "named"
    # with doors: the suite's own buildings, their doorways with doors, and said so too
    assert leaderboard.main(["--suite", "tracked-v0", "--doors", "1.0", "--recognizers",
                             "oracle", "--workers", "1", "--out", str(tmp_path / "doors")]) == 0
    doc = json.loads((tmp_path / "doors" / "carried" / "results.json").read_text())
    assert doc["settings"]["task"]["doors"] == 1.0 and doc["provenance"]["buildings"] == "named"
    assert doc["settings"]["scene_seeds"] == suite.scene_seeds("full", "carried")
    with pytest.raises(SystemExit):
        leaderboard.main(["--suite", "tracked-v0", "--doors", "2"])
    assert "--doors must be a fraction" in capsys.readouterr().err


def test_a_recognizer_that_cannot_localize_is_skipped_only_where_the_map_is_fixed(
        monkeypatch, tmp_path, capsys):
    suite = _tracked(continued=1, **{"changed-night-fixed": 1})
    monkeypatch.setattr(leaderboard, "get_suite", lambda name: suite)
    monkeypatch.setattr(leaderboard, "SUITES", {"tracked-v0": suite})
    mine = "examples.tiny_recognizer:HaarPlaces"  # no localize_one
    assert leaderboard.main(["--suite", "tracked-v0", "--recognizers", "oracle", mine,
                             "--workers", "1", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert f"skipped on a fixed map (no localize_one): {mine} (tracks changed-night-fixed)" \
        in err
    learning = json.loads((tmp_path / "continued" / "results.json").read_text())
    fixed = json.loads((tmp_path / "changed-night-fixed" / "results.json").read_text())
    assert [s["recognizer"] for s in learning["summaries"]] == ["oracle", mine]
    assert [s["recognizer"] for s in fixed["summaries"]] == ["oracle"]
    assert fixed["settings"]["skipped"] == [mine] and "skipped" not in learning["settings"]
    assert len(list((tmp_path / "runs").glob("*.json"))) == 2  # one tour a recognizer


def test_placenav_v5_asks_v4s_question_with_the_same_goals_for_all():
    """v5 runs PlaceNav-ImageGoal-v1 with the spot agent that remembers its errands, the
    gyro's heading and goals off the route; its changed tracks run on a fixed map too, and a
    building's one tour serves every lit track."""
    v5, v4 = SUITES["placenav-v5"], SUITES["placenav-v4"]
    assert v5.agent == "spot-memory" and v5.n_errands == v4.n_errands
    assert set(v4.track_names) < set(v5.track_names)
    fixed = v5.task(track="changed-night-fixed")
    assert fixed.errand_learn is False and fixed.errand_condition == "night"
    assert (fixed.env_id, fixed.goal_kind, fixed.compass) == (
        "PlaceNav-ImageGoal-v1", "image", "mpu9250")
    assert "env_id" not in v4.task(track="continued").kwargs()  # v4's jobs keep their names
    assert "long" not in v5.tracks_at("quick") and len(v5.tracks_at("quick")) == 10
    assert v5.task("quick", "continued").n_errands == 5 and v4.tracks_at("quick") == \
        v4.track_names  # v4's quick size as published
    plan = {t: (v5.scene_seeds("quick", t), v5.task(track=t)) for t in v5.track_names}
    jobs = leaderboard.suite_jobs(plan, ["oracle"], n_rooms=6, agent=v5.agent, seed=v5.seed)
    lit = [j for j in jobs if j.get("local_light")]
    assert len(lit) == 1 and len(lit[0]["tracks"]) == 8
    assert all(j["env_id"] == "PlaceNav-ImageGoal-v1" for j in jobs)
