"""The errands' one typed specification: checked once, the env's names, a job's plain key."""

import pytest

from envs.runs.suite import SUITES, track_task
from envs.runs.task_spec import ErrandTask
from envs.runs.tour_errands import check_goals


def test_a_task_says_only_the_count_and_what_differs_from_the_envs_defaults():
    assert ErrandTask().kwargs() == {"n_errands": 5}
    v4 = SUITES["placenav-v4"].task(track="carried")
    assert v4.kwargs() == {"n_errands": 15, "local_light": True, "errand_start": "carried",
                           "goal_kind": "image"}  # no env_id, tour length or radius: defaults
    assert ErrandTask.from_kwargs(v4.kwargs()) == v4


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"goal_kind": "door"}, "goal_kind must be one of"),
    ({"n_errands": 0}, "n_errands must be positive"),
    ({"doors": 1.5}, "doors must be a fraction"),
    ({"goal_kind": "image", "success_radius": 0.0}, "success_radius must be positive"),
    ({"env_id": "PlaceNav-ImageGoal-v1"}, "goals are pictures"),
    ({"goal_offset": 0.5}, "PlaceNav-ImageGoal-v1's"),
    ({"env_id": "PlaceNav-v0"}, "env_id must be one of"),
])
def test_a_bad_value_is_one_line_that_names_it(kwargs, message):
    with pytest.raises(ValueError, match=message):
        ErrandTask(**kwargs)


def test_an_argument_the_task_has_not_is_named():
    with pytest.raises(ValueError, match=r"unknown task arguments \['goals'\]"):
        ErrandTask.from_kwargs({"goals": 5})


def test_a_track_may_not_undo_an_option():
    corridor = ErrandTask(layout="corridor")
    assert corridor.with_settings(track_task("corridor"), "--track corridor") == corridor
    with pytest.raises(ValueError, match="leave out the option that sets it to 'corridor'"):
        corridor.with_settings({"layout": "grid"}, "--track continued")


def test_the_tour_and_the_errands_split_the_arguments():
    v5 = SUITES["placenav-v5"].task(track="changed-night-fixed")
    assert set(v5.tour_kwargs()) == {"env_id", "local_light", "compass"}
    assert v5.errand_kwargs() == {"errand_condition": "night", "errand_learn": False,
                                  "goal_kind": "image", "goal_offset": 0.5}


def test_the_goal_kind_decides_which_agents_may_run_it():
    check_goals("spot-memory", [ErrandTask(goal_kind="image")])
    with pytest.raises(ValueError, match="cannot run errands to image goals"):
        check_goals("planner", [ErrandTask(), ErrandTask(goal_kind="image")])
