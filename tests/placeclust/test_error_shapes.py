import math

import numpy as np
import pytest

from placeclust.error_shapes import error_shapes


def _drive(visits=(0, 1, 0, 2, 1, 0), frames=10):
    """A drive along a line, 0.1 m a frame, through rooms in the order given."""
    truth = np.repeat(np.array(visits), frames)
    xy = np.stack([0.1 * np.arange(len(truth)), np.zeros(len(truth))], axis=1)
    return truth, xy


def test_a_perfect_recognizer_has_no_lag_and_opens_nothing():
    truth, xy = _drive()
    shapes = error_shapes(truth.copy(), truth, xy)
    assert shapes["lag_m"] == 0.0 and shapes["revisit_new"] == 0.0
    assert math.isnan(shapes["near_door_share"])  # no wrong frame
    assert shapes["entries"] == 5 and shapes["revisits"] == 3


@pytest.mark.parametrize("lag", [1, 3])
def test_a_recognizer_that_lags_at_doors_is_measured_in_metres(lag):
    truth, xy = _drive()
    pred = truth.copy()
    starts = np.flatnonzero(np.diff(truth) != 0) + 1
    for s in starts:  # the room left is reported for `lag` frames
        pred[s:s + lag] = truth[s - 1]
    shapes = error_shapes(pred, truth, xy)
    assert shapes["lag_m"] == pytest.approx(0.1 * lag)
    assert shapes["near_door_share"] == 1.0 and shapes["revisit_new"] == 0.0


def test_a_recognizer_that_opens_a_place_on_every_revisit():
    truth, xy = _drive()
    pred = truth.copy()
    pred[20:30] = 7  # room 0's second visit: a place of its own
    pred[40:50] = 8  # room 1's second visit
    pred[50:60] = 9  # room 0's third
    shapes = error_shapes(pred, truth, xy)
    assert shapes["revisit_new"] == 1.0


def test_arrays_of_different_lengths_are_refused():
    with pytest.raises(ValueError, match="as long"):
        error_shapes(np.zeros(3), np.zeros(4), np.zeros((3, 2)))
