import json

import numpy as np
import pytest

from envs.commands import seed001


@pytest.fixture(scope="module")
def row():
    return seed001.run_scene(1000, n_rooms=2, steps_per_room=40, seed=0)


def test_tables_2_and_3_count_the_key_frames_of_the_mapping_drive(row):
    m = row["map"]
    table = row["table2"]
    assert sum(r["key_frames"] for r in table.values()) == m["key_frames"] > 0
    assert sum(r["images"] for r in table.values()) == 80
    assert sum(r["locations"] for r in table.values()) <= m["locations"]
    correct = sum(r["correct"] for r in table.values())
    assert correct / m["key_frames"] == pytest.approx(m["matching_rate"])
    for name in ("AC", "TP", "P"):
        assert 0.0 <= m[name] <= 1.0


def test_the_second_drive_and_seed_000_are_scored_on_the_same_building(row):
    assert 0.0 <= row["relocalization"]["rate"] <= 1.0
    assert 0.0 <= row["relocalization"]["unknown"] <= 1.0
    assert row["online"]["places"] >= 1
    assert 0.0 <= row["why"]["looks_elsewhere"] <= 1.0


def test_summary_reports_mean_and_worst_beside_the_paper(row):
    other = json.loads(json.dumps(row))
    other["map"]["matching_rate"] = 0.25
    summary = seed001.summarize([row, other])
    mean, worst, low, high = summary["matching_rate"]
    assert worst == 0.25 and mean == pytest.approx((row["map"]["matching_rate"] + 0.25) / 2)
    assert low == pytest.approx(0.25) and high == pytest.approx(row["map"]["matching_rate"])
    report = seed001.format_report(summary, "test")
    assert "0.938 / 0.902" in report and "| matching rate" in report
    assert f"{mean:.3f} [0.250, {high:.3f}]" in report
    alone = seed001.format_report(seed001.summarize([row]), "test")
    assert "[1 building: no interval]" in alone and "nan" not in alone


@pytest.mark.parametrize("args, named", [
    (["--param", "min_matchez=3"], "min_matchez"),
    (["--doors", "1.5"], "--doors must be a fraction"),
])
def test_bad_input_is_one_line_of_error(capsys, args, named):
    assert seed001.main(["--scene-seeds", "1000", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and named in err and err.count("\n") == 1


def test_a_bad_room_count_is_refused_while_parsing(capsys):
    with pytest.raises(SystemExit) as stop:
        seed001.main(["--scene-seeds", "1000", "--rooms", "0"])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1
    assert "argument --rooms: a building has 1 to 32 rooms, got '0'" in err


class _Fixed:
    """Answers the places it is given, one per frame; no key frames of its own."""

    def __init__(self, answers):
        self.answers = iter(answers)

    def reset_position(self):
        pass

    def localize_one(self, frame):
        return next(self.answers)


def test_relocalization_scores_the_key_frames_it_is_given():
    frames, rooms = np.zeros((4, 8, 8), np.uint8), np.array([0, 0, 1, 1])
    labels = {5: 0, 6: 1}
    scores, key = seed001.relocalize(_Fixed([5, 6, 6, -1]), frames, rooms, labels)
    assert key.all() and scores == {"rate": 0.5, "unknown": 0.25}
    only = np.array([True, False, True, False])
    scores, key = seed001.relocalize(_Fixed([5, 6, 6, -1]), frames, rooms, labels, only)
    assert key is only and scores == {"rate": 1.0, "unknown": 0.0}
