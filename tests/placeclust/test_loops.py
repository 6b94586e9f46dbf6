"""A loop-closure drive asks VPR-Bench's question: the map before the first revisit, queries
after, truth from the revisit matrix; a bad matrix is named."""

import cv2
import numpy as np
import pytest

from placeclust.datasets import DatasetError, write_image_folder
from placeclust.loops import LoopClosures
from placeclust.realdata import dataset_kind, run_dataset


@pytest.fixture
def drive(tmp_path, two_places):
    """Place A, place B, then place A again: frames 20-29 revisit frames 0-9."""
    frames, _ = two_places
    order = [*range(20), *range(20, 40), *range(10)]
    write_image_folder(tmp_path, frames[order])
    same = np.zeros((50, 50), np.uint8)
    for i in range(40, 50):
        same[i, i - 40] = 255
    same[45, 47] = 255  # above the diagonal: not a revisit, ignored
    cv2.imwrite(str(tmp_path / "same_place.bmp"), same)
    return tmp_path


def test_the_map_ends_at_the_first_revisit(drive):
    data = LoopClosures(drive)
    assert (len(data.ref), len(data.query)) == (40, 10)
    assert [g.tolist() for g in data.ground_truth] == [[q] for q in range(10)]
    assert data.query[0].shape == data.ref[0].shape and len(list(data.query)) == 10
    with pytest.raises(IndexError):
        data.query[10]


def test_a_drive_is_benchmarked_as_vpr_bench_is(drive):
    assert dataset_kind(drive) == "loop-closures"
    run_, truth = run_dataset("online", drive, "orb")
    assert run_.metrics["query_top1"] > 0.9 and (truth == -1).all()


@pytest.mark.parametrize("matrix, message", [
    (np.zeros((3, 3), np.uint8), "must be 50x50"), (np.zeros((50, 50), np.uint8), "no revisit"),
    (None, "cannot read"),
])
def test_a_bad_matrix_is_named(drive, matrix, message):
    path = drive / "same_place.bmp"
    if matrix is None:
        path.write_bytes(b"not a bitmap")
    else:
        cv2.imwrite(str(path), matrix)
    with pytest.raises(DatasetError, match=message):
        LoopClosures(drive)
