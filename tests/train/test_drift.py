import numpy as np
import pytest

from train.drift import agent_task, drift, main, table

POLICIES = "assets/policies/tour"


def test_the_drift_is_measured_after_every_decision_from_the_tours_end():
    errors, errand_of = drift(f"{POLICIES}/continued_oracle/best_model.zip", [1000], rooms=3,
                              errands=2)
    assert len(errors) == len(errand_of) > 0 and np.all(errors >= 0)
    assert set(errand_of) <= {0, 1}
    assert errors[0] < 0.05  # where the tour left it, the robot is where it thinks


def test_a_policy_of_carried_errands_has_nothing_to_measure():
    with pytest.raises(ValueError, match="carried-errand policy"):
        agent_task(f"{POLICIES}/carried_noplace/best_model.zip")
    assert main([f"{POLICIES}/carried_noplace/best_model.zip", "--n-scenes", "1"]) == 2


def test_the_table_groups_errands_in_quarters_of_the_episode():
    errors = np.array([0.1, 0.3, 1.0, 2.0])
    text = table({"a": (errors, np.array([0, 1, 2, 3]))}, errands=4)
    assert text.splitlines()[0].startswith("| policy | errands 1–1 | errands 2–2")
    assert "| a | 0.10 (0.10) | 0.30 (0.30) | 1.00 (1.00) | 2.00 (2.00) |" in text
