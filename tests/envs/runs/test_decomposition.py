import pytest

from envs.runs.decomposition import decomposition, decomposition_table


def _doc(errands_by_building):
    rows = [{"recognizer": "r", "scene_seed": s, "errands": errands}
            for s, errands in enumerate(errands_by_building)]
    return {"buildings": rows, "summaries": [{"recognizer": "r"}]}


def _errand(success, spot, steps=30, fine=True, room=True, unknown=False):
    return {"success": success, "steps": steps, "unknown": unknown, "named_room": room,
            "named_fine": fine, "spot_within": spot}


def test_the_driving_counts_only_errands_whose_spot_was_within_reach():
    doc = _doc([[_errand(True, True), _errand(False, False, fine=False)],
                [_errand(False, True), _errand(False, False, steps=1, room=False)]])
    (row,) = decomposition({"continued": doc})
    assert row["success"].mean == 0.25 and row["spot"].mean == 0.5
    assert row["driving"].mean == 0.5  # 1 of the 2 errands with a spot within 1 m
    assert row["within 1 m"].mean == 0.75 and row["room"].mean == 0.75
    assert row["first step"].mean == 0.25 and row["unknown"].mean == 0.0
    table = decomposition_table({"continued": doc})
    assert "| continued | r | 0.00 [" in table and "| driving |" in table


def test_records_without_the_decomposition_are_named():
    doc = _doc([[{"success": True, "steps": 3}]])
    with pytest.raises(ValueError, match="run PlaceNav-ImageGoal-v1"):
        decomposition({"carried": doc})
