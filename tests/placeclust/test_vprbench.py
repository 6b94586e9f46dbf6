from pathlib import Path

import numpy as np
import pytest

from placeclust.datasets import DatasetError
from placeclust.vprbench import (
    GROUND_TRUTH,
    VPRBench,
    is_vpr_bench,
    nearby_truth,
    read_ground_truth,
    same_place_truth,
    score_queries,
    write_vpr_bench,
)

CORRIDOR = Path(__file__).parents[2] / ".." / "shared" / "data" / "vpr-bench-corridor"


def _write(folder, truth=((0, 1), (1,), (2,))):
    frames = np.random.default_rng(0).integers(0, 255, (3, 20, 20, 3), np.uint8)
    write_vpr_bench(folder, frames, frames[::-1], truth)


def test_a_written_dataset_round_trips(tmp_path):
    _write(tmp_path)
    assert is_vpr_bench(tmp_path)
    data = VPRBench(tmp_path)
    assert [t.tolist() for t in data.ground_truth] == [[0, 1], [1], [2]]
    assert np.array_equal(data.query[0], data.ref[2])
    # the file is VPR-Bench's own format: numpy's pickled object array
    table = np.load(tmp_path / GROUND_TRUTH, allow_pickle=True)
    assert table.dtype == object and table[0, 1] == [0, 1]


class _Boom:
    def __reduce__(self):
        return (print, ("pickle ran code",))


def test_a_pickle_that_would_run_code_is_refused_unrun(tmp_path, capsys):
    _write(tmp_path)
    table = np.empty((3, 2), dtype=object)
    table[:, 0], table[:, 1] = [0, 1, 2], [_Boom(), [1], [2]]
    np.save(tmp_path / GROUND_TRUTH, table, allow_pickle=True)
    with pytest.raises(DatasetError, match="builtins.print, which is not a NumPy array"):
        VPRBench(tmp_path)
    assert "pickle ran code" not in capsys.readouterr().out


@pytest.mark.parametrize("truth, message", [
    ([[0], [1]], "expected one row per query"),
    ([[0], [1], [7]], "names reference 7"),
])
def test_ground_truth_that_does_not_fit_the_images_is_named(tmp_path, truth, message):
    _write(tmp_path, truth)
    with pytest.raises(DatasetError, match=message):
        read_ground_truth(tmp_path / GROUND_TRUTH, 3, 3)
    (tmp_path / "bad.npy").write_bytes(b"not numpy")
    with pytest.raises(DatasetError, match="bad.npy"):
        read_ground_truth(tmp_path / "bad.npy", 3, 3)


def test_a_folder_without_the_layout_is_named(tmp_path):
    with pytest.raises(DatasetError, match="not a VPR-Bench dataset"):
        VPRBench(tmp_path)


@pytest.mark.skipif(not CORRIDOR.is_dir(), reason="the shared corridor data set is absent")
def test_the_real_corridor_ground_truth_reads_as_numpy_unpickles_it():
    trusted = np.load(CORRIDOR / GROUND_TRUTH, allow_pickle=True)  # our own copy: trusted
    data = VPRBench(CORRIDOR)
    assert len(data.ref) == len(data.query) == len(trusted) == 111
    assert all(list(t) == list(row[1]) for t, row in zip(data.ground_truth, trusted))


def test_with_one_reference_a_place_top1_is_vpr_benchs_image_top1():
    rng = np.random.default_rng(1)
    truth = [np.unique(rng.integers(0, 30, 3)) for _ in range(40)]
    matched = rng.integers(0, 30, 40)  # each query's best reference image
    vpr_bench = np.mean([m in t for m, t in zip(matched, truth)])  # VPR-Bench's top-1
    scores = score_queries(np.arange(30), matched, truth,
                           ranked=[[m] for m in matched], recall_at=(1,))
    assert scores["top1"] == pytest.approx(vpr_bench) == scores["recall@1"]
    assert scores["refs_per_place"] == 1.0 and scores["n_places"] == 30


def test_one_place_for_everything_is_right_by_chance_and_says_so():
    truth = [np.array([q]) for q in range(10)]
    scores = score_queries(np.zeros(10, int), np.zeros(10, int), truth)
    assert scores["top1"] == 1.0 and scores["chance"] == 1.0 and scores["n_places"] == 1


def test_truth_from_positions_and_labels():
    ref = np.array([[0.0, 0, 0], [1.0, 0, 0], [1.5, 0, 0], [9, 9, 0]])
    query = np.array([[0.9, 0.0, 0], [9, 9, 0]])
    assert nearby_truth(ref, query, 1.0) == [[0, 1, 2], [3]]
    assert nearby_truth(ref, query, 1.0, np.array([0, 0, 1, 1]), np.array([0, 1])) == [[0, 1],
                                                                                        [3]]
    assert same_place_truth(np.array([0, 1, 0]), np.array([0, -1])) == [[0, 2], []]
