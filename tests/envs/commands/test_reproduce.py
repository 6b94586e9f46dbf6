"""``python -m envs.commands.reproduce``: a shipped store's rows come out of this install."""

import json
import shutil
from pathlib import Path

import pytest

from envs.commands import reproduce

STORES = Path(__file__).resolve().parents[3] / "docs" / "runs"
V4 = STORES / "placenav-v4"


def test_differences_name_each_field_that_moved_and_ignore_timings():
    stored = {"seconds": 3.0, "stamp": {}, "tracks": {"night": {"agent": "spot", "errands": [
        {"success": True, "spl": 0.5}, {"success": False, "spl": 0.0}]}}}
    same = json.loads(json.dumps(stored))
    same["seconds"] = 9.0  # a timing
    same["tracks"]["night"]["n_places"] = 7  # recorded only by a newer version
    assert reproduce.differences(stored, same) == []
    moved = json.loads(json.dumps(same))
    moved["tracks"]["night"]["errands"][1]["spl"] = 0.25
    del moved["tracks"]["night"]["agent"]
    assert reproduce.differences(stored, moved) == [
        "tracks.night.agent: \"spot\" -> (missing)", "tracks.night.errands[1].spl: 0.0 -> 0.25"]


def test_a_store_drawn_by_another_renderer_is_refused_in_one_line(tmp_path, capsys):
    store = tmp_path / "placenav-v4"
    shutil.copytree(V4 / "carried", store / "carried")
    (store / "runs").mkdir()
    row = json.loads(next((V4 / "runs").glob("none-*.json")).read_text())
    row["stamp"]["render_fingerprint"] = "0000000000000000"
    (store / "runs" / f"{row['key']}.json").write_text(json.dumps(row))
    assert reproduce.main([str(store)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "render fingerprint 0000000000000000" in err


def test_a_folder_that_is_no_suite_store_is_bad_input(tmp_path, capsys):
    assert reproduce.main([str(tmp_path)]) == 2
    assert "holds no results file of a suite" in capsys.readouterr().err


def test_a_stored_row_finds_its_job_under_todays_key():
    row = json.loads(next((V4 / "runs").glob("oracle-pose-*scene2010-*.json")).read_text())
    job = reproduce.job_of(row, "placenav-v4")
    assert job["scene_seed"] == 2010 and job["recognizer"] == "oracle-pose"
    assert set(job["tracks"]) == set(row["tracks"])


@pytest.mark.parametrize("suite, recognizers", [("placenav-v4", ("nested", "oracle-pose")),
                                                ("placenav-v5", ("nested",))])
def test_this_install_gives_a_shipped_stores_rows_again(suite, recognizers):
    """The cheapest job of a recognizer that reads pixels (seed 001's mapper, ~40 s a suite)
    and, for v4, the cheapest oracle's, row for row: the pinned environment reproduces the
    shipped stores (v5's on its own gyro, goals and agent). A machine whose renderer draws
    other pixels cannot, and says which."""
    rows = reproduce.stored_rows(STORES / suite)
    unlike = reproduce.unlike_here(rows[0])
    if unlike:
        pytest.skip(f"{suite}'s store cannot be reproduced here: {unlike}")
    for recognizer in recognizers:
        row = next(r for r in rows if r["recognizer"] == recognizer)
        assert reproduce.differences(row, reproduce.run_again(
            reproduce.job_of(row, suite))) == [], row["key"]
