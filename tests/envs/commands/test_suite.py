"""Frozen suites and the provenance every results file carries."""

import dataclasses

import pytest

from envs.commands import leaderboard
from envs.commands.suite import SUITES, get_suite, provenance, render_fingerprint
from envs.world.splits import SPLITS


def test_a_suite_reports_on_test_buildings_and_is_frozen():
    for suite in SUITES.values():
        assert suite.split == "test"
        assert set(suite.scene_seeds()) <= set(SPLITS["test"])
        assert len(suite.scene_seeds("quick")) < len(suite.scene_seeds())
        assert suite.task("long")["tour_steps_per_room"] >= 500
        with pytest.raises(dataclasses.FrozenInstanceError):
            suite.goals = 1  # type: ignore[misc]
    with pytest.raises(ValueError, match="unknown suite 'placenav-v0'"):
        get_suite("placenav-v0")
    with pytest.raises(ValueError, match="unknown size"):
        SUITES["placenav-v1"].scene_seeds("huge")


def test_the_render_fingerprint_is_stable_and_recorded():
    prov = provenance(SUITES["placenav-v1"], "quick")
    assert prov["render_fingerprint"] == render_fingerprint() and len(prov["versions"]) > 3
    assert prov["suite"] == "placenav-v1" and prov["definition"]["goals"] == 5
    render_fingerprint.cache_clear()
    assert render_fingerprint() == prov["render_fingerprint"]  # rendered again: the same


def test_a_suite_fixes_its_buildings_and_errands(capsys):
    with pytest.raises(SystemExit):
        leaderboard.main(["--suite", "placenav-v1", "--goals-per-scene", "3"])
    assert "fixes --goals-per-scene" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # an abbreviation would slip past the check
        leaderboard.main(["--suite", "placenav-v1", "--goals", "3"])
    assert "unrecognized arguments: --goals" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        leaderboard.main(["--size", "quick"])
    assert "--size goes with --suite" in capsys.readouterr().err
